//! The domain / problem language: a readable text close to IxTeT's (seed 1 Fig. 3), documented with its
//! grammar in `domains/README.md`. `lexer` → `parser` (syntax trees) → `resolve_*` (semantic checks that
//! build the [`crate::model`]). Every error is a [`Diagnostic`] (`file:line:col`, the line, a caret); no
//! input, whatever its bytes, makes these functions panic.

mod ast;
mod diag;
mod eval;
pub mod generate;
mod lexer;
mod lint;
mod load;
mod parser;
mod resolve_domain;
mod resolve_problem;
mod resolve_task;

pub use diag::{decode, Diagnostic, Diagnostics, Span, Warning};
pub use load::{
    domain_path_for, load_domain, load_problem, load_problem_and_domain, load_problem_warned,
    parse_domain, parse_goal, parse_problem, parse_problem_warned, peek_header, FileKind,
    EXTENSION,
};
