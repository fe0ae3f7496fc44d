//! `mavtempo fuzz --target T --execs N --seed S [--save DIR] [--json] [--replay FILE]`: wiring and printing
//! of [`crate::fuzz`].

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use crate::cli::out::outln;
use crate::fuzz::{self, Target};

#[derive(Args, Debug)]
pub struct FuzzArgs {
    /// What to fuzz: domain, problem, config (vehicle + [exec]), scenario, goals, intake, or all.
    #[arg(long, default_value = "all", value_parser = targets)]
    pub target: Targets,
    /// Executions per target.
    #[arg(long, default_value_t = 100_000)]
    pub execs: u64,
    /// Seeds the mutations: the same seed gives the same inputs.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Where failing inputs are written (default: a `mavtempo-fuzz` directory in the temp dir).
    #[arg(long)]
    pub save: Option<PathBuf>,
    /// One JSON object per target.
    #[arg(long)]
    pub json: bool,
    /// Run one saved input of --target (not all) and say whether it still fails.
    #[arg(long, value_name = "FILE")]
    pub replay: Option<PathBuf>,
}

/// The targets `--target` names (a newtype: clap reads a bare `Vec` as a repeated option).
#[derive(Debug, Clone)]
pub struct Targets(Vec<Target>);

/// A `--target` that names no fuzz target.
#[derive(Debug, thiserror::Error)]
#[error("`{0}`: expected all, domain, problem, config, scenario, goals or intake")]
pub struct UnknownTarget(String);

/// `all`, or one target's name.
fn targets(s: &str) -> Result<Targets, UnknownTarget> {
    if s == "all" {
        return Ok(Targets(Target::ALL.to_vec()));
    }
    <Target as clap::ValueEnum>::from_str(s, false)
        .map(|t| Targets(vec![t]))
        .map_err(|_| UnknownTarget(s.to_string()))
}

pub fn run(args: FuzzArgs) -> ExitCode {
    if let Some(file) = &args.replay {
        return replay(&args, file);
    }
    let save = args
        .save
        .clone()
        .unwrap_or_else(|| std::env::temp_dir().join("mavtempo-fuzz"));
    let mut failed = false;
    for &target in &args.target.0 {
        let r = fuzz::run(target, args.execs, args.seed, &save);
        failed |= r.failures > 0;
        if args.json {
            match serde_json::to_string(&r) {
                Ok(line) => outln!("{line}"),
                Err(e) => crate::cli::out::errln!("mavtempo fuzz: {e}"),
            }
            continue;
        }
        outln!(
            "{:<8} {:>10} execs in {:>7.1} s = {:>9.0} execs/s, slowest {:.1} ms, {} failures",
            target.name(),
            r.execs,
            r.seconds,
            r.execs_per_s,
            r.slowest_ms,
            r.failures
        );
        for k in &r.kinds {
            outln!("  {} x {}", k.count, k.message.replace('\n', " "));
            for p in &k.saved {
                outln!("    saved {}", p.display());
            }
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

fn replay(args: &FuzzArgs, file: &std::path::Path) -> ExitCode {
    let [target] = args.target.0[..] else {
        crate::cli::out::errln!("mavtempo fuzz --replay: name one --target");
        return ExitCode::FAILURE;
    };
    let input = match std::fs::read(file) {
        Ok(b) => b,
        Err(e) => {
            crate::cli::out::errln!("mavtempo fuzz: {}: {e}", file.display());
            return ExitCode::FAILURE;
        }
    };
    match fuzz::replay(target, &input) {
        Ok(()) => {
            outln!("{}: passes", file.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            outln!("{}: fails: {e}", file.display());
            ExitCode::FAILURE
        }
    }
}
