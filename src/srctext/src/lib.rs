//! The one place mavtempo and its SITL read text inputs (domains, problems, configurations, scenarios, goal
//! files): bytes are checked as UTF-8 with the first bad byte located, and every error is a [`Located`]
//! `file:line:col: error: message` with the offending line and a caret under the column.

mod located;
mod span;
pub mod toml_file;

pub use located::{decode, locate, read, Located, ReadError, Warning};
pub use span::Span;
