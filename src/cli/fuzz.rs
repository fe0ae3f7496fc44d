//! `mavtempo fuzz --target T --execs N --seed S [--save DIR] [--json] [--replay FILE]`: wiring and printing
//! of [`crate::fuzz`].

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;

use crate::fuzz::{self, Target};

#[derive(Args, Debug)]
pub struct FuzzArgs {
    /// What to fuzz: domain, problem, config (vehicle + [exec]), scenario, goals, intake, or all.
    #[arg(long, default_value = "all")]
    pub target: TargetArg,
    /// Executions per target.
    #[arg(long, default_value_t = 100_000)]
    pub execs: u64,
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

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
pub enum TargetArg {
    Domain,
    Problem,
    Config,
    Scenario,
    Goals,
    Intake,
    All,
}

impl TargetArg {
    fn targets(self) -> Vec<Target> {
        match self {
            TargetArg::Domain => vec![Target::Domain],
            TargetArg::Problem => vec![Target::Problem],
            TargetArg::Config => vec![Target::Config],
            TargetArg::Scenario => vec![Target::Scenario],
            TargetArg::Goals => vec![Target::Goals],
            TargetArg::Intake => vec![Target::Intake],
            TargetArg::All => Target::ALL.to_vec(),
        }
    }
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
    for target in args.target.targets() {
        let r = fuzz::run(target, args.execs, args.seed, &save);
        failed |= r.failures > 0;
        if args.json {
            match serde_json::to_string(&r) {
                Ok(line) => println!("{line}"),
                Err(e) => eprintln!("mavtempo fuzz: {e}"),
            }
            continue;
        }
        println!(
            "{:<8} {:>10} execs in {:>7.1} s = {:>9.0} execs/s, slowest {:.1} ms, {} failures",
            target.name(),
            r.execs,
            r.seconds,
            r.execs_per_s,
            r.slowest_ms,
            r.failures
        );
        for k in &r.kinds {
            println!("  {} x {}", k.count, k.message.replace('\n', " "));
            for p in &k.saved {
                println!("    saved {}", p.display());
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
    let [target] = args.target.targets()[..] else {
        eprintln!("mavtempo fuzz --replay: name one --target");
        return ExitCode::FAILURE;
    };
    let input = match std::fs::read(file) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("mavtempo fuzz: {}: {e}", file.display());
            return ExitCode::FAILURE;
        }
    };
    match fuzz::replay(target, &input) {
        Ok(()) => {
            println!("{}: passes", file.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            println!("{}: fails: {e}", file.display());
            ExitCode::FAILURE
        }
    }
}
