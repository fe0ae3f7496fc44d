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
    /// Achieved speed-up of the built-in SITL on a 10-waypoint mission at --speedup 500.
    Sim,
}

pub fn run(args: BenchArgs) -> ExitCode {
    match args.what {
        BenchWhat::Stn => {
            tracing::error!("bench stn: not yet implemented");
            let _ = args.json;
            ExitCode::FAILURE
        }
        BenchWhat::Sim => bench_sim(args.json),
    }
}

fn bench_sim(json: bool) -> ExitCode {
    let report = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| e.to_string())
        .and_then(|rt| {
            rt.block_on(sitl::bench::measure_speedup(500.0, 10, 100.0))
                .map_err(|e| e.to_string())
        });
    match report {
        Ok(r) if json => match serde_json::to_string(&r) {
            Ok(line) => {
                println!("{line}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("bench sim: {e}");
                ExitCode::FAILURE
            }
        },
        Ok(r) => {
            println!(
                "sim speed-up: requested {:.0}x, achieved {:.1}x ({} waypoints, {:.1} s sim in {:.3} s wall); ceiling {:.0}x",
                r.speedup_requested, r.speedup_achieved, r.waypoints, r.sim_s, r.wall_s, r.speedup_ceiling
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("bench sim: {e}");
            ExitCode::FAILURE
        }
    }
}
