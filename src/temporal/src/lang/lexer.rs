//! Lexer: text → tokens with byte spans. Comments are `// ...` and `/* ... */`.

use super::diag::{Diagnostic, Source, Span};

/// A time unit suffix glued to a number (`20min`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unit {
    Ms,
    S,
    Min,
    H,
}

impl Unit {
    /// Milliseconds per unit.
    pub fn ms(self) -> f64 {
        match self {
            Unit::Ms => 1.0,
            Unit::S => 1_000.0,
            Unit::Min => 60_000.0,
            Unit::H => 3_600_000.0,
        }
    }
}

/// A comparison: a token of its own, and the operator of a relation statement (`?d <= 30`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RelOp {
    Eq,
    Ne,
    Le,
    Ge,
    Lt,
    Gt,
}

impl RelOp {
    fn symbol(self) -> &'static str {
        match self {
            RelOp::Eq => "=",
            RelOp::Ne => "!=",
            RelOp::Le => "<=",
            RelOp::Ge => ">=",
            RelOp::Lt => "<",
            RelOp::Gt => ">",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    Ident(String),
    /// `?name`, stored without the `?`.
    Var(String),
    Num {
        value: f64,
        unit: Option<Unit>,
    },
    /// `HH:MM[:SS]`, in milliseconds since midnight.
    Clock(i64),
    /// `+oo`
    PlusInf,
    /// `-oo`
    MinusInf,
    LParen,
    RParen,
    LBrace,
    RBrace,
    LBracket,
    RBracket,
    Comma,
    Semi,
    Colon,
    Rel(RelOp),
    Plus,
    Minus,
    Star,
    Slash,
    Eof,
}

impl Tok {
    /// How the token reads in "expected X, found Y" messages.
    pub fn describe(&self) -> String {
        match self {
            Tok::Ident(s) => format!("`{s}`"),
            Tok::Var(s) => format!("`?{s}`"),
            Tok::Num { .. } => "a number".into(),
            Tok::Clock(_) => "a clock time".into(),
            Tok::PlusInf => "`+oo`".into(),
            Tok::MinusInf => "`-oo`".into(),
            Tok::Eof => "the end of the file".into(),
            other => format!("`{}`", other.symbol()),
        }
    }

