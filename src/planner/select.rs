//! Flaw selection: which flaw the next planning step resolves.
//!
//! Heuristic: *fewest resolvers first* over the whole flaw set (fail-first: a flaw without resolver ends the
//! branch at once, a flaw with one resolver is a forced move). Ties go to threats, then unary-resource
//! conflicts, then reservoir conflicts, then open conditions — conflicts first because they only add
//! constraints and prune the branch early, while open conditions may add actions. Among open conditions
//! with as many resolvers, the most urgent (smallest latest start of the condition) and then the most
//! recent (depth-first completion of the newest action) is chosen.
//!
//! One exception, from the abstraction hierarchy (Knoblock's ordered monotonicity, seed 1 §3.3): open
//! conditions on attributes that tasks change only as a *secondary* effect (`ROBOT_STATUS`) come after
//! every other flaw (static attributes such as `CONNECTED`, which nothing changes, are not deferred: their
//! resolvers are final). Their establishers are side effects of actions inserted for
//! other reasons; linking them early (to the initial state, say) commits before those actions exist and
//! makes the search incomplete in practice.

use std::cmp::Reverse;

use super::resolvers::{resolvers, Resolver};
use crate::plan::{Flaw, PartialPlan};

/// Forced flaws (at most one resolver) first, then open conditions, then conflicts that can still be
/// resolved in several ways — delaying those (as in DSep / ZLIFO) lets the open conditions decide the order
/// of actions (e.g. the tour of moves) before an arbitrary precedence does.
fn class(n: usize, open: bool) -> u8 {
    match (n <= 1, open) {
        (true, _) => 0,
        (false, true) => 1,
        (false, false) => 2,
    }
}

/// The selected flaw and its ordered resolvers; `None` when the plan has no flaw (a solution).
pub fn pick(plan: &mut PartialPlan) -> Option<(Flaw, Vec<Resolver>)> {
    type Key = (bool, u8, usize, u8, i64, Reverse<u32>);
    let mut best: Option<(Key, Flaw, Vec<Resolver>)> = None;
    let mut consider = |key: Key, f: Flaw, rs: Vec<Resolver>| {
        if best.as_ref().is_none_or(|(k, _, _)| key < *k) {
            best = Some((key, f, rs));
        }
    };
    for (event, link) in plan.live_threats() {
        let f = Flaw::Threat { event, link };
        let rs = resolvers(plan, &f);
        consider(
            (false, class(rs.len(), false), rs.len(), 0, 0, Reverse(0)),
            f,
            rs,
        );
    }
    for (a, b) in plan.live_unary_conflicts() {
        let f = Flaw::UnaryConflict { a, b };
        let rs = resolvers(plan, &f);
        consider(
            (false, class(rs.len(), false), rs.len(), 1, 0, Reverse(0)),
            f,
            rs,
        );
    }
    for c in plan.reservoir_conflicts() {
        let f = Flaw::Reservoir(c);
        let rs = resolvers(plan, &f);
        consider(
            (false, class(rs.len(), false), rs.len(), 2, 0, Reverse(0)),
            f,
            rs,
        );
    }
    let open: Vec<_> = plan.open_conditions().collect();
    for c in open {
        let f = Flaw::OpenCondition(c);
        let rs = resolvers(plan, &f);
        let cond = plan.cond(c);
        let urgency = plan.stn.ub(cond.from);
        let low_level = plan.domain.tasks_establishing(cond.attr).is_empty()
            && plan
                .domain
                .tasks
                .iter()
                .any(|t| t.events.iter().any(|e| e.attr == cond.attr));
        consider(
            (
                low_level,
                class(rs.len(), true),
                rs.len(),
                3,
                urgency,
                Reverse(c.0),
            ),
            f,
            rs,
        );
    }
    best.map(|(_, f, rs)| (f, rs))
}
