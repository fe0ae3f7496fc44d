//! Flaw selection: which flaw the next planning step resolves.
//!
//! Heuristic: *fewest resolvers first* over the whole flaw set (fail-first: a flaw without resolver ends the
//! branch at once, a flaw with one resolver is a forced move). Ties go to threats, then unary-resource
//! conflicts, then reservoir conflicts, then open conditions — conflicts first because they only add
//! constraints and prune the branch early, while open conditions may add actions. Among open conditions
//! with as many resolvers, the most urgent (smallest latest start of the condition) and then the most
//! recent (depth-first completion of the newest action) is chosen.

use std::cmp::Reverse;

use super::resolvers::{resolvers, Resolver};
use crate::plan::{Flaw, PartialPlan};

/// The selected flaw and its ordered resolvers; `None` when the plan has no flaw (a solution).
pub fn pick(plan: &mut PartialPlan) -> Option<(Flaw, Vec<Resolver>)> {
    let mut best: Option<((usize, u8, i64, Reverse<u32>), Flaw, Vec<Resolver>)> = None;
    let mut consider = |key: (usize, u8, i64, Reverse<u32>), f: Flaw, rs: Vec<Resolver>| {
        if best.as_ref().is_none_or(|(k, _, _)| key < *k) {
            best = Some((key, f, rs));
        }
    };
    for (event, link) in plan.live_threats() {
        let f = Flaw::Threat { event, link };
        let rs = resolvers(plan, &f);
        consider((rs.len(), 0, 0, Reverse(0)), f, rs);
    }
    for (a, b) in plan.live_unary_conflicts() {
        let f = Flaw::UnaryConflict { a, b };
        let rs = resolvers(plan, &f);
        consider((rs.len(), 1, 0, Reverse(0)), f, rs);
    }
    for c in plan.reservoir_conflicts() {
        let f = Flaw::Reservoir(c);
        let rs = resolvers(plan, &f);
        consider((rs.len(), 2, 0, Reverse(0)), f, rs);
    }
    let open: Vec<_> = plan.open_conditions().collect();
    for c in open {
        let f = Flaw::OpenCondition(c);
        let rs = resolvers(plan, &f);
        let urgency = plan.stn.ub(plan.cond(c).from);
        consider((rs.len(), 3, urgency, Reverse(c.0)), f, rs);
    }
    best.map(|(_, f, rs)| (f, rs))
}
