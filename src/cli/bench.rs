//! `mavtempo bench <what> [--json]`.

use std::process::ExitCode;

use clap::{Args, ValueEnum};

use super::json_out::print_json_lines;
use crate::bench::stn as stn_bench;
use crate::cli::out::outln;

#[derive(Args, Debug)]
pub struct BenchArgs {
    /// What to measure.
    pub what: BenchWhat,
    /// One JSON object per line instead of a table.
    #[arg(long)]
    pub json: bool,
    /// `suite`: seeds per size.
    #[arg(long, default_value_t = 10)]
    pub seeds: u64,
    /// `suite`: the first seed (seed S, S+1, … per size).
    #[arg(long, default_value_t = 1000)]
    pub first_seed: u64,
    /// `suite`: only this domain (rover, auv, shopping).
    #[arg(long)]
    pub domain: Option<String>,
    /// `suite`: only sizes up to this one.
    #[arg(long)]
    pub max_size: Option<usize>,
    /// `suite`: planning time limit per problem, seconds.
    #[arg(long, default_value_t = 10.0)]
    pub time_limit: f64,
    /// `suite`: write each generated problem to DIR/<domain>/<name>.ixt (for other planners).
    #[arg(long)]
    pub write: Option<std::path::PathBuf>,
    /// `suite`, with --write: also in PDDL, DIR/<domain>/domain.pddl and DIR/<domain>/n<N>_s<SEED>.pddl.
    #[arg(long, requires = "write")]
    pub pddl: bool,
    /// `plan`: the generated rover grids to plan, by number of targets (repeatable; default 10, 20, 40).
    #[arg(long = "grid")]
    pub grids: Vec<usize>,
    /// `ipc`: the IPC-2002 benchmarks' directory.
    #[arg(long)]
    pub dir: Option<std::path::PathBuf>,
    /// `ipc`: instance numbers, N or N-M.
    #[arg(long, default_value = "1-20")]
    pub instances: String,
    /// `ipc`: domains, comma-separated (rovers, satellite).
    #[arg(long, default_value = "rovers,satellite")]
    pub domains: String,
    /// `ipc`: variants, comma-separated (simple = SimpleTime, time = Time).
    #[arg(long, default_value = "simple,time")]
    pub variants: String,
    /// `ipc`: write each solved plan to DIR/<benchmark folder>/instance-N.plan (IPC format).
    #[arg(long)]
    pub plans_out: Option<std::path::PathBuf>,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum BenchWhat {
    /// Incremental STN vs Floyd-Warshall.
    Stn,
    /// Executive cycle time (p50/p99) on plans of 200 and 2,000 actions.
    Cycle,
    /// Plan repair vs complete replanning on each Fig. 2 event kind (rover, mock vehicle).
    Repair,
    /// Planning time and steps on the shipped and generated problems.
    Plan,
    /// Achieved speed-up of the built-in SITL on a 10-waypoint mission at --speedup 500.
    Sim,
    /// Goal-driven dispatch decision cost, Algorithm 2 vs the incremental marking, at 200 and 2,000 actions.
    Dispatch,
    /// MAVLink link: 100-item mission upload over loopback, telemetry messages per second.
    Link,
    /// Executive CPU over a Dala-length mission (1,285 s) against the in-process SITL.
    Cpu,
    /// Random rover, AUV and shopping problems of growing size: solved share and time per size, plans checked.
    Suite,
    /// IPC-2002 Rovers and Satellite (Time, SimpleTime) read as PDDL: solved, search time, makespan.
    Ipc,
}

pub fn run(args: BenchArgs) -> ExitCode {
    match args.what {
        BenchWhat::Stn => bench_stn(args.json),
        BenchWhat::Cycle => bench_cycle(args.json),
        BenchWhat::Plan => bench_plan(args.json, &args.grids),
        BenchWhat::Repair => bench_repair(args.json),
        BenchWhat::Sim => bench_sim(args.json),
        BenchWhat::Dispatch => bench_dispatch(args.json),
        BenchWhat::Link => bench_link(args.json),
        BenchWhat::Cpu => super::bench_cpu::run(args.json),
        BenchWhat::Suite => super::bench_suite::run(&args),
        BenchWhat::Ipc => super::bench_ipc::run(&args),
    }
}

/// A bench's figures: one JSON line each with `--json`, else printed by `table`. An error of the bench is
/// said on stderr as `{what}: {error}` and fails the command.
pub(super) fn show<T: serde::Serialize, E: std::fmt::Display>(
    what: &str,
    json: bool,
    figures: Result<Vec<T>, E>,
    table: impl FnOnce(&[T]),
) -> ExitCode {
    match figures {
        Ok(f) if json => print_json_lines(what, &f),
        Ok(f) => {
            table(&f);
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("{what}: {e}");
            ExitCode::FAILURE
        }
    }
}

fn bench_sim(json: bool) -> ExitCode {
    let report = super::runtime::multi_thread(None, "tokio runtime")
        .map_err(|e| e.to_string())
        .and_then(|rt| {
            rt.block_on(sitl::bench::measure_speedup(500.0, 10, 100.0))
                .map_err(|e| e.to_string())
        });
    show("bench sim", json, report.map(|r| vec![r]), |reports| {
        for r in reports {
            outln!(
                "sim speed-up: requested {:.0}x, achieved {:.1}x ({} waypoints, {:.1} s sim in {:.3} s wall); ceiling {:.0}x",
                r.speedup_requested, r.speedup_achieved, r.waypoints, r.sim_s, r.wall_s, r.speedup_ceiling
            );
        }
    })
}

fn bench_stn(json: bool) -> ExitCode {
    let figures = stn_bench::run(&[100, 1_000, 10_000], 1_000);
    show("bench stn", json, figures, |figures| {
        outln!(
            "{:>7} {:>8} {:>10} {:>11} {:>13} {:>8} {:>10}",
            "n",
            "constr",
            "insert µs",
            "execute µs",
            "exec med µs",
            "FW ms",
            "speed-up"
        );
        for f in figures {
            let fw = f
                .floyd_warshall_ms
                .map_or("-".into(), |v| format!("{v:.1}"));
            let sp = f
                .speedup_vs_floyd_warshall
                .map_or("-".into(), |v| format!("{v:.0}×"));
            outln!(
                "{:>7} {:>8} {:>10.3} {:>11.3} {:>13.3} {:>8} {:>10}",
                f.n,
                f.constraints,
                f.insert_mean_us,
                f.execute_mean_us,
                f.execute_median_us,
                fw,
                sp
            );
        }
    })
}

fn bench_dispatch(json: bool) -> ExitCode {
    let figures = crate::bench::dispatch::run(&[200, 2_000], 20_000, 2026);
    show("bench dispatch", json, figures, |figures| {
        let us = |v: Option<f64>| v.map_or("-".into(), |v| format!("{v:.3}"));
        outln!(
            "{:>7} {:>7} {:>9} {:>9} {:>9} {:>10} {:>11} {:>10} {:>10} {:>8}",
            "actions",
            "form",
            "mean µs",
            "p50 µs",
            "p99 µs",
            "dispatched",
            "upd mean µs",
            "upd p50 µs",
            "upd p99 µs",
            "build ms"
        );
        for f in figures {
            outln!(
                "{:>7} {:>7} {:>9.3} {:>9.3} {:>9.3} {:>10.2} {:>11} {:>10} {:>10} {:>8}",
                f.actions,
                f.form,
                f.mean_us,
                f.p50_us,
                f.p99_us,
                f.dispatched_share,
                us(f.update_mean_us),
                us(f.update_p50_us),
                us(f.update_p99_us),
                us(f.build_ms)
            );
        }
    })
}

fn bench_link(json: bool) -> ExitCode {
    let bench = crate::bench::vehicle::run_link_bench(21, 200_000);
    show("bench link", json, bench.map(|b| vec![b]), |benches| {
        for b in benches {
            outln!(
                "upload 100 items (median of {}): {:.2} ms (target <= 100 ms); telemetry: {:.0} msgs/s over {} msgs (target >= 50000/s)",
                b.upload_runs, b.upload_100_items_ms, b.telemetry_msgs_per_s, b.telemetry_msgs
            );
        }
    })
}

fn bench_plan(json: bool, grids: &[usize]) -> ExitCode {
    let grids = if grids.is_empty() {
        &crate::bench::plan::DEFAULT_GRIDS[..]
    } else {
        grids
    };
    let figures = crate::bench::plan::run(std::path::Path::new("domains"), 20_000, grids);
    show("bench plan", json, figures, |figures| {
        for f in figures {
            outln!(
                "{:<18} {:>6} {:>10.1} ms {:>7} steps {:>6} backtracks {:>4} actions {}",
                f.problem,
                if f.solved { "solved" } else { "FAILED" },
                f.ms,
                f.steps,
                f.backtracks,
                f.actions,
                f.failure.as_deref().unwrap_or("")
            );
        }
    })
}

fn bench_cycle(json: bool) -> ExitCode {
    // Each size is printed as soon as it is measured.
    for n in [200, 2_000] {
        let figures = crate::bench::exec::run(n, 100).map(|f| vec![f]);
        let shown = show("bench cycle", json, figures, |figures| {
            for f in figures {
                outln!(
                    "{:>6} actions: {} cycles, p50 {} µs, p99 {} µs, max {} µs",
                    f.actions,
                    f.cycles,
                    f.p50_us,
                    f.p99_us,
                    f.max_us
                );
            }
        });
        if shown != ExitCode::SUCCESS {
            return shown;
        }
    }
    ExitCode::SUCCESS
}

fn bench_repair(json: bool) -> ExitCode {
    show(
        "bench repair",
        json,
        crate::bench::repair::run(),
        |figures| {
            for f in figures {
                let repair = f
                    .repair_ms
                    .map_or("no repair (replanned)".to_string(), |ms| {
                        format!("{ms:.2} ms")
                    });
                outln!(
                    "{:<16} repair {repair}, complete replanning {:.2} ms ({})",
                    f.event,
                    f.replan_ms,
                    if f.replan_found {
                        "plan found"
                    } else {
                        "no plan"
                    }
                );
            }
        },
    )
}
