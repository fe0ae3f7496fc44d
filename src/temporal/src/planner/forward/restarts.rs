//! Restarts beside the search: greedy best-first search commits early, and on some problems the first
//! commitment leads into a region without a plan that its estimate cannot see (a rover left short of
//! energy away from the sun, the relaxed plan counting a move and a message from where it stands as
//! one). Randomised restarts are the usual remedy of local and satisficing search (LPG restarts, as do
//! SAT solvers); here they run *beside* the main search, which keeps going and stays complete.
//!
//! Once the main search has evaluated [`WARM_UP`] states without a plan, one state in every
//! [`TRIAL_SHARE`] goes to a trial search whose ties are broken by a seeded shuffle; a trial that has
//! evaluated its budget without a plan is replaced by the next seed with twice the budget. Each search,
//! main or trial, is complete on its own: the first plan or proof of exhaustion from either is the
//! answer. The seeds are fixed, so a run is reproducible.

use super::search::{Forward, ForwardOutcome};
use super::GroundTask;

/// States the main search evaluates alone before trials start: most problems are solved by then.
pub const WARM_UP: u64 = 2_000;
/// One state in this many goes to the trial search once it has started.
pub const TRIAL_SHARE: u64 = 3;
/// The first trial's budget (states); each next trial gets twice its predecessor's.
pub const FIRST_TRIAL: u64 = 1_000;
/// States evaluated per turn.
const CHUNK: u64 = 16;

/// The main search and the current trial.
pub struct Restarting {
    main: Forward,
    trial: Option<Forward>,
    /// The trial's seed and budget.
    seed: u64,
    budget: u64,
    turn: u64,
    /// States evaluated by the trials replaced.
    retired: u64,
}

impl Restarting {
    pub fn new(task: GroundTask) -> Self {
        Restarting {
            main: Forward::new(task),
            trial: None,
            seed: 0,
            budget: FIRST_TRIAL / 2,
            turn: 0,
            retired: 0,
        }
    }

    /// The ground task searched.
    pub fn task(&self) -> &GroundTask {
        self.main.task()
    }

    /// States evaluated so far, by every search.
    pub fn expanded(&self) -> u64 {
        self.main.expanded() + self.trial.as_ref().map_or(0, |t| t.expanded()) + self.retired
    }

    /// Evaluates at most about `max_expansions` states.
    pub fn run(&mut self, max_expansions: u64) -> ForwardOutcome {
        let start = self.expanded();
        while self.expanded() - start < max_expansions {
            let left = max_expansions - (self.expanded() - start);
            let step = CHUNK.min(left);
            self.turn += 1;
            let trial_turn =
                self.main.expanded() >= WARM_UP && self.turn.is_multiple_of(TRIAL_SHARE);
            let out = if trial_turn {
                self.trial_run(step)
            } else {
                self.main.run(step)
            };
            if out != ForwardOutcome::Paused {
                return out;
            }
        }
        ForwardOutcome::Paused
    }

    fn trial_run(&mut self, step: u64) -> ForwardOutcome {
        let spent = self
            .trial
            .as_ref()
            .is_some_and(|t| t.expanded() >= self.budget);
        if self.trial.is_none() || spent {
            self.retired += self.trial.take().map_or(0, |t| t.expanded());
            self.seed += 1;
            self.budget = self.budget.saturating_mul(2);
            tracing::debug!(
                seed = self.seed,
                budget = self.budget,
                "forward search restart"
            );
            self.trial = Some(Forward::seeded(self.main.task().clone(), Some(self.seed)));
        }
        match &mut self.trial {
            Some(t) => t.run(step),
            None => ForwardOutcome::Paused,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_tasks::{line, tank};
    use super::*;

    fn plan_of(mut f: Forward) -> ForwardOutcome {
        f.run(100_000)
    }

    #[test]
    fn a_seeded_search_is_reproducible_and_complete() {
        let t = line(5, 2, 20.0);
        let a = plan_of(Forward::seeded(t.clone(), Some(7)));
        assert!(matches!(a, ForwardOutcome::Plan(_)), "{a:?}");
        assert_eq!(a, plan_of(Forward::seeded(t, Some(7))));
        // Too little energy to reach the sun or the goal: every seed exhausts.
        assert_eq!(
            plan_of(Forward::seeded(line(6, 5, 9.0), Some(3))),
            ForwardOutcome::Exhausted
        );
    }

    #[test]
    fn trials_start_after_the_warm_up_and_exhaustion_is_still_answered() {
        // A tank that cannot be drained below -1: every state is reachable and none is a goal.
        let mut r = Restarting::new(tank(3_000.0, -1.0));
        let out = r.run(u64::MAX);
        assert_eq!(out, ForwardOutcome::Exhausted);
        assert!(r.seed >= 1, "a trial ran");
        assert!(
            r.expanded() > 3_000,
            "the main search's states and the trials'"
        );
        // A small problem is solved before any trial.
        let mut r = Restarting::new(line(4, 0, 50.0));
        assert!(matches!(r.run(u64::MAX), ForwardOutcome::Plan(_)));
        assert_eq!(r.seed, 0);
    }
}