    fn symbol(&self) -> &'static str {
        match self {
            Tok::LParen => "(",
            Tok::RParen => ")",
            Tok::LBrace => "{",
            Tok::RBrace => "}",
            Tok::LBracket => "[",
            Tok::RBracket => "]",
            Tok::Comma => ",",
            Tok::Semi => ";",
            Tok::Colon => ":",
            Tok::Rel(op) => op.symbol(),
            Tok::Plus => "+",
            Tok::Minus => "-",
            Tok::Star => "*",
            Tok::Slash => "/",
            _ => "?",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Token {
    pub tok: Tok,
    pub span: Span,
}

fn is_ident_start(c: u8) -> bool {
    c.is_ascii_alphabetic() || c == b'_'
}

fn is_ident_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// Splits `src.text` into tokens, ending with `Eof`; the first lexical error stops it.
pub fn lex(src: &Source<'_>) -> Result<Vec<Token>, Diagnostic> {
    let text = src.text;
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let start = i;
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        if c == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if c == b'/' && b.get(i + 1) == Some(&b'*') {
            match text[i + 2..].find("*/") {
                Some(k) => i = i + 2 + k + 2,
                None => return Err(src.error_at(start, "unterminated comment: missing `*/`")),
            }
            continue;
        }
        let tok = if is_ident_start(c) {
            while i < b.len() && is_ident_char(b[i]) {
                i += 1;
            }
            Tok::Ident(text[start..i].to_string())
        } else if c == b'?' {
            i += 1;
            if i >= b.len() || !is_ident_start(b[i]) {
                return Err(src.error_at(start, "expected a variable name after `?`"));
            }
            while i < b.len() && is_ident_char(b[i]) {
                i += 1;
            }
            Tok::Var(text[start + 1..i].to_string())
        } else if c.is_ascii_digit() {
            let (tok, end) = lex_number(src, start)?;
            i = end;
            tok
        } else if (c == b'+' || c == b'-')
            && text[i + 1..].starts_with("oo")
            && !b.get(i + 3).is_some_and(|&n| is_ident_char(n))
        {
            i += 3;
            if c == b'+' {
                Tok::PlusInf
            } else {
                Tok::MinusInf
            }
        } else {
            let two = b.get(i + 1).copied();
            let (tok, len) = match (c, two) {
                (b'!', Some(b'=')) => (Tok::Rel(RelOp::Ne), 2),
                (b'<', Some(b'=')) => (Tok::Rel(RelOp::Le), 2),
                (b'>', Some(b'=')) => (Tok::Rel(RelOp::Ge), 2),
                (b'(', _) => (Tok::LParen, 1),
                (b')', _) => (Tok::RParen, 1),
                (b'{', _) => (Tok::LBrace, 1),
                (b'}', _) => (Tok::RBrace, 1),
                (b'[', _) => (Tok::LBracket, 1),
                (b']', _) => (Tok::RBracket, 1),
                (b',', _) => (Tok::Comma, 1),
                (b';', _) => (Tok::Semi, 1),
                (b':', _) => (Tok::Colon, 1),
                (b'=', _) => (Tok::Rel(RelOp::Eq), 1),
                (b'<', _) => (Tok::Rel(RelOp::Lt), 1),
                (b'>', _) => (Tok::Rel(RelOp::Gt), 1),
                (b'+', _) => (Tok::Plus, 1),
                (b'-', _) => (Tok::Minus, 1),
                (b'*', _) => (Tok::Star, 1),
                (b'/', _) => (Tok::Slash, 1),
                _ => {
                    let ch = text[start..].chars().next().unwrap_or('?');
                    return Err(src.error_at(start, format!("unexpected character {ch:?}")));
                }
            };
            i += len;
            tok
        };
        out.push(Token {
            tok,
            span: Span::new(start, i),
        });
    }
    // "found the end of the file" points just after the last token, on a line that shows it.
    let eof = out.last().map_or(0, |t: &Token| t.span.end);
    out.push(Token {
        tok: Tok::Eof,
        span: Span::new(eof, eof),
    });
    Ok(out)
}

fn digits(b: &[u8], mut i: usize) -> usize {
    while i < b.len() && b[i].is_ascii_digit() {
        i += 1;
    }
    i
}

/// A number (`12`, `0.5`, `20min`, `1.5h`) or a clock time (`08:00`, `19:40:30`) starting at `start`.
fn lex_number(src: &Source<'_>, start: usize) -> Result<(Tok, usize), Diagnostic> {
    let text = src.text;
    let b = text.as_bytes();
    let int_end = digits(b, start);
    // HH:MM[:SS], only when two digits follow the colon (so `x():3` style stays a colon).
    let two_digits_at = |k: usize| {
        k + 1 < b.len()
            && b[k].is_ascii_digit()
            && b[k + 1].is_ascii_digit()
            && !b.get(k + 2).is_some_and(|c| c.is_ascii_digit())
    };
    if int_end - start <= 2 && b.get(int_end) == Some(&b':') && two_digits_at(int_end + 1) {
        let h: i64 = text[start..int_end].parse().unwrap_or(0);
        let m: i64 = text[int_end + 1..int_end + 3].parse().unwrap_or(0);
        let mut end = int_end + 3;
        let mut s = 0;
        if b.get(end) == Some(&b':') && two_digits_at(end + 1) {
            s = text[end + 1..end + 3].parse().unwrap_or(0);
            end += 3;
        }
        if m >= 60 || s >= 60 {
            return Err(src.error_at(
                start,
                "invalid clock time: minutes and seconds must be below 60",
            ));
        }
        return Ok((Tok::Clock(((h * 60 + m) * 60 + s) * 1000), end));
    }
    let mut end = int_end;
    if b.get(end) == Some(&b'.') && b.get(end + 1).is_some_and(|c| c.is_ascii_digit()) {
        end = digits(b, end + 1);
    }
    let value: f64 = text[start..end].parse().unwrap_or(f64::INFINITY);
    if !value.is_finite() {
        return Err(src.error_at(start, "number out of range"));
    }
    let unit_end = {
        let mut k = end;
        while k < b.len() && is_ident_char(b[k]) {
            k += 1;
        }
        k
    };
    let unit = match &text[end..unit_end] {
        "" => None,
        "ms" => Some(Unit::Ms),
        "s" => Some(Unit::S),
        "min" => Some(Unit::Min),
        "h" => Some(Unit::H),
        other => {
            return Err(src.error_at(
                end,
                format!("unknown time unit `{other}` (expected ms, s, min or h)"),
            ))
        }
    };
    Ok((Tok::Num { value, unit }, unit_end))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(s: &str) -> Vec<Tok> {
        let src = Source::new("t", s);
        lex(&src)
            .map(|v| v.into_iter().map(|t| t.tok).collect())
            .unwrap_or_default()
    }

    #[test]
    fn lexes_fig3_fragments() {
        assert_eq!(
            toks("(et-st) in]2, 60];"),
            vec![
                Tok::LParen,
                Tok::Ident("et".into()),
                Tok::Minus,
                Tok::Ident("st".into()),
                Tok::RParen,
                Tok::Ident("in".into()),
                Tok::RBracket,
                Tok::Num {
                    value: 2.0,
                    unit: None
                },
                Tok::Comma,
                Tok::Num {
                    value: 60.0,
                    unit: None
                },
                Tok::RBracket,
                Tok::Semi,
                Tok::Eof
            ]
        );
        assert_eq!(
            toks("(?xi, +oo) -oo 20min 08:30 x():30"),
            vec![
                Tok::LParen,
                Tok::Var("xi".into()),
                Tok::Comma,
                Tok::PlusInf,
                Tok::RParen,
                Tok::MinusInf,
                Tok::Num {
                    value: 20.0,
                    unit: Some(Unit::Min)
                },
                Tok::Clock(8 * 3_600_000 + 30 * 60_000),
                Tok::Ident("x".into()),
                Tok::LParen,
                Tok::RParen,
                Tok::Colon,
                Tok::Num {
                    value: 30.0,
                    unit: None
                },
                Tok::Eof
            ]
        );
    }

    #[test]
    fn lexical_errors_are_located() {
        let src = Source::new("t", "a\n  5km");
        let e = lex(&src).err().map(|d| (d.line, d.col));
        assert_eq!(e, Some((2, 4)));
        let src = Source::new("t", "a /* never closed");
        assert_eq!(lex(&src).err().map(|d| d.col), Some(3));
        let src = Source::new("t", "é");
        assert!(lex(&src).is_err());
    }
}
