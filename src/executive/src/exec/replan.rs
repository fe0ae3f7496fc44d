//! Complete replanning (seed 1 §3.6).
//!
//! Execution is aborted; the planning problem P_ti is extracted from P_ts: the state S_ti = S_ts (the last
//! values and the resource levels), the goals G_ti whose temporal constraints are still coherent with the
//! current time, the constraints on them (origin, horizon), their open conditions. A flexible timepoint
//! T_end, the end of the planning process, is constrained after t_i and before the horizon, and every goal and
//! new timepoint after it ("planning to plan"). Planning goes one step at a time until a solution, a dead end,
//! or the time limit `l = T_end_ub − d` (d: the slack); it goes on past l only while the search is
//! backtracking and l increases. Without a solution a goal is rejected — the lowest priority, then the least
//! flexibility `st_ub − d_achiev`, then the newest — S_t is refreshed (the paper's suggested improvement),
//! and a new attempt starts. Every attempt is bounded in steps as well (a stepped simulator's clock does not
//! move while it plans), each half the previous one's ([`attempt_cap`]), so a whole replanning — and the
//! memory its searches take — is bounded too. Before the first attempt, a goal that cannot be achieved even
//! alone (src/temporal/src/planner/reachability.rs) is rejected at once with why, instead of costing the goals after it
//! an attempt each. A new goal whose insertion attempt is in progress is not in the plan yet
//! (src/executive/src/exec/goal_insertion.rs): it never competes with the goals held.

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::executive::{Executive, Fate};
use super::outcome::{AbortReason, FateReason};
pub use super::replan_record::{
    AttemptEnd, AttemptRecord, ReplanOutcome, ReplanRecord, ReplanRejection,
};
use super::trace::TraceEvent;
use mavtempo_temporal::model::{Fact, GoalId, Problem, Time};
use mavtempo_temporal::plan::{PartialPlan, PlanError, TimeFloor};
use mavtempo_temporal::planner::reachability::{single_goal_searches_until, STEPS_PER_GOAL};
use mavtempo_temporal::planner::{Search, StepOutcome};
use mavtempo_temporal::stn::Timepoint;

/// P_ti and its T_end.
pub struct Extracted {
    pub plan: PartialPlan,
    pub t_end: Timepoint,
    /// Goals dropped because their constraints are not coherent with the current time.
    pub incoherent: Vec<GoalId>,
}

/// The problem of P_ti: S_t as the initial state, the resource levels at t, the timed facts still to come.
pub fn extract_problem(ex: &Executive, now: Time) -> Problem {
    let mut p: Problem = (**ex.plan.problem()).clone();
    for f in p.initial.iter_mut() {
        if let Some(v) = ex.state.get(&(f.attr, f.args.clone())) {
            f.value = v;
        }
    }
    for ((attr, args), (_, value)) in &ex.state.values {
        if !p.initial.iter().any(|f| f.attr == *attr && &f.args == args) {
            p.initial.push(Fact {
                attr: *attr,
                args: args.clone(),
                value: *value,
            });
        }
    }
    p.exogenous.retain(|tf| tf.at > now);
    ex.ledger.hand_to_planner(&mut p);
    p
}

/// P_ti: the extracted problem's root plan, without the goals in `dropped` or already achieved, with T_end.
pub fn extract(ex: &Executive, now: Time, dropped: &[GoalId]) -> Result<Extracted, PlanError> {
    let problem = Arc::new(extract_problem(ex, now));
    let mut plan = PartialPlan::new(ex.plan.domain().clone(), problem.clone())?;
    let t_end = plan.add_planning_end(now)?;
    let mut incoherent = Vec::new();
    for pg in plan.goals().to_vec() {
        let g = &problem.goals[pg.goal.index()];
        let settled = ex
            .goals
            .fate(pg.goal)
            .is_some_and(|f| f.fate != Fate::Pending);
        if settled || dropped.contains(&pg.goal) {
            plan.remove_goal(pg.goal);
            continue;
        }
        // Coherent with the current time: st^g can still be at or after now + d_achiev.
        let level = plan.save();
        let ok = plan
            .not_before(pg.st, now.saturating_add(g.achieve))
            .and_then(|_| plan.order(t_end, pg.st));
        if ok.is_err() {
            plan.restore(level);
            plan.remove_goal(pg.goal);
            incoherent.push(pg.goal);
        }
    }
    plan.set_time_floor(TimeFloor::After(t_end));
    Ok(Extracted {
        plan,
        t_end,
        incoherent,
    })
}

