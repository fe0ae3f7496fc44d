//! A message at a place of a text, and reading files as UTF-8.

use std::fmt;
use std::path::Path;

/// An error at `file:line:col` of a text.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct Located {
    /// The file name as given.
    pub file: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub col: usize,
    pub message: String,
    /// The offending line, control characters replaced so that it prints safely.
    pub source_line: String,
}

impl fmt::Display for Located {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write_as(f, "error")
    }
}

/// A [`Located`] message that does not stop anything: printed `file:line:col: warning: …`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning(pub Located);

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.write_as(f, "warning")
    }
}

impl Located {
    /// `file:line:col: KIND: message`, then the line and a caret under the column.
    fn write_as(&self, f: &mut fmt::Formatter<'_>, kind: &str) -> fmt::Result {
        write!(
            f,
            "{}:{}:{}: {kind}: {}",
            self.file, self.line, self.col, self.message
        )?;
        if !self.source_line.is_empty() {
            write!(f, "\n    {}", self.source_line)?;
            // Tabs kept so that the caret lines up under tab-indented text.
            let pad: String = self
                .source_line
                .chars()
                .take(self.col.saturating_sub(1))
                .map(|c| if c == '\t' { '\t' } else { ' ' })
                .collect();
            write!(f, "\n    {pad}^")?;
        }
        Ok(())
    }
}

/// `message` at byte offset `pos` of `text` (clamped to the text and to a character boundary).
pub fn locate(file: &str, text: &str, pos: usize, message: impl Into<String>) -> Located {
    let mut pos = pos.min(text.len());
    while !text.is_char_boundary(pos) {
        pos -= 1;
    }
    let before = &text[..pos];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line_end = text[line_start..]
        .find('\n')
        .map_or(text.len(), |i| line_start + i);
    Located {
        file: file.to_string(),
        line: before.matches('\n').count() + 1,
        col: text[line_start..pos].chars().count() + 1,
        message: message.into(),
        source_line: text[line_start..line_end]
            .trim_end_matches('\r')
            .chars()
            .map(|c| if c.is_control() && c != '\t' { '?' } else { c })
            .collect(),
    }
}

/// Raw bytes as text (an editor's byte-order mark dropped), or an error at the first byte that is not UTF-8.
pub fn decode<'a>(file: &str, bytes: &'a [u8]) -> Result<&'a str, Located> {
    match std::str::from_utf8(bytes) {
        Ok(s) => Ok(s.strip_prefix('\u{feff}').unwrap_or(s)),
        Err(e) => {
            let valid = e.valid_up_to();
            // Valid UTF-8 by construction; the bad byte is the next one.
            let prefix = std::str::from_utf8(&bytes[..valid]).unwrap_or("");
            let bad = bytes.get(valid).copied().unwrap_or(0);
            Err(locate(
                file,
                prefix,
                valid,
                format!("invalid UTF-8 (byte 0x{bad:02x}): the file must be UTF-8 text"),
            ))
        }
    }
}

/// Why a text file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    #[error("cannot read {path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("{0}")]
    Utf8(Located),
}

/// Reads a whole file as UTF-8 text.
pub fn read(path: &Path) -> Result<String, ReadError> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| ReadError::Io {
        path: name.clone(),
        source,
    })?;
    decode(&name, &bytes)
        .map(str::to_string)
        .map_err(ReadError::Utf8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_file_line_col_and_caret() {
        let e = locate("a.toml", "x = 1\n  y = [\n", 10, "bad");
        assert_eq!((e.line, e.col), (2, 5));
        assert_eq!(
            e.to_string(),
            "a.toml:2:5: error: bad\n      y = [\n        ^"
        );
    }

    #[test]
    fn the_first_bad_byte_is_located() {
        let e = decode("f", b"ab\ncd\xe9f\n").unwrap_err();
        assert_eq!((e.line, e.col), (2, 3));
        assert!(e.message.contains("0xe9"), "{e}");
        assert_eq!(decode("f", "\u{feff}x".as_bytes()), Ok("x"));
        // A truncated multi-byte character at the very end.
        let e = decode("f", b"\xc3").unwrap_err();
        assert_eq!((e.line, e.col), (1, 1));
    }
}
