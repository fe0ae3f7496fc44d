//! Planning a PDDL problem end to end: the planner on the translation, the independent checker on its
//! plan, the IPC plan ([`super::writer`]) and its replay on the PDDL itself ([`super::simulate`]).

use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

use super::finalise::{self, FinaliseError};
use super::{ast, simulate, writer, PddlError, Translated};
use crate::plan::solution::Solution;
use crate::plan::validate::validate;
use crate::planner::{self, Budget, PlanFailure};

/// A PDDL domain and problem, parsed and translated.
#[derive(Debug, Clone)]
pub struct Loaded {
    pub domain: ast::Domain,
    pub problem: ast::Problem,
    pub translated: Translated,
}

/// Reads, parses and translates a domain and a problem file.
pub fn load(domain: &Path, problem: &Path) -> Result<Loaded, PddlError> {
    let ds = super::read_src(domain)?;
    let ps = super::read_src(problem)?;
    let d = super::parse_domain(&ds)?;
    let p = super::parse_problem(&ps)?;
    let translated = super::translate(&ds, &d, &ps, &p)?;
    Ok(Loaded {
        domain: d,
        problem: p,
        translated,
    })
}

/// A plan for a PDDL problem, checked twice.
#[derive(Debug, Clone)]
pub struct Solved {
    pub solution: Solution,
    pub ipc: writer::IpcPlan,
    pub steps: u64,
    pub backtracks: u64,
    /// The planner's search alone (ms).
    pub search_ms: f64,
}

/// Why no checked plan came out.
#[derive(Debug, Clone, thiserror::Error)]
pub enum SolveError {
    #[error("no plan: {0}")]
    NoPlan(PlanFailure, f64),
    #[error("numeric fluents: {0}")]
    Finalise(FinaliseError, f64),
    #[error("checker: plan REJECTED: {0}")]
    Rejected(String, f64),
    #[error("no IPC plan: {0}")]
    Ipc(writer::IpcError, f64),
    #[error("the IPC plan fails its replay on the PDDL: {0}")]
    Replay(simulate::SimulateError, f64),
}

impl SolveError {
    /// The same error with the search time `ms`.
    fn with_ms(self, ms: f64) -> Self {
        match self {
            SolveError::NoPlan(e, _) => SolveError::NoPlan(e, ms),
            SolveError::Finalise(e, _) => SolveError::Finalise(e, ms),
            SolveError::Rejected(e, _) => SolveError::Rejected(e, ms),
            SolveError::Ipc(e, _) => SolveError::Ipc(e, ms),
            SolveError::Replay(e, _) => SolveError::Replay(e, ms),
        }
    }

    /// The search time spent (ms).
    pub fn search_ms(&self) -> f64 {
        match self {
            SolveError::NoPlan(_, t)
            | SolveError::Finalise(_, t)
            | SolveError::Rejected(_, t)
            | SolveError::Ipc(_, t)
            | SolveError::Replay(_, t) => *t,
        }
    }
}

/// Plans `l` within `budget`: the POCL searches with the forward search beside them ([`super::hybrid`]);
/// the plan is checked by the independent checker on the translation, and its IPC form replayed on the
/// PDDL.
pub fn solve(l: &Loaded, budget: Budget) -> Result<Solved, SolveError> {
    let t = &l.translated;
    let started = Instant::now();
    let mut hybrid = super::hybrid::Hybrid::new(l, budget.deadline);
    let planned = planner::solve_portfolio_with(
        t.domain.clone(),
        t.problem.clone(),
        budget,
        &mut |steps, share| hybrid.slice(steps, share),
    );
    let search_ms = started.elapsed().as_secs_f64() * 1e3;
    let planned = planned.map_err(|e| SolveError::NoPlan(e, search_ms))?;
    let (solution, ipc) = check(l, &planned).map_err(|e| e.with_ms(search_ms))?;
    Ok(Solved {
        solution,
        ipc,
        steps: planned.steps,
        backtracks: planned.backtracks,
        search_ms,
    })
}

/// The solution of a plan, accepted by the independent checker, and its IPC plan, replayed on the PDDL
/// (the times in the errors are 0: the caller sets them).
pub(super) fn check(
    l: &Loaded,
    planned: &planner::Planned,
) -> Result<(Solution, writer::IpcPlan), SolveError> {
    let t = &l.translated;
    let mut solution = planned.plan.to_solution(&HashMap::new());
    // Accesses to numeric fluents put in one order, ε apart, and state-dependent durations fixed.
    finalise::finalise(&t.domain, &t.fluents, &mut solution)
        .map_err(|e| SolveError::Finalise(e, 0.0))?;
    let checked = validate(&t.domain, &t.problem, &solution)
        .map_err(|r| SolveError::Rejected(r.to_string(), 0.0))?;
    let ipc = writer::ipc_plan(&t.domain, &t.problem, &solution, &checked)
        .map_err(|e| SolveError::Ipc(e, 0.0))?;
    let mut ipc = ipc;
    simulate::exact_durations(&l.domain, &l.problem, &mut ipc.steps);
    simulate::simulate(&l.domain, &l.problem, &ipc.steps)
        .map_err(|e| SolveError::Replay(e, 0.0))?;
    Ok((solution, ipc))
}