/// The goal to abandon: the lowest priority, then the least flexibility `st_ub − d_achiev`, then the
/// newest (the goals held longest are kept).
pub fn goal_to_reject(plan: &PartialPlan) -> Option<GoalId> {
    plan.goals()
        .iter()
        .filter(|g| g.active)
        .min_by_key(|g| {
            let goal = &plan.problem().goals[g.goal.index()];
            (
                goal.priority,
                plan.latest(g.st) - goal.achieve,
                std::cmp::Reverse(g.goal),
            )
        })
        .map(|g| g.goal)
}

/// The step cap of attempt `attempt` (from 1) of a complete replanning whose first attempt may take
/// `first`: half the previous attempt's, never under a sixteenth of the first. Each attempt has one goal
/// fewer, so it needs less; the whole replanning stays within about `2·first` steps (plus `first/16` per
/// attempt past the fifth), and its memory with it (the search grows with its steps).
pub fn attempt_cap(first: u64, attempt: usize) -> u64 {
    let halvings = u32::try_from(attempt.saturating_sub(1)).unwrap_or(u32::MAX);
    first
        .checked_shr(halvings)
        .unwrap_or(0)
        .max(first / 16)
        .max(1)
}

/// §3.6: plans one step at a time until a solution, a dead end, or the time limit `l = T_end_ub − d`
/// (re-read after each step: inserting timepoints lowers T_end_ub). Once `now() ≥ l`, planning stops unless
/// the next step is a backtrack and that step raises l (backtracking can relax T_end); a next step that
/// merely finds the current node flawless is taken too (it does no planning). `max_steps` bounds the attempt
/// whatever the clock does.
pub fn plan_until_limit(
    search: &mut Search,
    t_end: Timepoint,
    slack: Time,
    max_steps: u64,
    clock: &dyn super::clock::Clock,
) -> AttemptEnd {
    let bounds = AttemptBounds {
        max_steps,
        wall: None,
        max_actions: usize::MAX,
    };
    plan_within(search, t_end, slack, bounds, clock)
}

/// What bounds a replanning attempt besides the time limit l: steps, wall time, and the plan's size (its
/// memory), whatever a step costs.
#[derive(Clone, Copy)]
pub struct AttemptBounds<'a> {
    pub max_steps: u64,
    /// The wall-time end and the (companion's) clock it is read on.
    pub wall: Option<(Time, &'a dyn super::clock::Clock)>,
    pub max_actions: usize,
}

/// [`plan_until_limit`] within `bounds`.
pub fn plan_within(
    search: &mut Search,
    t_end: Timepoint,
    slack: Time,
    bounds: AttemptBounds<'_>,
    clock: &dyn super::clock::Clock,
) -> AttemptEnd {
    let limit = |s: &Search| s.plan().latest(t_end).saturating_sub(slack);
    loop {
        if search.steps() >= bounds.max_steps {
            return AttemptEnd::StepCap;
        }
        if bounds.wall.is_some_and(|(end, wall)| wall.now() >= end) {
            return AttemptEnd::WallBudget;
        }
        if search.plan().num_actions() >= bounds.max_actions {
            return AttemptEnd::SizeCap;
        }
        let l = limit(search);
        let past = clock.now() >= l;
        if past && !search.next_is_solution() && !search.next_is_backtrack() {
            return AttemptEnd::TimeLimit;
        }
        match search.step() {
            StepOutcome::Solved => return AttemptEnd::Solved,
            StepOutcome::Failed(_) => return AttemptEnd::DeadEnd,
            StepOutcome::Progress => {}
        }
        if past && limit(search) <= l {
            return AttemptEnd::TimeLimit;
        }
    }
}

/// How a replanning ended.
#[derive(Debug)]
pub enum ReplanResult {
    Plan(PartialPlan),
    /// Every goal was rejected (or none was left).
    NoGoals(PartialPlan),
    Error(String),
}

/// The names of the active goals of `plan`.
fn active_goal_names(plan: &PartialPlan) -> Vec<String> {
    active_goals(plan)
        .into_iter()
        .filter_map(|g| plan.problem().goals.get(g.index()))
        .map(|g| g.name.clone())
        .collect()
}

