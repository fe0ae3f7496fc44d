//! PDDL 2.1 (level 3) with PDDL 2.2's timed initial literals, in and out (issue 17).
//!
//! `sexpr` (spans) → `parse` ([`ast`]) → `invariants` (mutex groups: which predicates are one multi-valued
//! state variable, e.g. a rover's `at ?r ?w` as `at(?r) = ?w`) → `translate` and `task` (the
//! [`crate::model`] the planner works on) → `writer` (a plan in the IPC format). `simulate` replays an IPC
//! plan on the PDDL itself, sharing nothing with the translation, to check what the writer printed; `solve`
//! chains planner, checker, writer and replay. Every error is located
//! (`file:line:col`, the line, a caret) like the native language's; no input makes these functions panic.

pub mod ast;
mod finalise;
mod fluents;
pub mod ground;
pub mod hybrid;
mod invariants;
mod parse;
pub mod sexpr;
pub mod simulate;
mod solve;
mod task;
mod translate;
pub mod writer;

use std::path::Path;

pub use fluents::{Access, Change, Fluents, StateDuration, TaskNumeric};
pub use hybrid::Hybrid;
pub use solve::{load, solve, Loaded, SolveError, Solved};
pub use translate::{translate, Translated, HORIZON_S};
pub use writer::{ipc_plan, IpcPlan, IpcStep, EPSILON_MS};

/// A PDDL source text and its file name.
#[derive(Debug, Clone)]
pub struct Src {
    pub file: String,
    pub text: String,
}

impl Src {
    pub fn new(file: impl Into<String>, text: impl Into<String>) -> Self {
        Src {
            file: file.into(),
            text: text.into(),
        }
    }

    /// An error at byte offset `pos`.
    pub fn error(&self, pos: usize, message: impl Into<String>) -> PddlError {
        PddlError::At(Box::new(srctext::locate(
            &self.file, &self.text, pos, message,
        )))
    }
}

/// Why a PDDL domain / problem was not read or not translated.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PddlError {
    /// Malformed or unsupported text, at its place.
    #[error("{0}")]
    At(Box<srctext::Located>),
    /// The file could not be read.
    #[error("{0}")]
    Read(String),
}

/// Whether a file is PDDL: a `.pddl` name, or a text whose first form (after `;` comments) is `(define`.
pub fn is_pddl(path: &Path) -> bool {
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("pddl"))
    {
        return true;
    }
    std::fs::read(path).is_ok_and(|b| looks_like_pddl(&String::from_utf8_lossy(&b)))
}

/// Whether a text starts with `(define` after blanks and `;` comments.
pub fn looks_like_pddl(text: &str) -> bool {
    let mut rest = text.trim_start_matches('\u{feff}');
    loop {
        rest = rest.trim_start();
        if let Some(r) = rest.strip_prefix(';') {
            rest = r.find('\n').map_or("", |i| &r[i..]);
        } else {
            break;
        }
    }
    rest.strip_prefix('(')
        .is_some_and(|r| r.trim_start().to_lowercase().starts_with("define"))
}

/// Reads a file as UTF-8 text (the first bad byte located).
pub fn read_src(path: &Path) -> Result<Src, PddlError> {
    match srctext::read(path) {
        Ok(t) => Ok(Src::new(path.display().to_string(), t)),
        Err(srctext::ReadError::Utf8(l)) => Err(PddlError::At(Box::new(l))),
        Err(e) => Err(PddlError::Read(e.to_string())),
    }
}

/// Parses a domain text.
pub fn parse_domain(src: &Src) -> Result<ast::Domain, PddlError> {
    parse::domain(src)
}

/// Parses a problem text.
pub fn parse_problem(src: &Src) -> Result<ast::Problem, PddlError> {
    parse::problem(src)
}
