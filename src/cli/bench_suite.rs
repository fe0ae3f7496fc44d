//! `mavtempo bench suite`: the planner on random problems of growing size (see `planner::suite`).

use std::process::ExitCode;
use std::time::Duration;

use super::bench::SuiteArgs;
use crate::bench::suite::generate::{Mission, SuiteDomain};
use crate::bench::suite::{self, pddl, SuiteOptions, SuiteRun};
use crate::cli::out::outln;

pub fn run(args: &SuiteArgs) -> ExitCode {
    let domain = match args.domain.as_deref() {
        None => None,
        Some("rover") => Some(SuiteDomain::Rover),
        Some("auv") => Some(SuiteDomain::Auv),
        Some("shopping") => Some(SuiteDomain::Shopping),
        Some(other) => {
            crate::cli::out::errln!(
                "bench suite: unknown domain `{other}` (rover, auv or shopping)"
            );
            return ExitCode::FAILURE;
        }
    };
    if !(args.time_limit.is_finite() && args.time_limit > 0.0) {
        crate::cli::out::errln!("bench suite: --time-limit must be a positive number of seconds");
        return ExitCode::FAILURE;
    }
    let opts = SuiteOptions {
        seeds: args.seeds,
        first_seed: args.first_seed,
        time_limit: Duration::from_secs_f64(args.time_limit),
        domain,
        max_size: args.max_size,
    };
    let json = args.json;
    let mut write_error: Option<String> = None;
    let mut each = |r: &SuiteRun, mission: &Mission, text: &str| {
        if let Some(dir) = &args.write {
            let d = dir.join(r.domain.name());
            let mut files = vec![(
                d.join(format!("{}{}_{}.ixt", r.domain.name(), r.size, r.seed)),
                text.to_string(),
            )];
            if args.pddl {
                files.push((d.join("domain.pddl"), pddl::domain(r.domain).to_string()));
                files.push((d.join(pddl::file_name(mission)), pddl::problem(mission)));
            }
            for (file, body) in files {
                if let Err(e) =
                    std::fs::create_dir_all(&d).and_then(|()| std::fs::write(&file, body))
                {
                    write_error.get_or_insert(format!("{}: {e}", file.display()));
                }
            }
        }
        if json {
            if let Ok(line) = serde_json::to_string(r) {
                outln!("{line}");
            }
        } else if !r.solved {
            crate::cli::out::errln!(
                "  {} n={} seed={}: {}",
                r.domain.name(),
                r.size,
                r.seed,
                r.failure.as_deref().unwrap_or("not solved")
            );
        }
    };
    let sizes = match suite::run(std::path::Path::new("domains"), &opts, &mut each) {
        Ok(s) => s,
        Err(e) => {
            crate::cli::out::errln!("bench suite: {e}");
            return ExitCode::FAILURE;
        }
    };
    if let Some(e) = write_error {
        crate::cli::out::errln!("bench suite: cannot write a problem: {e}");
        return ExitCode::FAILURE;
    }
    for s in &sizes {
        if json {
            if let Ok(line) = serde_json::to_string(s) {
                outln!("{line}");
            }
        } else {
            let ms = |v: Option<f64>| v.map_or("-".to_string(), |m| format!("{m:.0} ms"));
            outln!(
                "{:<9} n={:<3} solved {:>2}/{:<2}  median {:>9}  max {:>9}",
                s.domain.name(),
                s.size,
                s.solved,
                s.problems,
                ms(s.median_ms),
                ms(s.max_ms)
            );
        }
    }
    ExitCode::SUCCESS
}
