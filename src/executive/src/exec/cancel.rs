//! Goals withdrawn by the ground station that uploaded them (MISSION_CLEAR_ALL, or a new list without
//! them): not in the papers, whose goals leave the plan only by complete replanning (seed 1 §3.6). A goal
//! waiting for or in its insertion attempt is dropped from the queue; a goal held in *ExecutingPlan* leaves
//! it with the actions not started yet that served only it and their causal links
//! ([`PartialPlan::withdraw_goal`]); running actions that served only it are stopped (`END i_a`, their
//! report integrated as for any interruption); the plan is then repaired (§3.4). Its fate is `cancelled`.

use super::executive::{Executive, Fate};
use super::outcome::FateReason;
use super::trace::TraceEvent;
use mavtempo_temporal::model::Time;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_vehicle::goals::GoalCancel;
use mavtempo_vehicle::GoalVerdict;

impl Executive {
    /// Withdraws the goals `cancel` names and answers with those it held or was inserting.
    pub fn cancel_goals(&mut self, cancel: GoalCancel, now: Time) {
        let mut withdrawn = Vec::new();
        for name in &cancel.names {
            if self.cancel_goal(name, &cancel.reason, now) {
                withdrawn.push(name.clone());
            }
        }
        cancel.answer(withdrawn);
    }

    /// Withdraws goal `name`; false when it is not held (already achieved, rejected, cancelled, unknown).
    pub fn cancel_goal(&mut self, name: &str, by: &str, now: Time) -> bool {
        let reason = FateReason::Cancelled { by: by.to_string() };
        if let Some(ins) = self.goals.take_insertion_named(name) {
            self.plan.restart_insertion();
            self.decide_goal(ins.reply, GoalVerdict::Cancelled(by.to_string()));
            self.never_held(name, Fate::Cancelled, reason);
            return true;
        }
        let Some(g) = self
            .goals
            .fates()
            .iter()
            .find(|(_, f)| f.name == name && f.fate == Fate::Pending)
            .map(|(&g, _)| g)
        else {
            return false;
        };
        let serving = self.plan.actions_serving_only(g);
        let (started, not_started): (Vec<_>, Vec<_>) = serving.into_iter().partition(|&a| {
            self.has_started(a) || self.plan.is_executed(self.plan.action(a).start)
        });
        self.plan.edit().withdraw_goal(g, &not_started);
        for a in started {
            self.dispatched.request_stop(a);
        }
        // The search in progress was rooted in the plan with the goal.
        self.repair.restart();
        self.trace(TraceEvent::GoalCancelled {
            goal: name.to_string(),
            reason: reason.clone(),
        });
        tracing::info!(
            goal = name,
            now,
            withdrawn = not_started.len(),
            "goal cancelled: {by}"
        );
        self.set_fate(g, Fate::Cancelled, Some(reason));
        true
    }
}

/// Whether `plan` still pursues a goal named `name` (for tests and the report).
pub fn pursues(plan: &PartialPlan, name: &str) -> bool {
    plan.goals()
        .iter()
        .any(|pg| pg.active && plan.problem().goals[pg.goal.index()].name == name)
}
