//! `mavtempo bench <what> [--json] [options of <what>]`: one subcommand per benchmark, each with its own
//! options (`bench suite --help`, `bench ipc --help`).

use std::process::ExitCode;

use clap::{Args, Subcommand};

use super::json_out::print_json_lines;
use crate::bench::stn as stn_bench;
use crate::cli::out::outln;

#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub what: BenchWhat,
}

/// `--json`, the only option most benchmarks take.
#[derive(Args, Debug)]
pub struct JsonArg {
    /// One JSON object per line instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// `bench suite`'s options.
#[derive(Args, Debug)]
pub struct SuiteArgs {
    /// One JSON object per line instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Seeds per size.
    #[arg(long, default_value_t = 10)]
    pub seeds: u64,
    /// The first seed (seed S, S+1, … per size).
    #[arg(long, default_value_t = 1000)]
    pub first_seed: u64,
    /// Only this domain (rover, auv, shopping).
    #[arg(long)]
    pub domain: Option<String>,
    /// Only sizes up to this one.
    #[arg(long)]
    pub max_size: Option<usize>,
    /// Planning time limit per problem, seconds.
    #[arg(long, default_value_t = 10.0)]
    pub time_limit: f64,
    /// Write each generated problem to DIR/<domain>/<name>.ixt (for other planners).
    #[arg(long, value_name = "DIR")]
    pub write: Option<std::path::PathBuf>,
    /// With --write: also in PDDL, DIR/<domain>/domain.pddl and DIR/<domain>/n<N>_s<SEED>.pddl.
    #[arg(long, requires = "write")]
    pub pddl: bool,
}

/// `bench plan`'s options.
#[derive(Args, Debug)]
pub struct PlanArgs {
    /// One JSON object per line instead of a table.
    #[arg(long)]
    pub json: bool,
    /// The generated rover grids to plan, by number of targets (repeatable; default 10, 20, 40).
    #[arg(long = "grid", value_name = "TARGETS")]
    pub grids: Vec<usize>,
}

/// `bench ipc`'s options.
#[derive(Args, Debug)]
pub struct IpcArgs {
    /// One JSON object per line instead of a table.
    #[arg(long)]
    pub json: bool,
    /// The IPC-2002 benchmarks' directory (default: ../shared/benchmarks/ipc2002).
    #[arg(long)]
    pub dir: Option<std::path::PathBuf>,
    /// Instance numbers, N or N-M.
    #[arg(long, default_value = "1-20")]
    pub instances: String,
    /// Domains, comma-separated (rovers, satellite).
    #[arg(long, default_value = "rovers,satellite")]
    pub domains: String,
    /// Variants, comma-separated (simple = SimpleTime, time = Time).
    #[arg(long, default_value = "simple,time")]
    pub variants: String,
    /// Planning time limit per instance, seconds.
    #[arg(long, default_value_t = 10.0)]
    pub time_limit: f64,
    /// Write each solved plan to DIR/<benchmark folder>/instance-N.plan (IPC format).
    #[arg(long, value_name = "DIR")]
    pub plans_out: Option<std::path::PathBuf>,
}

/// One subcommand per benchmark, each with its own options.
#[derive(Subcommand, Debug)]
pub enum BenchWhat {
    /// Incremental STN vs Floyd-Warshall.
    Stn(JsonArg),
    /// Executive cycle time (p50/p99) on plans of 200 and 2,000 actions.
    Cycle(JsonArg),
    /// Plan repair vs complete replanning on each event kind of the rover mission (mock vehicle).
    Repair(JsonArg),
    /// Planning time and steps on the shipped and generated problems.
    Plan(PlanArgs),
    /// Achieved speed-up of the built-in SITL on a 10-waypoint mission at --speedup 500.
    Sim(JsonArg),
    /// Goal-driven dispatch decision cost, Algorithm 2 vs the incremental marking, at 200 and 2,000 actions.
    Dispatch(JsonArg),
    /// MAVLink link: 100-item mission upload over loopback, telemetry messages per second.
    Link(JsonArg),
    /// Executive CPU over a Dala-length mission (1,285 s) against the in-process SITL.
    Cpu(JsonArg),
    /// Random rover, AUV and shopping problems of growing size: solved share and time per size, plans checked.
    Suite(SuiteArgs),
    /// IPC-2002 Rovers and Satellite (Time, SimpleTime) read as PDDL: solved, search time, makespan.
    Ipc(IpcArgs),
}

pub fn run(args: BenchArgs) -> ExitCode {
    match args.what {
        BenchWhat::Stn(a) => bench_stn(a.json),
        BenchWhat::Cycle(a) => bench_cycle(a.json),
        BenchWhat::Plan(a) => bench_plan(a.json, &a.grids),
        BenchWhat::Repair(a) => bench_repair(a.json),
        BenchWhat::Sim(a) => bench_sim(a.json),
        BenchWhat::Dispatch(a) => bench_dispatch(a.json),
        BenchWhat::Link(a) => bench_link(a.json),
        BenchWhat::Cpu(a) => super::bench_cpu::run(a.json),
        BenchWhat::Suite(a) => super::bench_suite::run(&a),
        BenchWhat::Ipc(a) => super::bench_ipc::run(&a),
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
            crate::cli::out::errln!("{what}: {e}");
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

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::super::{Cli, Command};
    use super::BenchWhat;

    fn parse(line: &str) -> Result<BenchWhat, clap::Error> {
        let args = std::iter::once("mavtempo").chain(line.split_whitespace());
        match Cli::try_parse_from(args)?.command {
            Command::Bench(b) => Ok(b.what),
            other => panic!("{other:?}"),
        }
    }

    /// The invocations the README, docs/, .ci/ and benches/peers/ write keep parsing, to the benchmark
    /// they name with the options they give.
    #[test]
    fn documented_invocations_parse() {
        for line in [
            "bench stn --json",
            "bench dispatch",
            "bench cycle --json",
            "bench cpu --json",
            "bench repair --json",
            "bench plan --json",
            "bench sim --json",
            "bench link --json",
        ] {
            assert!(parse(line).is_ok(), "{line}");
        }
        match parse("bench suite --seeds 10 --first-seed 1000 --max-size 4 --time-limit 3 --write D --pddl --json") {
            Ok(BenchWhat::Suite(s)) => {
                assert_eq!((s.seeds, s.first_seed, s.max_size), (10, 1000, Some(4)));
                assert!(s.pddl && s.json);
            }
            other => panic!("{other:?}"),
        }
        match parse("bench ipc --json --time-limit 10 --instances 1-20 --domains rovers,satellite --variants simple,time --plans-out P --dir D") {
            Ok(BenchWhat::Ipc(i)) => {
                assert_eq!((i.instances.as_str(), i.time_limit), ("1-20", 10.0));
                assert!(i.plans_out.is_some() && i.dir.is_some());
            }
            other => panic!("{other:?}"),
        }
    }

    /// An option of another benchmark is refused, not ignored.
    #[test]
    fn another_benchmarks_option_is_refused() {
        for line in [
            "bench stn --seeds 3",
            "bench ipc --seeds 3",
            "bench suite --instances 1-3",
            "bench cpu --time-limit 1",
        ] {
            let e = parse(line).map(|_| ()).expect_err(line);
            assert_eq!(e.kind(), clap::error::ErrorKind::UnknownArgument, "{line}");
        }
    }
}
