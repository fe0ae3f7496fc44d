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
    /// MAVLink link: 100-item mission upload over loopback, telemetry messages per second.
    Link,
}

pub fn run(args: BenchArgs) -> ExitCode {
    match args.what {
        BenchWhat::Stn => {
            tracing::error!("bench stn: not yet implemented");
            let _ = args.json;
            ExitCode::FAILURE
        }
        BenchWhat::Link => bench_link(args.json),
    }
}

fn bench_link(json: bool) -> ExitCode {
    match mavtempo_vehicle_bench() {
        Ok(b) => {
            if json {
                match serde_json::to_string(&b) {
                    Ok(s) => println!("{s}"),
                    Err(e) => {
                        eprintln!("bench link: {e}");
                        return ExitCode::FAILURE;
                    }
                }
            } else {
                println!(
                    "upload 100 items (median of {}): {:.2} ms (target <= 100 ms)",
                    b.upload_runs, b.upload_100_items_ms
                );
                println!(
                    "telemetry: {:.0} msgs/s over {} msgs (target >= 50000/s)",
                    b.telemetry_msgs_per_s, b.telemetry_msgs
                );
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("bench link: {e}");
            ExitCode::FAILURE
        }
    }
}

fn mavtempo_vehicle_bench(
) -> Result<crate::vehicle::bench::LinkBench, crate::vehicle::bench::BenchError> {
    crate::vehicle::bench::run_link_bench(21, 200_000)
}
