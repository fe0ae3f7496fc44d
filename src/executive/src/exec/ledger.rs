//! The resource ledger: the aggregated level `[lev_lb, lev_ub]` of each resource due to the actions that
//! left the plan (seed 1 §3.4: "executed resource propositions are aggregated in one proposition"; eq. (1)
//! starts from it), and every rule that writes it or the level the planner is handed:
//! - an action leaves the plan only with its usages folded in ([`ResourceLedger::drop_past`]);
//! - a capacity alteration clips both to the new capacity ([`ResourceLedger::clip_to_capacity`]);
//! - a reported level is posted on the aggregate, and the reservoir envelope starts from it
//!   ([`ResourceLedger::post_level`]);
//! - complete replanning starts from it ([`ResourceLedger::hand_to_planner`]).
//!
//! It starts as the problem's initial level (the paper's C(r)).

use std::sync::Arc;

use super::p_t::remove_past;
use super::resource_bounds::fold_removed;
use crate::id_vec::IdVec;
use mavtempo_temporal::model::{Problem, ResourceId, Time};
use mavtempo_temporal::plan::{ActionId, PartialPlan};

/// The aggregated past level of each resource, by resource, with what the vehicle last reported of it.
#[derive(Clone, Debug, Default)]
pub struct ResourceLedger {
    past: IdVec<ResourceId, (f64, f64)>,
    /// Reported levels within this distance of `[RscL_lb, RscL_ub]` are in bounds (the vehicle's
    /// resolution and tolerance, `[resources]`).
    tolerances: IdVec<ResourceId, f64>,
    /// The last level the vehicle reported and when (ms since origin): the report's
    /// `resources[].reported`.
    reported: IdVec<ResourceId, Option<(Time, f64)>>,
}

impl ResourceLedger {
    /// Each resource's initial level, exact.
    pub fn new(problem: &Problem) -> Self {
        let n = problem.resources.len();
        ResourceLedger {
            past: IdVec::from_items(
                problem
                    .resources
                    .iter()
                    .map(|s| (s.level, s.level))
                    .collect(),
            ),
            tolerances: IdVec::from_items(vec![super::resource_report::EPS; n]),
            reported: IdVec::from_items(vec![None; n]),
        }
    }

    /// The in-bounds distance of a reported level of `r`.
    pub fn tolerance(&self, r: ResourceId) -> f64 {
        self.tolerances
            .get(r)
            .copied()
            .unwrap_or(super::resource_report::EPS)
    }

    /// Each resource's in-bounds distance, in resource order.
    pub fn set_tolerances(&mut self, tolerances: Vec<f64>) {
        self.tolerances = IdVec::from_items(tolerances);
    }

    /// The vehicle reported `level` for `r` at `t`.
    pub fn reported(&mut self, r: ResourceId, t: Time, level: f64) {
        if let Some(slot) = self.reported.get_mut(r) {
            *slot = Some((t, level));
        }
    }

    /// The last level reported for resource `r` and when, if any.
    pub fn last_reported(&self, r: ResourceId) -> Option<(Time, f64)> {
        self.reported.get(r).copied().flatten()
    }

    /// `[lev_lb, lev_ub]` of every resource, by resource index.
    pub fn levels(&self) -> &[(f64, f64)] {
        self.past.as_slice()
    }

    /// `[lev_lb, lev_ub]` of `r` (`(0, 0)` for a resource the problem does not have).
    pub fn past(&self, r: ResourceId) -> (f64, f64) {
        self.past.get(r).copied().unwrap_or((0.0, 0.0))
    }

    /// The aggregate of `r` is `level` (e.g. a level measured before the start).
    pub fn set(&mut self, r: ResourceId, level: (f64, f64)) {
        if let Some(p) = self.past.get_mut(r) {
            *p = level;
        }
    }

    /// The actions wholly in the past at `t` leave the plan (P_t's past part), their resource usages folded
    /// into the aggregate: the two go together, or the levels forget what those actions did.
    pub fn drop_past(&mut self, plan: &mut PartialPlan, t: Time) -> Vec<ActionId> {
        let removed = remove_past(plan, t);
        for &p in &removed {
            fold_removed(plan, p, &mut self.past);
        }
        removed
    }

    /// Capacity alteration (§3.3): neither the aggregate nor the problem's level can exceed the new
    /// capacity (the lost part is gone).
    pub fn clip_to_capacity(&mut self, problem: &mut Problem, r: ResourceId, capacity: f64) {
        if let Some(setup) = problem.resources.get_mut(r.index()) {
            setup.level = setup.level.min(capacity);
        }
        if let Some(p) = self.past.get_mut(r) {
            p.0 = p.0.min(capacity);
            p.1 = p.1.min(capacity);
        }
    }

    /// A reported level posted on the past part: `past` is the aggregate eq. (1) must give with the usages
    /// it still counts (`counted`) subtracted back out. The reservoir envelope starts from the
    /// (pessimistic) aggregated level: the plan's problem with it.
    pub fn post_level(
        &mut self,
        plan: &PartialPlan,
        r: ResourceId,
        past: (f64, f64),
        counted: (f64, f64),
    ) -> Arc<Problem> {
        self.set(r, (past.0 - counted.0, past.1 - counted.1));
        let mut problem = (**plan.problem()).clone();
        if let Some(s) = problem.resources.get_mut(r.index()) {
            s.level = self.past(r).0;
        }
        Arc::new(problem)
    }

    /// Complete replanning (§3.6) starts from the aggregated levels, the pessimistic bound, never below
    /// empty.
    pub fn hand_to_planner(&self, problem: &mut Problem) {
        for (s, past) in problem.resources.iter_mut().zip(self.past.iter()) {
            s.level = past.0.max(0.0);
        }
    }
}
