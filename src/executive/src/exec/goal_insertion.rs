//! A new goal's bounded insertion attempt: a new goal never costs the goals already held.
//!
//! Seed 1 §3.3 puts a goal that passes the acceptance test into *ExecutingPlan* as an open condition and
//! leaves it to plan repair (§3.4); when repair fails, execution is aborted and complete replanning (§3.6)
//! drops goals by priority and flexibility — so a target that cannot be reached (a picture 50 km away) is
//! accepted at once, stops the running move, and costs every goal less flexible than itself.
//!
//! Here the insertion is an attempt beside *ExecutingPlan*: plan repair of a copy of it with the new goal
//! (the acceptance test passed on that copy), ordered depth-first as repair is in its first cycle and by
//! limited discrepancy search from its second (see `root_insertion`), given the cycle's repair
//! share (μ·ts, or μ·n steps) for at most `goal_insertion_cycles` cycles and started again from
//! *ExecutingPlan* whenever that changes (§3.2: a message integrated, a timepoint executed). *ExecutingPlan*
//! runs on untouched meanwhile. A solution becomes *ExecutingPlan* and the goal is accepted; a dead end, or
//! the cycles spent, rejects the goal with the planner's reason and the plan is the one it was before the
//! goal: no running action stopped, no goal already held considered. One attempt at a time, the highest
//! priority first (then in order of arrival); an attempt runs only in cycles with nothing else to repair,
//! so that its failure is the new goal's alone.

use super::executive::{Executive, Fate};
use super::goal_request::request;
pub use super::insertion::Insertion;
use super::outcome::FateReason;
use super::p_t::classify;
use super::repair_tree::RepairOutcome;
use super::trace::{RepairWork, TraceEvent};
use mavtempo_temporal::model::Time;
use mavtempo_temporal::plan::TimeFloor;
use mavtempo_temporal::planner::{FailReason, Search, StepOutcome};
use mavtempo_vehicle::goals::GoalBatch;
use mavtempo_vehicle::GoalVerdict;

impl Executive {
    /// An upload (or the goals requested at the start): each goal the mapping can read waits for its
    /// insertion attempt; the others are refused with the reason. The upload is answered at the end of this
    /// cycle's repair part ([`Executive::answer_goal_batches`]).
    pub fn receive_goals(&mut self, mut batch: GoalBatch) {
        let number = self.goals.next_batch_number();
        let requests = batch.goals.clone();
        for (i, g) in requests.iter().enumerate() {
            if let Some(why) = self.beyond_limits(g) {
                let reason = FateReason::BeyondLimits { why };
                batch.decide(i, GoalVerdict::Rejected(reason.to_string()));
                self.refuse(&g.name, reason);
                continue;
            }
            match self.goal_from_request(g) {
                Ok(goal) => {
                    // No plan can get there (issue 30: a figure, before any search).
                    if let Some(why) = self.trip_beyond_capacity(&goal) {
                        let reason = FateReason::BeyondLimits { why };
                        batch.decide(i, GoalVerdict::Rejected(reason.to_string()));
                        self.refuse(&g.name, reason);
                        continue;
                    }
                    self.trace(TraceEvent::GoalReceived {
                        goal: g.name.clone(),
                    });
                    self.goals.queue_insertion(Insertion {
                        goal,
                        reply: (number, i),
                        search: None,
                        steps: 0,
                        cycles: 0,
                        id: None,
                        watch: batch.watch(i),
                        tries: 1,
                    });
                }
                Err(e) => {
                    let reason = FateReason::Unmapped(e);
                    batch.decide(i, GoalVerdict::Rejected(reason.operator_text()));
                    self.refuse(&g.name, reason);
                }
            }
        }
        self.goals.add_batch(number, batch);
    }

    /// Answers the uploads not answered yet (goals still being inserted: "verdict to follow") and forgets
    /// those whose every goal has its final verdict.
    pub fn answer_goal_batches(&mut self) {
        self.goals.answer_batches();
    }

    /// The repair part of a cycle with nothing else to repair: the insertion attempt in progress, for this
    /// cycle's repair budget.
    pub fn insertion_phase(&mut self, now: Time, clock: &dyn super::clock::Clock) -> RepairOutcome {
        self.unpark(now);
        if !self.goals.is_inserting() {
            return RepairOutcome::Idle;
        }
        if let Err(reason) = self.root_insertion(now) {
            self.reject_insertion(reason, now);
            return self.next_insertion();
        }
        let (max_steps, deadline) = self.cycle_budget(clock);
        let wall = self.cycle_wall_deadline();
        let wall_clock = self.wall.clone();
        let Some(ins) = self.goals.current_mut() else {
            return RepairOutcome::Idle;
        };
        let Some(search) = ins.search.as_mut() else {
            return RepairOutcome::Idle;
        };
        let first = search.steps();
        let outcome = loop {
            if search.steps() - first >= max_steps
                || deadline.is_some_and(|d| clock.now() >= d)
                || wall_clock.now() >= wall
            {
                break None;
            }
            match search.step() {
                StepOutcome::Progress => {}
                other => break Some(other),
            }
        };
        let steps = search.steps() - first;
        ins.steps += steps;
        ins.cycles += 1;
        let (total, cycles) = (ins.steps, ins.cycles);
        // A goal tried again gets as many more cycles as it had (src/executive/src/exec/goal_retry.rs).
        let allowed = self.cfg.goal_insertion_cycles.saturating_mul(ins.tries);
        // What the search last ran into: the reason a rejection gives beside the budget.
        let dead_end = search.last_rejection().map(str::to_string);
        self.journal.insertion_steps(steps);
        match outcome {
            Some(StepOutcome::Solved) => {
                self.accept_insertion();
                RepairOutcome::Solved
            }
            Some(StepOutcome::Failed(r)) if !matches!(r, FailReason::Deadline { .. }) => {
                self.reject_insertion(
                    FateReason::InsertionFailed {
                        failure: r.to_string(),
                        dead_end,
                    },
                    now,
                );
                self.next_insertion()
            }
            _ if cycles >= allowed => {
                self.reject_insertion(
                    FateReason::InsertionTimedOut {
                        cycles,
                        steps: total,
                        dead_end,
                    },
                    now,
                );
                self.next_insertion()
            }
            _ => {
                if cycles == 1 {
                    // Re-rooted next cycle with limited discrepancy search (see `root_insertion`).
                    if let Some(ins) = self.goals.current_mut().filter(|i| i.tries == 1) {
                        ins.search = None;
                    }
                }
                self.trace(TraceEvent::RepairStep {
                    steps,
                    outcome: RepairWork::Inserting,
                });
                RepairOutcome::InProgress
            }
        }
    }

