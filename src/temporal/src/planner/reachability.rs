//! Fast, explained failure: before the search, each goal is planned alone (the other goals removed from
//! the root plan) within a small step budget.
//!
//! A solution of the whole problem is a solution of each single-goal problem (more goals only add
//! conditions and constraints), so a goal whose single-goal search fails for good — its first flaw has no
//! resolver, or every branch dies — cannot be achieved with the others either, as far as this planner's
//! resolvers reach. The problem is then refused at once, naming the goal and the dead end its search met:
//! a window that closes before the target can be reached (no move ordering fits the network), energy or
//! storage beyond a reservoir's capacity, a value nothing establishes. A single-goal search that runs out
//! of its budget proves nothing: the goal is kept.

use super::{Budget, FailReason, Search, StepOutcome};
use crate::model::GoalId;
use crate::plan::PartialPlan;

/// Steps each goal's single-goal search may take: enough for a goal that needs a few actions (a move, a
/// PTU move and a picture: ~20 steps; with a recharge or a download: ~60), small against a full search.
pub const STEPS_PER_GOAL: u64 = 300;

/// A goal that no plan achieves, and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("goal {name} cannot be achieved: planned alone, {reason}")]
pub struct Unreachable {
    pub goal: GoalId,
    pub name: String,
    pub reason: String,
}

/// What planning each goal alone found: the goals no plan achieves, and a plan for each goal that its
/// single-goal search solved (a fallback for complete replanning: that goal at least can be kept).
#[derive(Clone, Debug, Default)]
pub struct SingleGoalSearches {
    pub unreachable: Vec<Unreachable>,
    pub solved: Vec<(GoalId, PartialPlan)>,
    /// Planning steps all the single-goal searches took.
    pub steps: u64,
}

/// The active goals of `root` that cannot be achieved even alone, in the order of the problem's goals.
pub fn unreachable_goals(root: &PartialPlan, steps_each: u64) -> Vec<Unreachable> {
    single_goal_searches(root, steps_each, false).unreachable
}

/// Plans each active goal of `root` alone within `steps_each` steps. With one active goal, the whole
/// search is the single-goal search: it is run only when `lone` asks for it.
pub fn single_goal_searches(root: &PartialPlan, steps_each: u64, lone: bool) -> SingleGoalSearches {
    single_goal_searches_until(root, steps_each, lone, None)
}

/// [`single_goal_searches`] that also stop at `deadline` (wall time): a search cut by it proves nothing.
pub fn single_goal_searches_until(
    root: &PartialPlan,
    steps_each: u64,
    lone: bool,
    deadline: Option<std::time::Instant>,
) -> SingleGoalSearches {
    let active: Vec<GoalId> = root
        .goals
        .iter()
        .filter(|g| g.active)
        .map(|g| g.goal)
        .collect();
    let mut out = SingleGoalSearches::default();
    if active.len() < 2 && !lone {
        return out;
    }
    for &g in &active {
        let mut alone = root.clone();
        for &other in active.iter().filter(|&&o| o != g) {
            alone.remove_goal(other);
        }
        // As the executive's own searches (the explanation must match what they can find).
        let mut search = Search::new(alone).bounded_regress();
        let outcome = search.run(Budget {
            max_steps: Some(steps_each),
            deadline,
        });
        out.steps += search.steps();
        let reason = match outcome {
            StepOutcome::Solved => {
                out.solved.push((g, search.into_plan()));
                continue;
            }
            StepOutcome::Failed(FailReason::NoResolver { flaw }) => format!(
                "no resolver for {flaw}{}",
                search
                    .last_rejection()
                    .map_or(String::new(), |r| format!(" (last rejected: {r})"))
            ),
            StepOutcome::Failed(r @ FailReason::Bounded { .. }) => format!(
                "{r}{}",
                search
                    .last_rejection()
                    .map_or(String::new(), |r| format!("; the last dead end: {r}"))
            ),
            StepOutcome::Failed(FailReason::Exhausted { steps }) => format!(
                "every way fails ({steps} steps){}",
                search
                    .last_rejection()
                    .map_or(String::new(), |r| format!("; the last dead end: {r}"))
            ),
            _ => continue,
        };
        out.unreachable.push(Unreachable {
            goal: g,
            name: root
                .problem
                .goals
                .get(g.index())
                .map_or_else(|| format!("#{}", g.index()), |goal| goal.name.clone()),
            reason,
        });
    }
    out
}
