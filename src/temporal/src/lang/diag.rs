//! Diagnostics: `file:line:col: error: message`, then the source line and a caret under the column.

use std::fmt;

pub use srctext::Span;

/// One error located in a file: `file:line:col: error: message`, the line and a caret.
pub use srctext::Located as Diagnostic;

/// A diagnostic that does not stop loading: `file:line:col: warning: message`.
pub use srctext::Warning;

/// One or more diagnostics (what every loader returns on failure).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Diagnostics(pub Vec<Diagnostic>);

impl Diagnostics {
    /// A single diagnostic not tied to any source text (e.g. a file that cannot be read).
    pub fn file_error(file: &str, message: impl Into<String>) -> Self {
        Diagnostics(vec![Diagnostic {
            file: file.to_string(),
            line: 1,
            col: 1,
            message: message.into(),
            source_line: String::new(),
        }])
    }

    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    pub fn len(&self) -> usize {
        self.0.len()
    }

    pub fn iter(&self) -> std::slice::Iter<'_, Diagnostic> {
        self.0.iter()
    }

    /// Appends all of `other`.
    pub fn extend(&mut self, other: Diagnostics) {
        self.0.extend(other.0);
    }
}

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for d in &self.0 {
            writeln!(f, "{d}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Diagnostics {}

/// A source text with its file name: turns byte offsets into line/column diagnostics.
#[derive(Debug, Clone, Copy)]
pub struct Source<'a> {
    pub file: &'a str,
    pub text: &'a str,
}

impl<'a> Source<'a> {
    pub fn new(file: &'a str, text: &'a str) -> Self {
        Source { file, text }
    }

    /// The 1-based line of byte offset `pos` (clamped to the text).
    pub fn line(&self, pos: usize) -> usize {
        let pos = pos.min(self.text.len());
        self.text.as_bytes()[..pos]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    }

    /// A diagnostic at byte offset `pos` (clamped to the text and to a char boundary).
    pub fn error_at(&self, pos: usize, message: impl Into<String>) -> Diagnostic {
        srctext::locate(self.file, self.text, pos, message)
    }

    /// A diagnostic at the start of `span`.
    pub fn error(&self, span: Span, message: impl Into<String>) -> Diagnostic {
        self.error_at(span.start, message)
    }
}

/// Turns raw bytes into text, or a diagnostic at the first invalid UTF-8 byte (see [`srctext::decode`]).
pub fn decode<'a>(file: &str, bytes: &'a [u8]) -> Result<&'a str, Diagnostics> {
    srctext::decode(file, bytes).map_err(|e| Diagnostics(vec![e]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_file_line_col_and_caret() {
        let src = Source::new("a.ixt", "domain x;\n  type = 3;\n");
        let d = src.error_at(17, "expected a name");
        assert_eq!((d.line, d.col), (2, 8));
        // Each diagnostic of a list ends its caret line.
        let text = Diagnostics(vec![d]).to_string();
        assert!(text.starts_with("a.ixt:2:8: error: expected a name\n"));
        assert!(text.contains("      type = 3;\n           ^\n"), "{text}");
    }

    #[test]
    fn invalid_utf8_is_located() {
        let bytes = b"domain x;\nab\xffcd";
        let d = decode("f", bytes).err().map(|d| d.0[0].clone());
        let d = d.map(|d| (d.line, d.col));
        assert_eq!(d, Some((2, 3)));
        assert_eq!(
            decode("f", "\u{feff}domain x;".as_bytes()).ok(),
            Some("domain x;")
        );
    }
}
