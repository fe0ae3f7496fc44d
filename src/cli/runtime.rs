//! The tokio runtimes the subcommands start for their sockets, the SITL and the live page.

use tokio::runtime::Runtime;

use super::error::CliError;

/// A multi-threaded runtime with `workers` threads (None: one per core); `what` names it in the error.
pub fn multi_thread(workers: Option<usize>, what: &'static str) -> Result<Runtime, CliError> {
    let mut builder = tokio::runtime::Builder::new_multi_thread();
    if let Some(n) = workers {
        builder.worker_threads(n);
    }
    builder
        .enable_all()
        .build()
        .map_err(|source| CliError::Setup { what, source })
}
