//! The edits the executive makes to *ExecutingPlan* while it runs (seed 1 §3.3–§3.6), and the reads it
//! needs of the plan's timepoints. Each edit keeps the flaw caches right by construction (recomputing the
//! candidate threats and resource conflicts where the edit can change them), so that the executive never
//! edits the plan's networks itself nor has to remember to refresh the caches.

use std::sync::Arc;

use super::{ActionId, LinkId, PartialPlan, PlanError, STerm, VarId};
use crate::model::{AttrId, ObjectId, Problem, Time, Value};
use crate::stn::{Inconsistent, Timepoint, INF};

impl PartialPlan {
    /// The simple temporal network, to read (the rules of Definition 2–5 and the dispatch decision read
    /// distances and predecessors).
    pub fn temporal_network(&self) -> &crate::stn::Stn {
        &self.stn
    }

    /// Binds `v` to `value` (an action's parameter instantiated before its START), then re-propagates what
    /// depends on the binding (the distances of moves); on `Err` the caller restores its level.
    pub fn bind_var(&mut self, v: VarId, value: ObjectId) -> Result<(), PlanError> {
        self.bindings.restrict_var(v, &[value])?;
        self.propagate_changed_bindings()
    }

    /// Keeps `v` off `value`, then re-propagates what depends on the binding; on `Err` the caller restores
    /// its level.
    pub fn keep_var_off(&mut self, v: VarId, value: ObjectId) -> Result<(), PlanError> {
        self.bindings.separate(STerm::Var(v), STerm::Obj(value))?;
        self.propagate_changed_bindings()
    }

    /// The lower bound of `tp` (ms since the origin).
    pub fn earliest(&self, tp: Timepoint) -> Time {
        self.stn.lb(tp)
    }

    /// The upper bound of `tp` (ms since the origin; [`INF`] when unbounded).
    pub fn latest(&self, tp: Timepoint) -> Time {
        self.stn.ub(tp)
    }

    pub fn is_executed(&self, tp: Timepoint) -> bool {
        self.stn.is_executed(tp)
    }

    /// When `tp` was executed, if it was.
    pub fn executed_at(&self, tp: Timepoint) -> Option<Time> {
        self.stn.executed_at(tp)
    }

    /// Timepoint `tp` happened at `t` (seed 1 §3.5 ExecTPs; an action's end reported in time, §3.3).
    pub fn execute_at(&mut self, tp: Timepoint, t: Time) -> Result<(), Inconsistent> {
        self.stn.execute(tp, t).map(|_| ())
    }

    /// `tp` cannot happen before `t` (time moves on: the repair root §3.4, a new goal's d_achiev §3.3).
    pub fn not_before(&mut self, tp: Timepoint, t: Time) -> Result<(), Inconsistent> {
        let origin = self.stn.origin();
        self.stn.add_constraint(origin, tp, t, INF).map(|_| ())
    }

    /// `before` precedes `after` (a goal after the running actions it threatens, §3.3; goals after T_end,
    /// §3.6).
    pub fn order(&mut self, before: Timepoint, after: Timepoint) -> Result<(), Inconsistent> {
        self.stn.add_precedence(before, after).map(|_| ())
    }

    /// `min ≤ to − from ≤ max` (a resolver's temporal constraint, for plans built by hand). Constraints only
    /// narrow the windows, so a candidate flaw once resolved stays resolved: the caches stay right.
    pub fn constrain(
        &mut self,
        from: Timepoint,
        to: Timepoint,
        min: Time,
        max: Time,
    ) -> Result<(), Inconsistent> {
        self.stn.add_constraint(from, to, min, max).map(|_| ())
    }

    /// §3.6 T_end, the end of the planning process: a new timepoint within `[now, horizon]`.
    pub fn add_planning_end(&mut self, now: Time) -> Result<Timepoint, Inconsistent> {
        let origin = self.stn.origin();
        let t_end = self.stn.add_timepoint();
        self.stn.add_constraint(origin, t_end, now, self.horizon)?;
        Ok(t_end)
    }

    /// §3.3 a report before its end's lower bound: the end's constraints are relaxed and it is executed at
    /// `t`, then constrained before every timepoint that directly followed it (keeping the end's identity
    /// keeps its events attached to it).
    pub fn execute_end_early(&mut self, a: ActionId, t: Time) -> Result<(), Inconsistent> {
        let (st, et) = (self.action(a).start, self.action(a).end);
        let origin = self.stn.origin();
        let followers: Vec<(Timepoint, Time)> = self
            .stn
            .constraints_of(et)
            .filter_map(|(_, k)| {
                (k.from == et && k.to != et && k.to != origin && k.to != st && k.lb >= 0)
                    .then_some((k.to, k.lb))
            })
            .filter(|&(s, _)| !self.stn.is_executed(s))
            .collect();
        self.stn.relax_timepoint(et);
        self.stn.execute(et, t)?;
        for (s, lb) in followers {
            self.stn.add_constraint(et, s, lb.max(0), INF)?;
        }
        self.recompute_candidates();
        Ok(())
    }

    /// A new problem whose resource levels or capacities changed (§3.3 resource level, capacity
    /// alteration): the resource conflicts are checked again.
    pub fn set_resource_problem(&mut self, problem: Arc<Problem>) {
        self.set_problem(problem);
        self.recompute_candidates();
    }

    /// §3.3 state variables: the causal links the reported values contradict are broken and the values
    /// observed at `t` enter the plan (those that cannot are returned with why).
    pub fn integrate_observations(
        &mut self,
        broken: &[LinkId],
        observed: Vec<(AttrId, Vec<ObjectId>, Value)>,
        t: Time,
    ) -> Vec<super::PlanError> {
        for &l in broken {
            self.remove_link(l);
        }
        let errors = observed
            .into_iter()
            .filter_map(|(attr, args, value)| self.add_observation(attr, &args, value, t).err())
            .collect();
        self.recompute_candidates();
        errors
    }

    /// §3.3 causal-link removal via the abstraction hierarchy: the links are broken, their conditions open.
    pub fn break_links(&mut self, links: &[LinkId]) {
        for &l in links {
            self.remove_link(l);
        }
        self.recompute_candidates();
    }
}
