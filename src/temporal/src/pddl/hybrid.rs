//! The forward search of a PDDL problem as one search of the planner's portfolio
//! ([`crate::planner::solve_portfolio_with`]): the problem grounded ([`super::ground`]), searched forward
//! with h_FF in slices ([`crate::planner::forward::Forward`]), its sequential plan deordered and completed
//! as a partial plan ([`crate::planner::forward::embed`]) and checked like a POCL plan. When it cannot
//! help (a feature it does not ground, no sequential plan, a plan the model or the checker refuses) it
//! steps aside and the POCL searches go on alone.

use std::time::{Duration, Instant};

use super::ground::ground;
use super::Loaded;
use crate::planner::forward::{embed, ForwardOutcome, Restarting};
use crate::planner::Planned;

/// Expansions between two looks at the clock.
const CHUNK: u64 = 32;

/// Planning steps the POCL search may take to complete a sequential plan, per action in it (it mostly
/// links and orders; a plan it cannot complete within this is handed over to the POCL searches).
const COMPLETION_STEPS_PER_ACTION: u64 = 60;

/// The forward search's state between slices.
pub struct Hybrid<'a> {
    loaded: &'a Loaded,
    forward: Option<Restarting>,
    deadline: Option<Instant>,
    /// Why it stepped aside, for the log.
    pub aside: Option<String>,
}

impl<'a> Hybrid<'a> {
    /// The forward search of `loaded` (stepped aside at once when the problem is not grounded).
    pub fn new(loaded: &'a Loaded, deadline: Option<Instant>) -> Self {
        let (forward, aside) = match ground(&loaded.domain, &loaded.problem) {
            Ok(task) => {
                tracing::debug!(
                    actions = task.actions.len(),
                    atoms = task.atoms.len(),
                    "grounded"
                );
                (Some(Restarting::new(task)), None)
            }
            Err(e) => (None, Some(format!("not grounded: {e}"))),
        };
        Hybrid {
            loaded,
            forward,
            deadline,
            aside,
        }
    }

    /// One slice of about `share` of time and at most `steps` expansions (one step each): a checked plan,
    /// or the steps taken.
    pub fn slice(&mut self, steps: u64, share: Duration) -> Result<Planned, u64> {
        let Some(forward) = &mut self.forward else {
            return Err(0);
        };
        let started = forward.expanded();
        let clock = Instant::now();
        let mut outcome = ForwardOutcome::Paused;
        while outcome == ForwardOutcome::Paused
            && clock.elapsed() < share
            && forward.expanded() - started < steps
            && self.deadline.is_none_or(|d| Instant::now() < d)
        {
            let left = steps - (forward.expanded() - started);
            outcome = forward.run(CHUNK.min(left));
        }
        let used = forward.expanded() - started;
        tracing::debug!(expanded = forward.expanded(), "forward slice");
        let ForwardOutcome::Plan(seq) = outcome else {
            if outcome == ForwardOutcome::Exhausted {
                self.step_aside("no sequential plan".into());
            }
            return Err(used);
        };
        tracing::debug!(actions = seq.len(), "sequential plan found");
        if tracing::enabled!(tracing::Level::TRACE) {
            for &i in &seq {
                if let Some(a) = forward.task().actions.get(i as usize) {
                    tracing::trace!("({} {})", a.name, a.args.join(" "));
                }
            }
        }
        let t = &self.loaded.translated;
        let max_steps = COMPLETION_STEPS_PER_ACTION * (seq.len() as u64 + 10);
        let embedded = embed(
            t.domain.clone(),
            t.problem.clone(),
            forward.task(),
            &seq,
            max_steps,
        );
        let planned = match embedded {
            Ok(p) => p,
            Err(e) => {
                self.step_aside(format!("its plan of {} actions: {e}", seq.len()));
                return Err(used + max_steps);
            }
        };
        if let Err(e) = super::solve::check(self.loaded, &planned) {
            self.step_aside(format!("its plan is refused: {e}"));
            return Err(used + planned.steps);
        }
        if self.deadline.is_some_and(|d| Instant::now() >= d) {
            return Err(used + planned.steps);
        }
        Ok(Planned {
            steps: planned.steps + used,
            ..planned
        })
    }

    fn step_aside(&mut self, why: String) {
        tracing::debug!(why = %why, "forward search steps aside");
        self.forward = None;
        self.aside = Some(why);
    }
}
