//! Seed 2's Algorithm 1 over the standalone causal graph ([`crate::dispatch::CausalGraph`] and its
//! [`Marking`]): the form `mavtempo bench dispatch` times and the dispatch scenario tests drive. The
//! executive's own is `exec::dispatch_policy::PlanDispatch`, over the plan.

use crate::dispatch::graph::{ActionId, CausalView};
use crate::dispatch::marking::Marking;
use crate::dispatch::policy::{
    Decision, DispatchPolicy, PolicyKind, StartWindow, SupportForm, Tick,
};
use crate::dispatch::search::GoalSearch;

/// A policy with what it needs to answer for an action of the plan.
#[derive(Debug)]
pub struct Dispatcher {
    kind: PolicyKind,
    policy: Box<dyn DispatchPolicy>,
    search: GoalSearch,
}

impl Dispatcher {
    pub fn new(kind: PolicyKind) -> Self {
        Dispatcher {
            kind,
            policy: kind.policy(),
            search: GoalSearch::new(),
        }
    }

    pub fn kind(&self) -> PolicyKind {
        self.kind
    }

    /// Whether `a` supports an external goal, by the configured form (Algorithm 2 over `causal`, or the
    /// lookup in `marking`). False for policies that do not ask.
    pub fn supports(&mut self, a: ActionId, causal: &dyn CausalView, marking: &Marking) -> bool {
        match self.kind {
            PolicyKind::GoalDriven(SupportForm::Search) => {
                self.search.supports_external_goal(causal, a)
            }
            PolicyKind::GoalDriven(SupportForm::Marking) => marking.supports_external_goal(a),
            _ => false,
        }
    }

    /// The decision for action `a`'s start this cycle.
    pub fn decide(
        &mut self,
        a: ActionId,
        window: StartWindow,
        tick: Tick,
        causal: &dyn CausalView,
        marking: &Marking,
    ) -> Decision {
        let supports = self.policy.needs_goal_support() && self.supports(a, causal, marking);
        self.policy.decide(window, tick, supports)
    }
}
