//! A new goal rejected for a reason that may stop holding is tried again (issue 31, "rejections are
//! true"): its insertion attempt was cut by its budget (the cycles' repair share was spent, which proves
//! nothing about the goal) or could not be rooted because the plan was not executable at that instant.
//! Such a goal is parked; it is inserted again once the situation changed — an action of the plan ended,
//! or the plan has none left (the vehicle would sit idle with the goal rejected), or a minute of mission
//! time passed — at most
//! [`MAX_TRIES`] times, the k-th attempt with k times the cycles of the first. Its first rejection stays in
//! the trace; its fate is the last attempt's.

use super::executive::Executive;
use super::insertion::Insertion;
pub use super::insertion::Parked;
use super::outcome::FateReason;
use super::trace::TraceEvent;
use mavtempo_temporal::model::Time;

/// Insertion attempts of one goal, the first one included.
pub const MAX_TRIES: u32 = 3;

/// Mission time after which a parked goal is tried again even while actions run, ms.
pub const RETRY_AFTER_MS: Time = 60_000;

/// Whether a rejection says only that the attempt ran out, not that the goal cannot be had.
pub fn may_stop_holding(reason: &FateReason) -> bool {
    matches!(
        reason,
        FateReason::InsertionTimedOut { .. } | FateReason::NotExecutable { .. }
    )
}

impl Executive {
    /// Parks a goal whose insertion was rejected for `reason`, when trying again may succeed.
    pub(crate) fn park(&mut self, insertion: Insertion, reason: &FateReason, now: Time) {
        if may_stop_holding(reason) && insertion.tries < MAX_TRIES {
            let actions = self.plan.live_actions().count();
            self.goals.park(Parked {
                insertion,
                at: now,
                actions,
            });
        }
    }

    /// With no insertion in progress: the first parked goal whose situation changed is queued again.
    pub(crate) fn unpark(&mut self, now: Time) {
        if self.goals.is_inserting() || !self.goals.has_parked() || self.operator.is_held() {
            return;
        }
        let actions = self.plan.live_actions().count();
        let Some(p) = self
            .goals
            .unpark_first(|p| actions != p.actions || actions == 0 || now - p.at >= RETRY_AFTER_MS)
        else {
            return;
        };
        let mut ins = p.insertion.again();
        ins.tries += 1;
        let name = ins.goal.name.clone();
        // Its refusal is withdrawn: the goal is pending again until this attempt's verdict.
        self.goals.withdraw_refusal(&name);
        tracing::info!(goal = %name, tries = ins.tries, "rejected goal tried again");
        self.trace(TraceEvent::GoalReceived { goal: name });
        self.goals.requeue(ins);
    }

    /// Goals parked for another attempt.
    pub fn parked_goals(&self) -> impl Iterator<Item = &str> {
        self.goals.parked().map(|p| p.insertion.goal.name.as_str())
    }
}
