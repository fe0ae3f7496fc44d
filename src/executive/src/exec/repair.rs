//! Plan repair across cycles (seed 1 §3.2 problems 1 and 2, §3.4).
//!
//! The root of the search tree is *ExecutingPlan*, partially invalidated; the tree is developed by the
//! planner's ordered depth-first search, one step at a time, for at most μ·ts of mission time per cycle (the
//! executive's clock, so a vehicle at N× gets μ·ts/N of wall time), and never more than a hard step cap (a
//! stepped simulator's clock does not move while the cycle runs), each new timepoint
//! constrained after the end of the current cycle. Each node is labelled when its plan is executable
//! (Definition 5); at the deadline, the last labelled node becomes *ExecutingPlan*. If nothing changed
//! meanwhile (no message, no timepoint executed), the tree is kept and developed in the next cycle;
//! otherwise a new tree is rooted at the new *ExecutingPlan*.

use super::executive::Executive;
use super::outcome::AbortReason;
use super::p_t::classify;
pub use super::repair_tree::{NotExecutable, Repair, RepairOutcome};
use super::trace::{RepairWork, TraceEvent};
use mavtempo_temporal::model::Time;
use mavtempo_temporal::plan::{PartialPlan, TimeFloor};
use mavtempo_temporal::planner::{FailReason, Search, StepOutcome};

/// Timepoints not executed yet cannot happen before `now`: the search must not move them into the past
/// (e.g. a goal supported again by an effect that was executed before now).
fn not_before(
    plan: &mut PartialPlan,
    now: Time,
) -> Result<(), mavtempo_temporal::stn::Inconsistent> {
    let mut tps: Vec<_> = plan
        .live_actions()
        .flat_map(|a| plan.action(a).tps.clone())
        .collect();
    tps.extend(
        plan.goals()
            .iter()
            .filter(|g| g.active)
            .flat_map(|g| [g.st, g.et]),
    );
    for tp in tps {
        if !plan.is_executed(tp) && plan.earliest(tp) < now {
            plan.not_before(tp, now)?;
        }
    }
    Ok(())
}

impl Executive {
    /// The root of a repair tree: *ExecutingPlan* with its timepoints not executed yet no earlier than
    /// `now + 1`, and new timepoints after the end of this cycle (§3.4).
    pub fn repair_root(&self, now: Time) -> Result<PartialPlan, NotExecutable> {
        let mut root = self.plan.clone();
        not_before(&mut root, now + 1).map_err(|source| NotExecutable {
            now_ms: now,
            source,
        })?;
        root.set_time_floor(TimeFloor::At(self.cycle_end(now)));
        Ok(root)
    }

    /// This cycle's repair budget: μ·n steps with deterministic budgets, else until μ·ts of mission time on
    /// `clock`; never more than the hard cap of steps per cycle.
    pub fn cycle_budget(&self, clock: &dyn super::clock::Clock) -> (u64, Option<Time>) {
        let cap = self.cfg.repair_cycle_max_steps;
        match self.cfg.repair_max_steps {
            Some(n) => (
                (((n as f64) * self.cfg.repair_share).ceil() as u64).min(cap),
                None,
            ),
            None => (
                cap,
                Some(
                    clock
                        .now()
                        .saturating_add(self.cfg.repair_budget_ms().max(0)),
                ),
            ),
        }
    }

    /// This cycle's wall-time bound (`cycle_max_wall_ms` from now on the executive's wall clock), whatever
    /// the mission clock does.
    pub fn cycle_wall_deadline(&self) -> Time {
        let max = self.cfg.cycle_max_wall_ms.min(i64::MAX as u64) as Time;
        self.wall.now().saturating_add(max)
    }