/// A plan found for one goal alone, kept while its goal is not rejected: what a failed replanning can
/// still adopt rather than lose every goal.
struct SoloPlans(Vec<(GoalId, PartialPlan)>);

/// The active goals of `plan`.
fn active_goals(plan: &PartialPlan) -> Vec<GoalId> {
    plan.goals()
        .iter()
        .filter(|g| g.active)
        .map(|g| g.goal)
        .collect()
}

impl SoloPlans {
    /// Whether a plan was found for one of `goals` alone.
    fn has(&self, goals: &[GoalId]) -> bool {
        self.0.iter().any(|(g, _)| goals.contains(g))
    }

    /// The plan of the goal kept first by the rejection order (the highest priority, then the most
    /// flexibility, then the oldest) among those not dropped.
    fn best(&self, dropped: &[GoalId]) -> Option<(GoalId, PartialPlan)> {
        self.0
            .iter()
            .filter(|(g, _)| !dropped.contains(g))
            .max_by_key(|(g, p)| {
                let goal = &p.problem().goals[g.index()];
                let st = p.goals().iter().find(|pg| pg.goal == *g).map(|pg| pg.st);
                (
                    goal.priority,
                    st.map_or(0, |st| p.latest(st) - goal.achieve),
                    std::cmp::Reverse(*g),
                )
            })
            .map(|(g, p)| (*g, p.clone()))
    }
}

impl Executive {
    /// Complete replanning at the clock's time; `refresh` updates S_t between attempts (vehicle levels). Every
    /// attempt, the goals it kept and rejected are traced and kept in [`Executive::replannings`].
    pub fn replan(
        &mut self,
        clock: &dyn super::clock::Clock,
        refresh: &mut dyn FnMut(&mut Executive),
    ) -> ReplanResult {
        let started = clock.now();
        let abort = self
            .abort
            .reason()
            .cloned()
            .unwrap_or(AbortReason::Unstated);
        let pending = self.pending_goals();
        let mut attempts = Vec::new();
        let mut steps = 0;
        let result = self.replan_attempts(clock, refresh, &mut attempts, &mut steps);
        let rejected: Vec<ReplanRejection> = pending
            .iter()
            .filter_map(|&g| self.goals.fate(g))
            .filter(|f| f.fate == Fate::Rejected)
            .filter_map(|f| {
                Some(ReplanRejection {
                    goal: f.name.clone(),
                    reason: f.reason.clone()?,
                })
            })
            .collect();
        let (outcome, kept, error) = match &result {
            ReplanResult::Plan(p) => (ReplanOutcome::NewPlan, active_goal_names(p), None),
            ReplanResult::NoGoals(_) => (ReplanOutcome::NoGoals, Vec::new(), None),
            ReplanResult::Error(e) => (ReplanOutcome::Error, Vec::new(), Some(e.clone())),
        };
        self.trace(TraceEvent::ReplanDone {
            outcome,
            attempts: attempts.len() as u32,
            steps,
            kept: kept.clone(),
            rejected: rejected.iter().map(|r| r.goal.clone()).collect(),
        });
        if let Some(e) = &error {
            tracing::warn!("complete replanning: {e}");
        }
        self.journal.replanned(ReplanRecord {
            time_ms: started,
            end_ms: clock.now(),
            abort,
            attempts,
            steps,
            outcome,
            error,
            kept,
            rejected,
        });
        result
    }

    /// Traces an attempt and keeps its record.
    fn attempt_done(&mut self, attempts: &mut Vec<AttemptRecord>, a: AttemptRecord) {
        self.trace(TraceEvent::Replan(a.clone()));
        attempts.push(a);
    }

