//! `mavtempo bench cycle`: the executive's cycle time (sense + repair + act, the executive's own CPU time,
//! the vehicle excluded) on a plan of n actions, a chain of `step(a, b)` moves between two places, each
//! supported by the previous one's effect, executed against MockVehicle with the manual clock.

use std::sync::Arc;

use serde::Serialize;

use crate::exec::config::ExecConfig;
use crate::exec::cycle::CycleOutcome;
use crate::exec::executive::Executive;
use crate::lang::{parse_domain, parse_problem};
use crate::plan::PartialPlan;
use crate::vehicle::mock::Outcome;
use crate::vehicle::MockVehicle;

const DOMAIN: &str = "domain bench;
type place;
attribute AT(): place;
task step(?from: place, ?to: place) (st, et) {
    ?from != ?to;
    event(AT(): (?from, ?to), et);
    (et - st) in [1, 3];
} nonPreemptive
";

const PROBLEM: &str = "problem chain;
domain bench;
horizon 100h;
object a, b: place;
initial {
    AT() = a;
}
";

/// Cycle-time figures for one plan size.
#[derive(Clone, Debug, Serialize)]
pub struct CycleFigures {
    pub actions: usize,
    pub cycles: usize,
    pub p50_us: u64,
    pub p99_us: u64,
    pub max_us: u64,
}

/// Why a bench's plan or run could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ExecBenchError {
    /// The bench's shipped domain, problem or config does not load.
    #[error("{file}: {reason}")]
    Load { file: &'static str, reason: String },
    #[error("the bench problem has no {0}")]
    Missing(&'static str),
    #[error(transparent)]
    Plan(#[from] crate::plan::PlanError),
    #[error(transparent)]
    Binding(#[from] crate::plan::BindingConflict),
    #[error(transparent)]
    Temporal(#[from] crate::stn::Inconsistent),
    #[error("the chain plan has flaws")]
    Flawed,
    #[error("{problem} not planned: {outcome}")]
    NotPlanned {
        problem: &'static str,
        outcome: String,
    },
    #[error("aborted: {0}")]
    Aborted(crate::exec::outcome::AbortReason),
    #[error("no cycle ran")]
    NoCycle,
}

impl ExecBenchError {
    pub fn load(file: &'static str, reason: impl std::fmt::Display) -> Self {
        ExecBenchError::Load {
            file,
            reason: reason.to_string(),
        }
    }
}

/// The chain plan of `n` steps (a solution: every condition supported, steps ordered).
pub fn chain_plan(n: usize) -> Result<PartialPlan, ExecBenchError> {
    let d = parse_domain("bench.ixt", DOMAIN).map_err(|e| ExecBenchError::load("bench.ixt", e))?;
    let p = parse_problem("chain.ixt", PROBLEM, &d)
        .map_err(|e| ExecBenchError::load("chain.ixt", e))?;
    let task = d
        .task_id("step")
        .ok_or(ExecBenchError::Missing("step task"))?;
    let (a, b) = (
        p.object_id("a")
            .ok_or(ExecBenchError::Missing("object a"))?,
        p.object_id("b")
            .ok_or(ExecBenchError::Missing("object b"))?,
    );
    let mut plan = PartialPlan::new(Arc::new(d), Arc::new(p))?;
    let mut prev_event = *plan
        .events()
        .iter()
        .enumerate()
        .find(|(_, e)| e.owner == crate::plan::Owner::Initial)
        .map(|(i, _)| i)
        .as_ref()
        .ok_or(ExecBenchError::Missing("initial event"))?;
    let mut prev_end = None;
    for i in 0..n {
        let act = plan.insert_action(task)?;
        let (from, to) = if i % 2 == 0 { (a, b) } else { (b, a) };
        let vars = plan.action(act).vars.clone();
        plan.bind_var(vars[0], from)?;
        plan.bind_var(vars[1], to)?;
        if let Some(e) = prev_end {
            let st = plan.action(act).start;
            plan.order(e, st)?;
        }
        let ev = plan.action(act).events[0];
        let cond = plan
            .event(ev)
            .cond
            .ok_or(ExecBenchError::Missing("condition of a step's event"))?;
        plan.add_link(crate::plan::EventId(prev_event as u32), cond)?;
        prev_event = ev.index();
        prev_end = Some(plan.action(act).end);
    }
    if !plan.flaws().is_empty() {
        return Err(ExecBenchError::Flawed);
    }
    Ok(plan)
}

/// Runs `cycles` cycles (every 500 ms of manual time) over the chain of `n` steps.
pub fn run(n: usize, cycles: usize) -> Result<CycleFigures, ExecBenchError> {
    let plan = chain_plan(n)?;
    let cfg = ExecConfig {
        timestep_ms: 1_000,
        repair_share: 0.6,
        replan_slack_ms: 1_000,
        repair_max_steps: Some(100),
        // The chain serves no external goal: goal-driven dispatch (the default since issue 33) would defer
        // every step to its latest start; the cycle figures are of a chain run as early as it can.
        dispatch: crate::dispatch::PolicyKind::Earliest,
        ..ExecConfig::default()
    };
    let mut ex = Executive::new(plan, cfg);
    let mut v = MockVehicle::new();
    v.script("step", Outcome::nominal(2_000));
    let mut t = 0;
    for _ in 0..cycles {
        v.advance_to(t as u64);
        match ex.cycle(&mut v, t) {
            CycleOutcome::Continue { .. } => {}
            CycleOutcome::Finished => break,
            CycleOutcome::Aborted(r) => return Err(ExecBenchError::Aborted(r)),
        }
        t += 500;
    }
    let t = ex.cycles().times();
    if t.count == 0 {
        return Err(ExecBenchError::NoCycle);
    }
    Ok(CycleFigures {
        actions: n,
        cycles: t.count,
        p50_us: t.p50_us,
        p99_us: t.p99_us,
        max_us: t.max_us,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_chain_is_a_solution_and_runs_to_its_end() {
        let f = super::run(10, 200).expect("runs");
        // 10 steps of 2 s, one cycle every 500 ms: finished well before 200 cycles.
        assert!(f.cycles < 200 && f.cycles >= 40, "{f:?}");
    }
}
