//! PDDL's surface syntax: s-expressions with byte spans. Names are lower-cased (PDDL is case-insensitive);
//! `;` starts a comment up to the end of the line.

use super::{PddlError, Src};

pub use srctext::Span;

/// An atom (a name, a `?variable`, a number, `:keyword`) or a parenthesised list.
#[derive(Debug, Clone, PartialEq)]
pub enum SxKind {
    Atom(String),
    List(Vec<Sx>),
}

/// An s-expression and where it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Sx {
    pub kind: SxKind,
    pub span: Span,
}

impl Sx {
    /// The lower-cased text of an atom.
    pub fn atom(&self) -> Option<&str> {
        match &self.kind {
            SxKind::Atom(a) => Some(a),
            SxKind::List(_) => None,
        }
    }

    /// The items of a list.
    pub fn list(&self) -> Option<&[Sx]> {
        match &self.kind {
            SxKind::List(l) => Some(l),
            SxKind::Atom(_) => None,
        }
    }

    /// The head atom of a list (`and` in `(and ...)`).
    pub fn head(&self) -> Option<&str> {
        self.list().and_then(|l| l.first()).and_then(Sx::atom)
    }
}

/// Nesting deeper than this is refused (no stack overflow on `((((…`).
const MAX_DEPTH: usize = 200;

/// Reads the whole text as s-expressions.
pub fn read(src: &Src) -> Result<Vec<Sx>, PddlError> {
    let text = src.text.as_bytes();
    let mut stack: Vec<(usize, Vec<Sx>)> = Vec::new();
    let mut top: Vec<Sx> = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let c = text[i];
        match c {
            b';' => {
                while i < text.len() && text[i] != b'\n' {
                    i += 1;
                }
            }
            b'(' => {
                if stack.len() >= MAX_DEPTH {
                    return Err(src.error(i, "nesting too deep"));
                }
                stack.push((i, Vec::new()));
                i += 1;
            }
            b')' => {
                let Some((start, items)) = stack.pop() else {
                    return Err(src.error(i, "unmatched `)`"));
                };
                let sx = Sx {
                    kind: SxKind::List(items),
                    span: Span { start, end: i + 1 },
                };
                match stack.last_mut() {
                    Some((_, parent)) => parent.push(sx),
                    None => top.push(sx),
                }
                i += 1;
            }
            c if c.is_ascii_whitespace() => i += 1,
            _ => {
                let start = i;
                while i < text.len()
                    && !text[i].is_ascii_whitespace()
                    && !matches!(text[i], b'(' | b')' | b';')
                {
                    i += 1;
                }
                let word = src.text.get(start..i).unwrap_or("").to_lowercase();
                let sx = Sx {
                    kind: SxKind::Atom(word),
                    span: Span { start, end: i },
                };
                match stack.last_mut() {
                    Some((_, parent)) => parent.push(sx),
                    None => top.push(sx),
                }
            }
        }
    }
    if let Some((start, _)) = stack.last() {
        return Err(src.error(*start, "this `(` is never closed"));
    }
    Ok(top)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn src(t: &str) -> Src {
        Src::new("t.pddl", t)
    }

    #[test]
    fn reads_nested_lists_lower_cased_without_comments() {
        let s = src("(define (Domain X) ; note (\n  (:types a))");
        let sx = read(&s).map_err(|e| e.to_string());
        let sx = sx.as_deref().map(|v| v.len());
        assert_eq!(sx, Ok(1));
        let all = read(&s).ok().unwrap_or_default();
        let l = all[0].list().unwrap_or(&[]);
        assert_eq!(l[1].head(), Some("domain"));
        assert_eq!(l[1].list().and_then(|l| l[1].atom()), Some("x"));
    }

    #[test]
    fn unbalanced_parentheses_are_located() {
        let e = read(&src("(define\n  (domain x)"))
            .err()
            .map(|e| e.to_string());
        assert!(
            e.as_deref().is_some_and(|e| e.starts_with("t.pddl:1:1:")),
            "{e:?}"
        );
        let e = read(&src("(a)\n (b))")).err().map(|e| e.to_string());
        assert!(
            e.as_deref().is_some_and(|e| e.starts_with("t.pddl:2:5:")),
            "{e:?}"
        );
    }
}
