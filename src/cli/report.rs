//! `mavtempo report RUN.json [--out DIR]`: the pictures of a mission report (`demo`, `run` or `soak
//! --report FILE`): the executed plan over time, each reservoir against its bounds, the track on a map,
//! and one HTML page holding them with the goals and the counters.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use crate::cli::out::outln;
use crate::report::{self, data::Charts};

#[derive(Args, Debug)]
pub struct ReportArgs {
    /// A mission report written with --report FILE.
    pub report: PathBuf,
    /// Where the page and the SVG files go (created if missing).
    #[arg(long, default_value = "report")]
    pub out: PathBuf,
}

pub fn run(args: ReportArgs) -> ExitCode {
    let view = match report::read_report(&args.report) {
        Ok(v) => v,
        Err(e) => {
            crate::cli::out::errln!("mavtempo report: {e}");
            return ExitCode::FAILURE;
        }
    };
    let charts = Charts::from_report(&view);
    let title = format!("mavtempo: {}", args.report.display());
    match report::write_all(&args.out, &title, &charts) {
        Ok(files) => {
            outln!(
                "{} actions, {} marks, {} resources, {} track points, {} goals",
                charts.bars.len(),
                charts.marks.len(),
                charts.series.len(),
                charts.track.len(),
                charts.goals.len()
            );
            for f in files {
                outln!("wrote {}", f.display());
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            crate::cli::out::errln!("mavtempo report: {e}");
            ExitCode::FAILURE
        }
    }
}
