//! `mavtempo plan DOMAIN.pddl PROBLEM.pddl [--pddl-out FILE]`: a PDDL problem planned like a native one;
//! the plan checked by the independent checker (on the translation) and replayed on the PDDL, printed in
//! the IPC format (`--pddl-out -`: only the IPC plan on stdout, the summary on stderr).

use std::process::ExitCode;

use super::plan::PlanArgs;
use crate::cli::out::{out, outln};
use crate::pddl;
use crate::planner::Budget;

pub fn run(args: &PlanArgs) -> ExitCode {
    let loaded = match pddl::load(&args.domain, &args.problem) {
        Ok(l) => l,
        Err(e) => {
            crate::cli::out::errln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let t = &loaded.translated;
    for n in &t.notes {
        crate::cli::out::errln!("note: {n}");
    }
    let solved = match pddl::solve(&loaded, Budget::steps(args.max_steps)) {
        Ok(s) => s,
        Err(e) => {
            crate::cli::out::errln!("{}: {e}", t.problem.name);
            return ExitCode::FAILURE;
        }
    };
    let summary = format!(
        "{} actions, makespan {:.3} s, {} planning steps, {} backtracks\nchecker: plan accepted; IPC plan replayed on the PDDL: valid",
        solved.ipc.steps.len(),
        solved.ipc.makespan_ms() as f64 / 1000.0,
        solved.steps,
        solved.backtracks
    );
    let to_stdout = args.pddl_out.as_deref() == Some(std::path::Path::new("-"));
    if let Some(path) = args.pddl_out.as_deref().filter(|_| !to_stdout) {
        if let Err(e) = std::fs::write(path, solved.ipc.to_string()) {
            crate::cli::out::errln!("cannot write {}: {e}", path.display());
            return ExitCode::FAILURE;
        }
    }
    if args.json {
        let printed =
            super::json_out::print_json_pretty("cannot serialise the plan", &solved.solution);
        if printed != ExitCode::SUCCESS {
            return printed;
        }
    } else if args.dot {
        out!("{}", super::plan::dot(&solved.solution, &t.problem));
    } else if to_stdout {
        out!("{}", solved.ipc);
        crate::cli::out::errln!("{summary}");
    } else {
        outln!("plan for {} ({}):", t.problem.name, t.domain.name);
        out!("{}", solved.ipc);
        outln!("{summary}");
    }
    ExitCode::SUCCESS
}