    /// The attempts of [`Executive::replan`]: one goal rejected after each failed attempt (the lowest
    /// priority, then the least flexibility), all of them within `2 · replan_max_steps` steps; when that
    /// budget is spent with goals left, the plan found for the best of them alone is adopted, if any.
    fn replan_attempts(
        &mut self,
        clock: &dyn super::clock::Clock,
        refresh: &mut dyn FnMut(&mut Executive),
        attempts: &mut Vec<AttemptRecord>,
        steps: &mut u64,
    ) -> ReplanResult {
        self.journal.replanning();
        let wall = self.wall.clone();
        let wall_end = wall
            .now()
            .saturating_add(self.cfg.replan_max_wall_ms.min(i64::MAX as u64) as Time);
        let mut dropped: Vec<GoalId> = Vec::new();
        let first_cap = self.replan_step_cap();
        let budget = first_cap.saturating_mul(2);
        let slack = self.cfg.replan_slack_ms;
        let mut solo = SoloPlans(Vec::new());
        // Seed 1 §3.6: after a failed attempt P_ti is extracted again; goals made inconsistent with the
        // current time are rejected, and only if there are none is one goal abandoned.
        let mut abandon: Option<(AttemptEnd, u64)> = None;
        for attempt in 1.. {
            let t = clock.now();
            if t >= self.plan.horizon() {
                // Nothing can be planned past the mission's end: what is left is settled here.
                for g in self.pending_goals() {
                    self.reject_goal(g, FateReason::HorizonPassed);
                }
                let plan = self.plan.clone();
                return ReplanResult::NoGoals(plan);
            }
            self.state.refresh(&self.plan, t);
            let ext = match extract(self, t, &dropped) {
                Ok(e) => e,
                Err(e) => return ReplanResult::Error(e.to_string()),
            };
            for &g in &ext.incoherent {
                let goal = &self.plan.problem().goals[g.index()];
                let reason = FateReason::WindowPassed {
                    now_ms: t,
                    achieve_ms: goal.achieve,
                    window: goal.start_window.to_string(),
                };
                self.reject_goal(g, reason);
            }
            dropped.extend(ext.incoherent.iter().copied());
            let mut ext = ext;
            if let Some((end, steps)) = abandon.take() {
                if ext.incoherent.is_empty() {
                    if let Some(g) = goal_to_reject(&ext.plan) {
                        let reason = FateReason::Abandoned {
                            abort: self
                                .abort
                                .reason()
                                .cloned()
                                .unwrap_or(AbortReason::Unstated),
                            end,
                            steps,
                        };
                        self.reject_goal(g, reason);
                        ext.plan.remove_goal(g);
                        dropped.push(g);
                    }
                }
            }
            if attempt == 1 {
                tracing::debug!(
                    state = ?ext.plan.problem().initial.iter().map(|f| ext.plan.problem().fact_string(ext.plan.domain(), f)).collect::<Vec<_>>(),
                    levels = ?ext.plan.problem().resources.iter().map(|r| r.level).collect::<Vec<_>>(),
                    "P_ti extracted"
                );
                // A goal no plan achieves even alone is rejected at once, with why, rather than costing
                // every goal after it an attempt; a plan found for a goal alone is kept as a fallback.
                // The planner's bound is an `Instant`: the wall time left, from the companion's clock.
                let left = Duration::from_millis(wall_end.saturating_sub(wall.now()).max(0) as u64);
                let singles = single_goal_searches_until(
                    &ext.plan,
                    STEPS_PER_GOAL,
                    false,
                    Some(Instant::now() + left),
                );
                *steps += singles.steps;
                for u in singles.unreachable {
                    let reason = FateReason::Unreachable {
                        name: u.name.clone(),
                        why: u.reason.clone(),
                    };
                    self.reject_goal(u.goal, reason);
                    ext.plan.remove_goal(u.goal);
                    dropped.push(u.goal);
                }
                solo = SoloPlans(singles.solved);
            }
            let t_end = ext.t_end;
            let goals = active_goal_names(&ext.plan);
            if goals.is_empty() {
                return ReplanResult::NoGoals(ext.plan);
            }
            let spent = *steps;
            let max_steps = attempt_cap(first_cap, attempt).min(budget.saturating_sub(spent));
            if max_steps == 0 {
                let reason = FateReason::ReplanBudgetSpent {
                    abort: self
                        .abort
                        .reason()
                        .cloned()
                        .unwrap_or(AbortReason::Unstated),
                    steps: spent,
                };
                return self.fall_back(&solo, &mut dropped, t_end, reason, clock, ext.plan);
            }
            let alone = goals.len() == 1;
            let mut search = Search::new(ext.plan).bounded_regress();
            // Half of the wall time left (the last goal gets all of it): later attempts keep some.
            let now = wall.now();
            let left = wall_end.saturating_sub(now).max(0);
            let bounds = AttemptBounds {
                max_steps,
                wall: Some((now + if alone { left } else { left / 2 }, &*wall)),
                max_actions: self.cfg.plan_max_actions,
            };
            let end = plan_within(&mut search, t_end, slack, bounds, clock);
            *steps += search.steps();
            let mut record = AttemptRecord {
                attempt: attempt as u32,
                goals,
                steps: search.steps(),
                end,
                not_adopted: None,
            };
            let mut solution = (end == AttemptEnd::Solved).then(|| search.plan().clone());
            if let Some(b) = solution.as_mut().and_then(|p| self.banned_in_plan(p)) {
                let what = self.action_text_in(search.plan(), b.action);
                record.not_adopted = Some(format!("it needs {what} ({})", b.reason));
                self.attempt_done(attempts, record);
                let reason = FateReason::NeedsBanned {
                    action: what.clone(),
                    ban: b.reason.clone(),
                };
                let goals = if b.goals.is_empty() {
                    goal_to_reject(search.plan()).into_iter().collect()
                } else {
                    b.goals
                };
                for g in goals {
                    self.reject_goal(g, reason.clone());
                    dropped.push(g);
                }
                refresh(self);
                continue;
            }
            if let Some(mut plan) = solution {
                plan.set_time_floor(TimeFloor::None);
                // T_end happens now: planning is over, the new plan's first timepoints may follow it.
                if plan.execute_at(t_end, clock.now()).is_ok() {
                    self.attempt_done(attempts, record);
                    return ReplanResult::Plan(plan);
                }
                record.not_adopted = Some("found too late (after T_end)".into());
            }
            self.attempt_done(attempts, record);
            if alone && end != AttemptEnd::DeadEnd && solo.has(&active_goals(search.plan())) {
                // The last goal's search ran out without proving it impossible, and a plan was found
                // for it alone at the first attempt: that plan is kept.
                let reason = FateReason::NoPlanFound {
                    end,
                    steps: search.steps(),
                };
                return self.fall_back(
                    &solo,
                    &mut dropped,
                    t_end,
                    reason,
                    clock,
                    search.into_plan(),
                );
            }
            if goal_to_reject(search.plan()).is_none() {
                return ReplanResult::NoGoals(search.into_plan());
            }
            abandon = Some((end, search.steps()));
            refresh(self);
        }
        ReplanResult::Error("unreachable".into())
    }

