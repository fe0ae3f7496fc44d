//! What mavtempo's test binaries share, out of the shipped binary: a dev-dependency of the layer crates and
//! of the application, never a dependency.
//! - [`repo!`]: a path of the repository from a crate at `src/<name>` (tests run in their crate's directory);
//! - [`problems`]: the shipped rover problems, varied;
//! - [`mapping`]: the executive's `[mapping]` of a shipped configuration, through the check `run` uses;
//! - [`http`]: one raw HTTP/1.1 exchange;
//! - [`stops`]: where a stopped move leaves the mock vehicle.

/// `repo!("domains/rover/rover.ixt")`: that file of the repository, as a `&'static str`, from a crate two
/// levels down (`src/<name>`), whose directory its tests run in.
#[macro_export]
macro_rules! repo {
    ($rel:literal) => {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../", $rel)
    };
}

pub mod http;
pub mod mapping;
pub mod problems;
pub mod stops;
