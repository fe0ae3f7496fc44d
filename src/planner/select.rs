//! Flaw selection: which flaw the next planning step resolves.
//!
//! 1. Flaws without any resolver first: the branch is dead, backtrack at once.
//! 2. Conflicts (threats, resource conflicts) with exactly one resolver that only adds a constraint: a
//!    forced move that prunes and propagates, never a commitment.
//! 3. Everything else by the abstraction hierarchy ([`super::hierarchy`]): flaws on the most abstract
//!    attributes first; a reservoir conflict just below the level of the most abstract action involved,
//!    a unary conflict just above the secondary attributes. Within a level: forced flaws (one resolver), then open conditions, then
//!    conflicts that can still be resolved in several ways — delaying those (as in DSep / ZLIFO) lets the
//!    open conditions decide the order of actions (the tour of moves) before an arbitrary precedence does;
//!    then fewest resolvers (fail-first); among open conditions the most urgent (smallest latest start of
//!    the condition) and then the most recent (depth-first completion of the newest action).

use std::cmp::Reverse;

use super::hierarchy::Hierarchy;
use super::resolvers::{refine, resolvers, Resolver};
use crate::plan::{Flaw, PartialPlan};

/// Rank of a flaw on an attribute in the hierarchy (higher first): attribute levels doubled, so that
/// resource conflicts can sit between two levels.
fn rank_attr(h: &Hierarchy, attr: crate::model::AttrId) -> u64 {
    u64::from(h.level(attr)) * 2
}

/// Rank of a unary-resource conflict: just above the secondary attributes. It only ever needs an
/// ordering, which the causal structure usually implies by then (two pictures at different places are
/// ordered by the tour); resolving it earlier would fix an arbitrary order before the tour exists.
const RANK_UNARY: u64 = 1;

/// Rank of a reservoir conflict: just below the level of the most abstract action involved (the highest
/// main attribute of its task; tasks without one, such as a download, count as the lowest established
/// level). A picture's storage is settled right after the pictures exist, before the tour — it may need a
/// download inserted, which constrains the tour — while a move's energy waits until the tour has bound
/// its origin: before that its consumption spans every distance of the map and the envelope reports
/// conflicts that are not there.
fn rank_reservoir(plan: &PartialPlan, h: &Hierarchy, flaw: &Flaw) -> u64 {
    let level = plan
        .involved_actions(flaw)
        .into_iter()
        .flat_map(|a| plan.domain.task(plan.action(a).task).main_attributes())
        .map(|attr| h.level(attr))
        .filter(|&l| l != super::hierarchy::STATIC)
        .max()
        .unwrap_or(1)
        .max(1);
    u64::from(level) * 2 - 1
}

/// 0 = dead end, 1 = forced constraint, 2 = the rest.
fn tier(rs: &[Resolver], open: bool) -> u8 {
    match rs.len() {
        0 => 0,
        1 if !open && !rs[0].inserts() => 1,
        _ => 2,
    }
}

/// Within a level: forced flaws, then open conditions, then conflicts with a choice.
fn class(n: usize, open: bool) -> u8 {
    match (n <= 1, open) {
        (true, _) => 0,
        (false, true) => 1,
        (false, false) => 2,
    }
}

type Key = (u8, Reverse<u64>, u8, usize, u8, i64, Reverse<u32>);

fn key(rank: u64, rs: &[Resolver], open: bool, kind: u8, urgency: i64, recency: u32) -> Key {
    let t = tier(rs, open);
    // Dead ends and forced constraints are taken whatever their level.
    let rank = if t < 2 { 0 } else { rank };
    (
        t,
        Reverse(rank),
        class(rs.len(), open),
        rs.len(),
        kind,
        urgency,
        Reverse(recency),
    )
}

/// The selected flaw and its ordered resolvers; `None` when the plan has no flaw (a solution).
pub fn pick(plan: &mut PartialPlan, h: &Hierarchy) -> Option<(Flaw, Vec<Resolver>)> {
    let mut best: Option<(Key, Flaw, Vec<Resolver>)> = None;
    let mut consider = |key: Key, f: Flaw, rs: Vec<Resolver>| {
        if best.as_ref().is_none_or(|(k, _, _)| key < *k) {
            best = Some((key, f, rs));
        }
    };
    for (event, link) in plan.live_threats() {
        let f = Flaw::Threat { event, link };
        let rs = resolvers(plan, &f);
        let rank = rank_attr(h, plan.cond(plan.link(link).cond).attr);
        consider(key(rank, &rs, false, 0, 0, 0), f, rs);
    }
    for (a, b) in plan.live_unary_conflicts() {
        let f = Flaw::UnaryConflict { a, b };
        let rs = resolvers(plan, &f);
        consider(key(RANK_UNARY, &rs, false, 1, 0, 0), f, rs);
    }
    // Open conditions below the best rank present can only win as dead ends; their resolvers (the
    // costliest to list) are computed only at the best rank, and reservoirs that cannot reach it are
    // not checked this step.
    let open: Vec<_> = plan.open_conditions().collect();
    let top = open
        .iter()
        .map(|&c| rank_attr(h, plan.cond(c).attr))
        .max()
        .unwrap_or(0);
    for c in plan.reservoir_conflicts_of(|r| u64::from(h.resource_level(r)) * 2 > top) {
        let f = Flaw::Reservoir(c);
        let rs = resolvers(plan, &f);
        let rank = rank_reservoir(plan, h, &f);
        consider(key(rank, &rs, false, 2, 0, 0), f, rs);
    }
    for c in open {
        let cond = plan.cond(c);
        let rank = rank_attr(h, cond.attr);
        if rank < top {
            continue;
        }
        let urgency = plan.stn.ub(cond.from);
        let f = Flaw::OpenCondition(c);
        let rs = resolvers(plan, &f);
        consider(key(rank, &rs, true, 3, urgency, c.0), f, rs);
    }
    best.map(|(_, f, mut rs)| {
        refine(plan, &f, &mut rs);
        (f, rs)
    })
}
