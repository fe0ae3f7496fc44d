//! New goals on their way into the plan: one waiting for, or in, its insertion attempt beside *ExecutingPlan*
//! ([`super::goal_insertion`]), and one rejected for a reason that may stop holding, waiting to be tried
//! again ([`super::goal_retry`]). Data only: those files hold the rules.

use mavtempo_temporal::model::{Goal, GoalId, Time};
use mavtempo_temporal::planner::Search;

/// A requested goal waiting for, or in, its insertion attempt.
pub struct Insertion {
    pub goal: Goal,
    /// The upload it came in (its number) and its index there: where the verdict goes.
    pub reply: (u64, usize),
    /// The attempt's search, rooted at a copy of *ExecutingPlan* with the goal; `None` before the attempt
    /// starts and when *ExecutingPlan* changed under it.
    pub(super) search: Option<Search>,
    /// Planning steps spent, over all the attempt's cycles.
    pub steps: u64,
    /// Cycles in which the attempt was developed.
    pub cycles: u32,
    /// The goal's id in the attempt's plan.
    pub(super) id: Option<GoalId>,
    /// Where its end is told once accepted.
    pub(super) watch: Option<mavtempo_vehicle::goals::GoalWatch>,
    /// Insertion attempts so far, this one included (src/executive/src/exec/goal_retry.rs).
    pub tries: u32,
}

impl Insertion {
    pub(super) fn started(&self) -> bool {
        self.search.is_some() || self.cycles > 0
    }

    /// The same goal, request and watch, for a new attempt from scratch.
    pub(crate) fn again(self) -> Insertion {
        Insertion {
            search: None,
            steps: 0,
            cycles: 0,
            id: None,
            ..self
        }
    }
}

/// A rejected goal waiting to be tried again.
pub struct Parked {
    pub insertion: Insertion,
    /// When it was rejected, ms since origin.
    pub at: Time,
    /// The plan's actions then.
    pub(super) actions: usize,
}
