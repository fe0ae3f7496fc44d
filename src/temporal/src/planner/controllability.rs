//! Dynamic controllability at a solution (docs/stnu.md): a plan without flaws is checked as an STNU
//! (its `contingent` durations decided by the world, [`crate::plan::PartialPlan::check_dc`]). Under
//! [`DcMode::Require`] a plan that is not DC is a dead end — the search backtracks from it — and a search
//! that runs out of branches after one says so ([`super::FailReason::NotControllable`]). Under
//! [`DcMode::Report`] the plan is returned DC or not, its verdict kept ([`super::Search::not_controllable`]).

use super::{FailReason, Search, Status, StepOutcome};
use crate::plan::NotControllable;

/// What the search does with a solution's dynamic controllability.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum DcMode {
    /// Check it and keep the verdict; the plan is returned either way (the executive's waits and plan
    /// repair handle what the world does). The default: a deadline the slowest durations would miss
    /// (seed 1's Fig. 2 plan, g2's window) is kept as a chance rather than rejected up front.
    #[default]
    Report,
    /// Only a dynamically controllable plan is a solution.
    Require,
}

impl Search {
    /// Sets what a solution's dynamic controllability decides.
    pub fn set_dc_mode(&mut self, mode: DcMode) {
        self.dc = mode;
    }

    /// Why the plan found is not dynamically controllable (`None` if it is, or before a solution).
    pub fn not_controllable(&self) -> Option<&NotControllable> {
        self.not_dc.as_ref()
    }

    /// Checks the current (flawless) plan; false when [`DcMode::Require`] refuses it.
    pub(super) fn admit_solution(&mut self) -> bool {
        self.not_dc = self.plan.check_dc().err();
        match (&self.not_dc, self.dc) {
            (Some(why), DcMode::Require) => {
                tracing::debug!(%why, "solution refused: not dynamically controllable");
                self.last_rejection = Some(why.text.clone());
                false
            }
            _ => true,
        }
    }

    /// [`Self::admit_solution`] without keeping anything (for a look-ahead).
    pub(super) fn solution_admitted(&self) -> bool {
        self.dc == DcMode::Report || self.plan.check_dc().is_ok()
    }

    /// A search that ran out of branches after refusing a plan for dynamic controllability fails for
    /// that reason.
    pub(super) fn no_dc_plan(&mut self, out: StepOutcome) -> StepOutcome {
        let exhausted = matches!(
            out,
            StepOutcome::Failed(FailReason::Exhausted { .. } | FailReason::NoResolver { .. })
        );
        match (&self.not_dc, exhausted) {
            (Some(why), true) => {
                let r = FailReason::NotControllable {
                    steps: self.steps,
                    reason: why.text.clone(),
                };
                self.status = Status::Failed(r.clone());
                StepOutcome::Failed(r)
            }
            _ => out,
        }
    }
}
