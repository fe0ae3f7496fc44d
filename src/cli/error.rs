//! Why a command failed: the library's typed errors as they print, and the few the command line finds
//! itself (a flag out of range, a vehicle that never answers). Each prints the message users see.

use std::io;
use std::net::SocketAddr;

use thiserror::Error;

use crate::lang::Diagnostics;
use crate::planner::PlanFailure;
use crate::vehicle::config::ConfigError;
use crate::vehicle::goal_files::FileError;
use crate::vehicle::link::LinkError;

#[derive(Debug, Error)]
pub enum CliError {
    #[error("{0}")]
    Read(#[from] srctext::ReadError),
    #[error("{0}")]
    Lang(#[from] Diagnostics),
    #[error("{0}")]
    Config(#[from] ConfigError),
    #[error("{0}")]
    GoalFile(#[from] FileError),
    #[error("{0}")]
    Link(#[from] LinkError),
    #[error("{0}")]
    Sim(#[from] sitl::SimError),
    /// Every mismatch of a configuration with its domain, one a line, then the count.
    #[error("{issues}\n{origin} does not match domain `{domain}`: {errors} error(s)")]
    ConfigMismatch {
        issues: String,
        origin: String,
        domain: String,
        errors: usize,
    },
    #[error("no initial plan for {problem}: {failure}")]
    NoInitialPlan {
        problem: String,
        failure: PlanFailure,
    },
    #[error("report serialisation: {0}")]
    Serialise(#[from] serde_json::Error),
    #[error("cannot write {path}: {source}")]
    Write { path: String, source: io::Error },
    /// The report's page (charts or HTML) could not be made or written.
    #[error("{0}")]
    Page(#[from] crate::report::ReportError),
    /// A runtime, handler or thread the command needs (`what` names it).
    #[error("{what}: {source}")]
    Setup {
        what: &'static str,
        source: io::Error,
    },
    #[error("--http {addr}: {source}")]
    Http { addr: SocketAddr, source: io::Error },
    #[error("--speedup must be > 0, got {0}")]
    Speedup(f64),
    #[error("--http-goals needs --gcs (the form uploads there)")]
    HttpGoalsWithoutGcs,
    #[error(
        "check --config {config}: give the domain and optionally the problem, got {files} files"
    )]
    CheckFiles { config: String, files: usize },
    #[error("{0} before the mission started: nothing sent to the vehicle, no report")]
    Interrupted(String),
    #[error("no heartbeat and clock from the vehicle within {0} s")]
    NoHeartbeat(u64),
    /// The vehicle did not become ready (fix, arming) in time: which step is missing.
    #[error("{0}")]
    NotReady(String),
    #[error("the ground-station endpoint has no address")]
    NoGcsAddress,
    #[error("--nominal-for takes CONFIG DOMAIN PROBLEM, got {0} files")]
    NominalFor(usize),
    #[error("the vehicle link did not connect to the SITL")]
    SitlNotConnected,
    #[error("no telemetry from the SITL rover")]
    NoTelemetry,
    #[error("the mission did not run")]
    NoMission,
}
