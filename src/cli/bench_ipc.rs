//! `mavtempo bench ipc`: the IPC-2002 temporal Rovers and Satellite benchmarks (Time and SimpleTime) read
//! as PDDL, planned, checked by the independent checker and replayed on the PDDL: solved, search time,
//! makespan per instance; totals per domain and variant.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

use serde::Serialize;

use super::bench::IpcArgs;
use crate::cli::out::outln;
use crate::pddl;
use crate::planner::Budget;

/// The benchmarks' default place, relative to the repository (as `../shared` is on the lab machine).
pub const DEFAULT_DIR: &str = "../shared/benchmarks/ipc2002";

/// One instance's result (one JSON line).
#[derive(Debug, Clone, Serialize)]
struct Row {
    domain: String,
    variant: String,
    instance: u32,
    solved: bool,
    /// Search time alone (ms).
    ms: f64,
    /// Parsing and translation (ms).
    prepare_ms: f64,
    makespan: Option<f64>,
    actions: Option<usize>,
    reason: Option<String>,
}

fn parse_range(s: &str) -> Option<(u32, u32)> {
    match s.split_once('-') {
        Some((a, b)) => Some((a.trim().parse().ok()?, b.trim().parse().ok()?)),
        None => {
            let v = s.trim().parse().ok()?;
            Some((v, v))
        }
    }
}

/// `<dir>/<domain>-time[-simple]-automatic`.
fn folder(domain: &str, variant: &str) -> String {
    match variant {
        "simple" => format!("{domain}-time-simple-automatic"),
        _ => format!("{domain}-time-automatic"),
    }
}

pub fn run(args: &IpcArgs) -> ExitCode {
    let dir = args
        .dir
        .clone()
        .unwrap_or_else(|| PathBuf::from(DEFAULT_DIR));
    let Some((first, last)) = parse_range(&args.instances) else {
        crate::cli::out::errln!("bench ipc: --instances takes N or N-M (e.g. 1-10)");
        return ExitCode::FAILURE;
    };
    if !(args.time_limit.is_finite() && args.time_limit > 0.0) {
        crate::cli::out::errln!("bench ipc: --time-limit must be a positive number of seconds");
        return ExitCode::FAILURE;
    }
    let domains: Vec<&str> = args.domains.split(',').map(str::trim).collect();
    let variants: Vec<&str> = args.variants.split(',').map(str::trim).collect();
    if let Some(d) = domains
        .iter()
        .find(|d| !matches!(**d, "rovers" | "satellite"))
    {
        crate::cli::out::errln!("bench ipc: unknown domain `{d}` (rovers, satellite)");
        return ExitCode::FAILURE;
    }
    if let Some(v) = variants.iter().find(|v| !matches!(**v, "simple" | "time")) {
        crate::cli::out::errln!("bench ipc: unknown variant `{v}` (simple, time)");
        return ExitCode::FAILURE;
    }
    if !dir.is_dir() {
        crate::cli::out::errln!("bench ipc: no benchmark directory {}", dir.display());
        return ExitCode::FAILURE;
    }
    let mut rows: Vec<Row> = Vec::new();
    if !args.json {
        outln!(
            "{:<10} {:<7} {:>4}  {:>6} {:>10} {:>10} {:>9} {:>7}",
            "domain",
            "variant",
            "inst",
            "solved",
            "search ms",
            "prep ms",
            "makespan",
            "actions"
        );
    }
    for d in &domains {
        for v in &variants {
            let name = folder(d, v);
            let base = dir.join(&name);
            for i in first..=last {
                let problem = base.join("instances").join(format!("instance-{i}.pddl"));
                if !problem.is_file() {
                    continue;
                }
                let row = one(d, v, i, &base.join("domain.pddl"), &problem, args, &name);
                if args.json {
                    if let Ok(line) = serde_json::to_string(&row) {
                        outln!("{line}");
                    }
                } else {
                    outln!(
                        "{:<10} {:<7} {:>4}  {:>6} {:>10.1} {:>10.1} {:>9} {:>7}{}",
                        row.domain,
                        row.variant,
                        row.instance,
                        if row.solved { "yes" } else { "no" },
                        row.ms,
                        row.prepare_ms,
                        row.makespan.map_or("-".into(), |m| format!("{m:.3}")),
                        row.actions.map_or("-".into(), |a| a.to_string()),
                        row.reason
                            .as_deref()
                            .map_or(String::new(), |r| format!("  {}", first_line(r))),
                    );
                }
                rows.push(row);
            }
        }
    }
    if !args.json {
        outln!("totals:");
        for d in &domains {
            for v in &variants {
                let these: Vec<&Row> = rows
                    .iter()
                    .filter(|r| r.domain == *d && r.variant == *v)
                    .collect();
                let mut ms: Vec<f64> = these.iter().filter(|r| r.solved).map(|r| r.ms).collect();
                ms.sort_by(f64::total_cmp);
                let median = match ms.len() {
                    0 => None,
                    n if n % 2 == 1 => ms.get(n / 2).copied(),
                    n => Some((ms[n / 2 - 1] + ms[n / 2]) / 2.0),
                };
                outln!(
                    "  {d:<10} {v:<7} solved {}/{}  median search {}",
                    ms.len(),
                    these.len(),
                    median.map_or("-".into(), |m| format!("{m:.1} ms"))
                );
            }
        }
    }
    ExitCode::SUCCESS
}

fn first_line(s: &str) -> &str {
    s.lines().next().unwrap_or("")
}

fn one(
    d: &str,
    v: &str,
    i: u32,
    domain: &Path,
    problem: &Path,
    args: &IpcArgs,
    folder: &str,
) -> Row {
    let mut row = Row {
        domain: d.to_string(),
        variant: v.to_string(),
        instance: i,
        solved: false,
        ms: 0.0,
        prepare_ms: 0.0,
        makespan: None,
        actions: None,
        reason: None,
    };
    let started = Instant::now();
    let loaded = pddl::load(domain, problem);
    row.prepare_ms = started.elapsed().as_secs_f64() * 1e3;
    let loaded = match loaded {
        Ok(l) => l,
        Err(e) => {
            row.reason = Some(format!("refused: {e}"));
            return row;
        }
    };
    let budget = Budget {
        max_steps: None,
        deadline: Some(Instant::now() + Duration::from_secs_f64(args.time_limit)),
    };
    match pddl::solve(&loaded, budget) {
        Ok(s) => {
            row.solved = true;
            row.ms = s.search_ms;
            row.makespan = Some(s.ipc.makespan_ms() as f64 / 1000.0);
            row.actions = Some(s.ipc.steps.len());
            if let Some(out) = &args.plans_out {
                let dir = out.join(folder);
                let file = dir.join(format!("instance-{i}.plan"));
                if let Err(e) = std::fs::create_dir_all(&dir)
                    .and_then(|()| std::fs::write(&file, s.ipc.to_string()))
                {
                    row.reason = Some(format!("plan not written: {}: {e}", file.display()));
                }
            }
        }
        Err(e) => {
            row.ms = e.search_ms();
            row.reason = Some(e.to_string());
        }
    }
    row
}
