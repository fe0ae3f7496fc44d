//! TOML files read so that every error points into the user's text: syntax, type and unknown-key errors at
//! the span the parser gives, `nan`/`inf` (which TOML accepts) refused wherever they are written, and a
//! semantic error found after parsing placed on the key it is about ([`at_key`]).

use serde::de::DeserializeOwned;
use toml_edit::{ImDocument, Item, Table, Value};

use crate::located::{locate, Located};

/// Parses `text` into `T`: every error (syntax, type, unknown key, a non-finite number) at its line and column.
pub fn parse<T: DeserializeOwned>(file: &str, text: &str) -> Result<T, Located> {
    let doc = ImDocument::parse(text).map_err(|e| {
        let at = e.span().map_or(0, |s| s.start);
        locate(file, text, at, e.message().trim_end())
    })?;
    if let Some(at) = first_non_finite(doc.as_table()) {
        return Err(locate(
            file,
            text,
            at,
            "not a finite number (nan and inf are refused)",
        ));
    }
    toml::from_str(text).map_err(|e| {
        let at = e.span().map_or(0, |s| s.start);
        locate(file, text, at, e.message().trim_end())
    })
}

/// A semantic error found after parsing: the key path it is about (`slow_zones.1.radius_m`) and why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{key}: {reason}")]
pub struct KeyError {
    pub key: String,
    pub reason: String,
}

impl KeyError {
    pub fn new(key: impl Into<String>, reason: impl Into<String>) -> Self {
        Self {
            key: key.into(),
            reason: reason.into(),
        }
    }

    /// The error placed on its key in `text` (see [`at_key`]), the message `key: reason`.
    pub fn locate(&self, file: &str, text: &str) -> Located {
        at_key(file, text, &self.key, self.to_string())
    }
}

/// `message` placed on the key path `key` (`actions.move.speed_m_s`, `slow_zones.1.radius_m`): at its
/// value when written, else at the closest written table or key on the way, else at the start.
pub fn at_key(file: &str, text: &str, key: &str, message: impl Into<String>) -> Located {
    locate(file, text, key_offset(text, key).unwrap_or(0), message)
}

/// The byte offset of what `key` is written as (see [`at_key`]).
pub fn key_offset(text: &str, key: &str) -> Option<usize> {
    let doc = ImDocument::parse(text).ok()?;
    let mut best = None;
    let mut node = Node::Table(doc.as_table());
    for seg in key.split('.').filter(|s| !s.is_empty()) {
        let Some((key_at, next)) = node.child(seg) else {
            break;
        };
        // An implicit table (`actions` of `[actions.move]`) is written nowhere of its own.
        if !next.is_implicit() {
            best = next.span().or(key_at).or(best);
        }
        node = next;
    }
    best
}

/// One level of a parsed document, whatever way it is written.
#[derive(Clone, Copy)]
enum Node<'a> {
    Table(&'a Table),
    Item(&'a Item),
    Value(&'a Value),
}

impl<'a> Node<'a> {
    /// The child named `seg` (a key, or an index in an array), with the offset of its key when it has one.
    fn child(self, seg: &str) -> Option<(Option<usize>, Node<'a>)> {
        let index = seg.parse::<usize>().ok();
        match self {
            Node::Table(t) => {
                let (k, v) = t.get_key_value(seg)?;
                Some((k.span().map(|s| s.start), Node::Item(v)))
            }
            Node::Item(Item::Table(t)) => Node::Table(t).child(seg),
            Node::Item(Item::Value(v)) => Node::Value(v).child(seg),
            Node::Item(Item::ArrayOfTables(a)) => Some((None, Node::Table(a.get(index?)?))),
            Node::Item(Item::None) => None,
            Node::Value(Value::InlineTable(t)) => {
                let (k, v) = t.get_key_value(seg)?;
                Some((k.span().map(|s| s.start), Node::Item(v)))
            }
            Node::Value(Value::Array(a)) => Some((None, Node::Value(a.get(index?)?))),
            Node::Value(_) => None,
        }
    }

    fn is_implicit(self) -> bool {
        match self {
            Node::Table(t) | Node::Item(Item::Table(t)) => t.is_implicit(),
            _ => false,
        }
    }

    /// Where this is written, if it is written at all.
    fn span(self) -> Option<usize> {
        let span = match self {
            Node::Table(t) => t.span(),
            Node::Item(Item::Table(t)) => return Node::Table(t).span(),
            Node::Item(i) => i.span(),
            Node::Value(v) => v.span(),
        };
        span.map(|s| s.start)
    }
}

/// The offset of the first `nan` or `inf` in the document.
fn first_non_finite(table: &Table) -> Option<usize> {
    table.iter().find_map(|(_, item)| item_non_finite(item))
}

fn item_non_finite(item: &Item) -> Option<usize> {
    match item {
        Item::Table(t) => first_non_finite(t),
        Item::ArrayOfTables(a) => a.iter().find_map(first_non_finite),
        Item::Value(v) => value_non_finite(v),
        Item::None => None,
    }
}

fn value_non_finite(value: &Value) -> Option<usize> {
    match value {
        Value::Float(f) if !f.value().is_finite() => Some(f.span().map_or(0, |s| s.start)),
        Value::Array(a) => a.iter().find_map(value_non_finite),
        Value::InlineTable(t) => t.iter().find_map(|(_, v)| value_non_finite(v)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)] // read by the deserializer only
    struct Cfg {
        a: A,
        #[serde(default)]
        zones: Vec<Zone>,
    }
    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct A {
        x: f64,
        #[serde(default)]
        y: u32,
    }
    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Zone {
        r: f64,
    }

    const TEXT: &str = "# c\n[a]\nx = 1.5\ny = 2\n\n[[zones]]\nr = 1.0\n\n[[zones]]\nr = 3.0\n";

    fn err(text: &str) -> (usize, usize) {
        let e = parse::<Cfg>("c.toml", text).unwrap_err();
        (e.line, e.col)
    }

    #[test]
    fn errors_are_placed_where_written() {
        assert!(parse::<Cfg>("c.toml", TEXT).is_ok());
        assert_eq!(err(&TEXT.replace("y = 2", "y = \"2\"")), (4, 5), "type");
        assert_eq!(err(&TEXT.replace("y = 2", "z = 2")), (4, 1), "unknown key");
        assert_eq!(err(&TEXT.replace("r = 3.0", "r = nan")), (10, 5), "nan");
        assert_eq!(err(&TEXT.replace("x = 1.5", "x = -inf")), (3, 5), "inf");
        assert_eq!(err(&TEXT.replace("y = 2", "y = ]")), (4, 5), "syntax");
        let at = |k| {
            let e = at_key("c.toml", TEXT, k, "m");
            (e.line, e.col)
        };
        assert_eq!(at("a.y"), (4, 5));
        assert_eq!(at("zones.1.r"), (10, 5));
        assert_eq!(at("a.missing"), (2, 1));
        assert_eq!(at("nowhere"), (1, 1));
    }
}