    /// The attempts cannot go on (the replanning's step budget is spent, or the last goal's attempt failed
    /// without proving it impossible): the plan found at the first attempt for the best goal left alone is
    /// adopted and the other goals left are rejected with `reason`; without such a plan, every goal left is.
    fn fall_back(
        &mut self,
        solo: &SoloPlans,
        dropped: &mut Vec<GoalId>,
        t_end: Timepoint,
        reason: FateReason,
        clock: &dyn super::clock::Clock,
        left: PartialPlan,
    ) -> ReplanResult {
        let kept = solo.best(dropped).and_then(|(g, mut plan)| {
            plan.set_time_floor(TimeFloor::None);
            plan.execute_at(t_end, clock.now())
                .is_ok()
                .then_some((g, plan))
        });
        let reason = match &kept {
            Some((g, _)) => FateReason::OtherKept {
                reason: Box::new(reason),
                kept: self.plan.problem().goals[g.index()].name.clone(),
            },
            None => reason,
        };
        for g in left.goals().iter().filter(|g| g.active).map(|g| g.goal) {
            if kept.as_ref().is_none_or(|(k, _)| *k != g) {
                self.reject_goal(g, reason.clone());
                dropped.push(g);
            }
        }
        match kept {
            Some((_, plan)) => ReplanResult::Plan(plan),
            None => ReplanResult::NoGoals(left),
        }
    }

    /// The hard step cap of the first replanning attempt: `replan_max_steps`, and with deterministic step
    /// budgets the steps of 40 cycles (a manual clock does not move while planning, so l is never reached).
    fn replan_step_cap(&self) -> u64 {
        let cap = self.cfg.replan_max_steps;
        self.cfg
            .repair_max_steps
            .map_or(cap, |n| n.saturating_mul(40).min(cap))
    }

    /// Adopts a plan from complete replanning: running actions are forgotten (P_ts has none).
    pub fn adopt(&mut self, plan: PartialPlan) {
        self.plan.replace(plan);
        // Reports of the old plan's actions are ignored from now on (their ids mean nothing in the new plan).
        self.dispatched.forget_plan();
        self.repair.reset();
        self.abort.clear();
        self.hierarchy = super::abstraction::Hierarchy::new(self.plan.domain());
        self.check_reserves();
    }
}
