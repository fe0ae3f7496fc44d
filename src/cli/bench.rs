//! `mavtempo bench <what> [--json]`.

use std::process::ExitCode;

use clap::{Args, ValueEnum};

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// What to measure.
    pub what: BenchWhat,
    /// One JSON object per line instead of a table.
    #[arg(long)]
    pub json: bool,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum BenchWhat {
    /// Incremental STN vs Floyd-Warshall.
    Stn,
}

pub fn run(args: BenchArgs) -> ExitCode {
    match args.what {
        BenchWhat::Stn => {
            tracing::error!("bench stn: not yet implemented");
            let _ = args.json;
            ExitCode::FAILURE
        }
    }
}