    /// The plan repair part of a cycle at `now`; `clock` is the executive's clock (mission time, ms since
    /// the plan's origin), read to stop at `μ·ts` after the phase starts.
    pub fn repair_phase(&mut self, now: Time, clock: &dyn super::clock::Clock) -> RepairOutcome {
        let running = classify(&self.plan, now).running;
        if self.repair.tree.is_none() && !self.repair.requested && self.plan.is_flawless() {
            // Nothing to repair: the cycle's repair share goes to a new goal's insertion, if any.
            return self.insertion_phase(now, clock);
        }
        self.repair.requested = false;
        // `changed` covers everything since the tree was last developed, the previous cycle's act part
        // included (a timepoint it executed is not in the tree's nodes).
        let changed = self.plan.take_repair_stale();
        if self.repair.tree.is_none() || changed {
            let root = match self.repair_root(now) {
                Ok(r) => r,
                Err(e) => {
                    let reason = AbortReason::from(e);
                    self.abort_with(reason.clone());
                    return RepairOutcome::Failed(reason);
                }
            };
            // Repair is local (a few choices around the broken links) and its tree is rebuilt whenever the
            // plan moves on: chronological depth-first, as in seed 1 — discrepancy iterations would
            // redo the tree from its root every cycle. A repair that thrashes is cut off by its episode
            // budget and replaced by a complete replanning, which searches by discrepancies.
            self.repair.tree = Some(Repair {
                search: Search::depth_first(root).bounded_regress(),
                labelled: None,
            });
        }
        let (max_steps, deadline) = self.cycle_budget(clock);
        let wall = self.cycle_wall_deadline();
        let wall_clock = self.wall.clone();
        // ExecutingPlan is about to change: an insertion rooted at it starts again.
        self.plan.restart_insertion();
        let Some(rep) = self.repair.tree.as_mut() else {
            return RepairOutcome::Idle;
        };
        let first = rep.search.steps();
        let outcome = loop {
            if rep.search.steps() - first >= max_steps
                || deadline.is_some_and(|d| clock.now() >= d)
                || wall_clock.now() >= wall
            {
                break None;
            }
            match rep.search.step() {
                StepOutcome::Progress => {
                    if rep.search.executable(&running) {
                        rep.labelled = Some(rep.search.plan().clone());
                    }
                }
                other => break Some(other),
            }
        };
        let steps = rep.search.steps() - first;
        self.journal.repair_steps(steps);
        self.repair.episode_steps += steps;
        let finished = match &outcome {
            Some(StepOutcome::Solved) => true,
            Some(StepOutcome::Failed(r)) => !matches!(r, FailReason::Deadline { .. }),
            _ => false,
        };
        if finished {
            self.repair.episode_steps = 0;
        } else if self.repair.episode_steps > self.cfg.repair_episode_max_steps {
            let reason = AbortReason::RepairDiverged {
                steps: self.repair.episode_steps,
            };
            self.repair.tree = None;
            self.repair.episode_steps = 0;
            self.abort_with(reason.clone());
            return RepairOutcome::Failed(reason);
        }
        match outcome {
            Some(StepOutcome::Solved) => {
                let Some(rep) = self.repair.tree.take() else {
                    return RepairOutcome::Idle;
                };
                let total = rep.search.steps();
                let mut plan = rep.search.into_plan();
                plan.set_time_floor(TimeFloor::None);
                self.plan.replace(plan);
                self.journal.repaired();
                self.trace(TraceEvent::RepairDone { steps: total });
                RepairOutcome::Solved
            }
            Some(StepOutcome::Failed(r)) if !matches!(r, FailReason::Deadline { .. }) => {
                // The search's last dead end says why, before the search is dropped.
                let dead_end = self
                    .repair
                    .tree
                    .take()
                    .and_then(|rep| rep.search.last_rejection().map(str::to_string));
                let flaws = self.plan.flaw_texts();
                tracing::debug!(?flaws, "plan repair failed on the executing plan's flaws");
                let reason = AbortReason::RepairFailed {
                    failure: r.to_string(),
                    dead_end,
                };
                self.abort_with(reason.clone());
                RepairOutcome::Failed(reason)
            }
            _ => {
                if let Some(p) = self.repair.tree.as_mut().and_then(|r| r.labelled.take()) {
                    self.plan.replace(p);
                }
                self.trace(TraceEvent::RepairStep {
                    steps,
                    outcome: RepairWork::Repairing,
                });
                RepairOutcome::InProgress
            }
        }
    }
}
