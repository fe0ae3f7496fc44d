//! The dispatch decision (seed 1 §3.5, seed 2): when to execute a controllable timepoint. Starts of actions
//! go through the configured [`crate::dispatch::DispatchPolicy`] (`earliest`, IxTeT-eXeC's default;
//! `latest`; `goal-driven`, seed 2's Algorithm 1 with Algorithm 2 or the marking of Algorithms 3–8); ends
//! and goal timepoints keep seed 1's execution times ([`super::t_exec`]), whatever the policy.

use std::collections::HashSet;

use super::t_exec::{t_exec, TpKind};
use crate::dispatch::{
    DispatchPolicy, GoalSearch, PlanMarking, PlanView, PolicyKind, StartWindow, SupportForm,
};
use mavtempo_temporal::model::Time;
use mavtempo_temporal::plan::{ActionId, Owner, PartialPlan};
use mavtempo_temporal::stn::Timepoint;

/// What the executive sees of one timepoint it may execute.
#[derive(Copy, Clone, Debug)]
pub struct Candidate {
    pub tp: Timepoint,
    pub kind: TpKind,
    pub lb: Time,
    pub ub: Time,
}

/// The executive's dispatcher: the policy and, for `goal-driven`, how it learns an action's goal support.
#[derive(Debug)]
pub struct PlanDispatch {
    kind: PolicyKind,
    policy: Box<dyn DispatchPolicy>,
    marking: PlanMarking,
    search: GoalSearch,
    /// [`super::deferral::latest_at_longest`] for the network it was computed on (its fingerprint).
    longest: Option<(u64, Option<Vec<Time>>)>,
}

impl PlanDispatch {
    pub fn new(kind: PolicyKind) -> Self {
        PlanDispatch {
            kind,
            policy: kind.policy(),
            marking: PlanMarking::new(),
            search: GoalSearch::new(),
            longest: None,
        }
    }

    pub fn kind(&self) -> PolicyKind {
        self.kind
    }

    pub fn name(&self) -> &'static str {
        self.policy.name()
    }

    /// The execution time of `c` (`None`: not as things stand — `latest` and `goal-driven` never start an
    /// action whose start has no upper bound unless it supports an external goal). `action` is the action
    /// whose start `c` is, if it is one.
    pub fn exec_time(
        &mut self,
        plan: &PartialPlan,
        action: Option<ActionId>,
        c: &Candidate,
        ts: Time,
    ) -> Option<Time> {
        match (c.kind, action) {
            (TpKind::Start, Some(a)) => {
                let supports = self.policy.needs_goal_support() && self.supports(plan, a);
                let window = StartWindow {
                    lb: c.lb,
                    ub: self.deferred_ub(plan, c, supports),
                };
                self.policy.t_exec(window, ts, supports)
            }
            _ => Some(t_exec(c.kind, c.lb, c.ub, ts)),
        }
    }

    /// Whether `a` supports an external goal ([`super::goal_support`]'s rule): forward through causal links
    /// (Algorithm 2 on the plan, or the marking read from the plan's change log, which answers at once for
    /// every action it marks) and through the reservoirs the actions on the way produce.
    pub fn supports(&mut self, plan: &PartialPlan, a: ActionId) -> bool {
        let mut seen = HashSet::from([a]);
        let mut todo = vec![a];
        while let Some(x) = todo.pop() {
            if self.supports_causally(plan, x) {
                return true;
            }
            let mut next = Vec::new();
            super::goal_support::supported_by(plan, x, &mut |owner| {
                if let Owner::Action(b) = owner {
                    next.push(b);
                }
            });
            todo.extend(next.into_iter().filter(|&b| seen.insert(b)));
        }
        false
    }

    /// Seed 2's support through causal links only: Algorithm 2, or the marking (if the log does not fit,
    /// a bug, Algorithm 2 answers instead).
    fn supports_causally(&mut self, plan: &PartialPlan, a: ActionId) -> bool {
        let view = PlanView(plan);
        if self.kind == PolicyKind::GoalDriven(SupportForm::Marking) {
            match self.marking.sync(plan) {
                Ok(()) => return self.marking.supports_external_goal(a),
                Err(e) => tracing::warn!("dispatch marking out of step with the plan: {e}"),
            }
        }
        self.search.supports_external_goal(&view, a)
    }

    /// The upper bound a start may be deferred to: for a start the policy defers (not served as early as
    /// possible), the latest start with every duration after it at its longest ([`super::deferral`]),
    /// never below its lower bound; otherwise the STN's.
    fn deferred_ub(&mut self, plan: &PartialPlan, c: &Candidate, supports: bool) -> Time {
        let defers = match self.kind {
            PolicyKind::Earliest => false,
            PolicyKind::Latest => true,
            PolicyKind::GoalDriven(_) => !supports,
        };
        if !defers {
            return c.ub;
        }
        let key = fingerprint(plan);
        if self.longest.as_ref().map(|(k, _)| *k) != Some(key) {
            self.longest = Some((key, super::deferral::latest_at_longest(plan)));
        }
        match &self.longest {
            Some((_, Some(latest))) => latest
                .get(c.tp.index())
                .map_or(c.ub, |&l| l.min(c.ub).max(c.lb)),
            _ => c.ub,
        }
    }

    /// The marking as last read (for tests and traces).
    pub fn marking(&self) -> &PlanMarking {
        &self.marking
    }
}

impl Default for PlanDispatch {
    fn default() -> Self {
        PlanDispatch::new(PolicyKind::Earliest)
    }
}

/// A fingerprint of the plan's temporal network (its constraints and which actions are live), to reuse
/// the longest-duration bounds while nothing changed.
fn fingerprint(plan: &PartialPlan) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    for (c, k) in plan.temporal_network().constraints() {
        (c.index(), k.from.index(), k.to.index(), k.lb, k.ub).hash(&mut h);
    }
    for a in plan.live_actions() {
        (a.index(), plan.is_executed(plan.action(a).end)).hash(&mut h);
    }
    h.finish()
}