    /// After an attempt ended: the next one waits for the next cycle, which comes as soon as a repair's.
    fn next_insertion(&self) -> RepairOutcome {
        if !self.goals.is_inserting() {
            RepairOutcome::Idle
        } else {
            RepairOutcome::InProgress
        }
    }

    /// (Re)roots the attempt in progress at *ExecutingPlan*: the acceptance test of §3.3 on a copy of it.
    fn root_insertion(&mut self, now: Time) -> Result<(), FateReason> {
        let stale = self.plan.take_insertion_stale();
        let needs_root = self
            .goals
            .current()
            .is_some_and(|i| i.search.is_none() || stale);
        if !needs_root {
            return Ok(());
        }
        let mut root = self
            .repair_root(now)
            .map_err(|e| FateReason::NotExecutable {
                now_ms: e.now_ms,
                error: e.source.to_string(),
            })?;
        let running = classify(&self.plan, now).running;
        let Some(ins) = self.goals.current_mut() else {
            return Ok(());
        };
        let id =
            request(&mut root, ins.goal.clone(), now, &running).map_err(FateReason::Acceptance)?;
        ins.id = Some(id);
        // The first cycle searches as plan repair does (chronological depth-first: local, usually quick);
        // later ones with limited discrepancy search, so that one early wrong choice (e.g. where a download
        // for a fourth picture goes) does not use up the attempt's cycles.
        // A goal tried again starts with limited discrepancy search: depth-first had its chance.
        ins.search = Some(if ins.cycles == 0 && ins.tries == 1 {
            Search::depth_first(root).bounded_regress()
        } else {
            Search::new(root).bounded_regress()
        });
        Ok(())
    }

    /// The attempt in progress found a plan: it becomes *ExecutingPlan*, the goal is accepted.
    fn accept_insertion(&mut self) {
        let Some(ins) = self.goals.take_current() else {
            return;
        };
        let (Some(search), Some(id)) = (ins.search, ins.id) else {
            return;
        };
        let mut plan = search.into_plan();
        plan.set_time_floor(TimeFloor::None);
        self.plan.replace(plan);
        self.journal.repaired();
        self.goals.hold(id, &ins.goal.name, ins.watch);
        self.trace(TraceEvent::RepairDone { steps: ins.steps });
        self.trace(TraceEvent::GoalAccepted {
            goal: ins.goal.name.clone(),
        });
        self.decide_goal(ins.reply, GoalVerdict::Accepted);
        self.check_reserves();
    }

    /// The attempt in progress failed: the goal is rejected, *ExecutingPlan* was never touched.
    fn reject_insertion(&mut self, reason: FateReason, now: Time) {
        let Some(ins) = self.goals.take_current() else {
            return;
        };
        self.plan.restart_insertion();
        tracing::info!(goal = %ins.goal.name, steps = ins.steps, "new goal rejected: {reason}");
        self.decide_goal(ins.reply, GoalVerdict::Rejected(reason.operator_text()));
        self.refuse(&ins.goal.name, reason.clone());
        self.park(ins, &reason, now);
    }

    /// A requested goal that does not enter the plan: its fate and the trace say why.
    fn refuse(&mut self, name: &str, reason: FateReason) {
        self.never_held(name, Fate::Rejected, reason);
    }

    /// A requested goal that left before it entered the plan (rejected or cancelled): its fate and the
    /// trace say why.
    pub(crate) fn never_held(&mut self, name: &str, fate: Fate, reason: FateReason) {
        let goal = name.to_string();
        self.trace(match fate {
            Fate::Cancelled => TraceEvent::GoalCancelled {
                goal,
                reason: reason.clone(),
            },
            _ => TraceEvent::GoalRejected {
                goal,
                reason: reason.clone(),
            },
        });
        self.goals.never_held(name, fate, reason);
    }

    pub(crate) fn decide_goal(&mut self, (batch, i): (u64, usize), verdict: GoalVerdict) {
        self.goals.decide((batch, i), verdict);
    }
}
