//! Flaw selection: which flaw the next planning step resolves.
//!
//! 1. Flaws without any resolver first: the branch is dead, backtrack at once.
//! 2. Conflicts (threats, resource conflicts) with exactly one resolver that only adds a constraint: a
//!    forced move that prunes and propagates, never a commitment.
//! 3. Everything else by the abstraction hierarchy ([`super::hierarchy`]): flaws on the most abstract
//!    attributes first; a reservoir conflict just below the level of the most abstract action involved,
//!    a unary conflict just above the secondary attributes. Within a level: forced flaws (one resolver
//!    that inserts no action), then open conditions, then conflicts that can still be resolved in several
//!    ways — delaying those (as in DSep / ZLIFO) lets the open conditions decide the order of actions (the
//!    tour of moves) before an arbitrary precedence does. Conflicts: fewest resolvers first (fail-first).
//!    Open conditions: the most urgent (smallest latest start of the condition), then the most recent
//!    (LIFO: depth-first completion of the newest action) — *not* fewest resolvers: a condition whose one
//!    resolver inserts an action (a picture's move) waits its turn like the others, so that a new move's
//!    origin is linked before the next move is inserted. Inserting every picture's move first leaves n
//!    unordered moves and n² threats to examine at every step (grid 40: 4.3 s against 1.2 s).
//! 4. Open conditions that take any value (a PDDL add's prior value) only once no other is left: they get
//!    no insertion, so the actions they may be linked to must all be in the plan by then.

use std::cmp::Reverse;

use super::hierarchy::Hierarchy;
use super::resolvers::{refine, resolvers, resolvers_below, Resolver};
use crate::plan::{CondId, EventId, Flaw, LinkId, PartialPlan, UsageId};

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

/// 0 = dead end, 1 = forced constraint, 2 = the rest (`n` resolvers, the first inserting an action or not).
fn tier(n: usize, first_inserts: bool, open: bool) -> u8 {
    match n {
        0 => 0,
        1 if !open && !first_inserts => 1,
        _ => 2,
    }
}

/// Within a level: forced flaws (for an open condition: one resolver that inserts no action), then open
/// conditions, then conflicts with a choice.
fn class(n: usize, first_inserts: bool, open: bool) -> u8 {
    match (n <= 1, open) {
        (true, true) if n == 1 && first_inserts => 1,
        (true, _) => 0,
        (false, true) => 1,
        (false, false) => 2,
    }
}

/// Whether an open condition's resolvers commit to nothing: none (a dead end) or one that inserts no
/// action. No open condition examined after it can be selected instead but by being a dead end.
fn zero_commitment(rs: &[Resolver]) -> bool {
    rs.is_empty() || (rs.len() == 1 && !rs[0].inserts())
}

type Key = (u8, Reverse<u64>, u8, usize, u8, i64, Reverse<u32>);

/// The key of a flaw with `n` resolvers. For a given first resolver kind it never decreases with `n`,
/// so a flaw proven to have at least `n` resolvers has at least `key_n(.., n, ..)`.
fn key_n(
    rank: u64,
    n: usize,
    first_inserts: bool,
    open: bool,
    kind: u8,
    urgency: i64,
    recency: u32,
) -> Key {
    let t = tier(n, first_inserts, open);
    // Dead ends and forced constraints are taken whatever their level.
    let rank = if t < 2 { 0 } else { rank };
    // Open conditions are not ranked by their number of resolvers (see the module docs).
    let count = if open { 0 } else { n };
    (
        t,
        Reverse(rank),
        class(n, first_inserts, open),
        count,
        kind,
        urgency,
        Reverse(recency),
    )
}

fn key(rank: u64, rs: &[Resolver], open: bool, kind: u8, urgency: i64, recency: u32) -> Key {
    let first_inserts = rs.first().is_some_and(Resolver::inserts);
    key_n(rank, rs.len(), first_inserts, open, kind, urgency, recency)
}

/// Where a flaw comes in the order of consideration (threats and unary conflicts, then reservoir
/// conflicts, then open conditions by urgency): the first of equal keys wins.
type Pos = (u8, usize);

/// The best flaw so far: the least `(key, position)`.
struct Best {
    best: Option<(Key, Pos, Flaw, Vec<Resolver>)>,
}

impl Best {
    fn beats(&self, key: Key, pos: Pos) -> bool {
        self.best
            .as_ref()
            .is_none_or(|(k, p, _, _)| (key, pos) < (*k, *p))
    }

    /// The fewest resolvers a flaw at `pos` must be proven to have to lose to the best so far
    /// (`usize::MAX` when nothing bounds it); `key_of(n)` is its key with `n` resolvers.
    fn limit(&self, pos: Pos, key_of: impl Fn(usize) -> Key) -> usize {
        if self.best.is_none() {
            return usize::MAX;
        }
        // Keys grow with n, by n itself past 1: the first losing n is found within the best's count.
        (0..=self.best.as_ref().map_or(0, |b| b.0 .3).saturating_add(2))
            .find(|&n| !self.beats(key_of(n), pos))
            .unwrap_or(usize::MAX)
    }

    fn consider(&mut self, key: Key, pos: Pos, f: Flaw, rs: Vec<Resolver>) {
        if self.beats(key, pos) {
            self.best = Some((key, pos, f, rs));
        }
    }
}

/// Which order [`pick`] takes the open conditions in.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum Order {
    /// By the abstraction hierarchy alone: static conditions first.
    #[default]
    Hierarchy,
    /// The same, but a static condition with a choice among several facts last ([`rank_open`]).
    StaticChoicesLast,
}

/// Rank of an open condition: its attribute's, except that a condition on a static attribute with a
/// choice among several facts ranks last (below the secondary attributes). Such a choice only binds
/// variables (a communication's place among every place that sees the lander): made first, it follows
/// the order of the facts; made last, the action's other conditions have bound them through their
/// establishers (where the vehicle already is), and it is then forced or a dead end, taken at once.
fn rank_open(
    plan: &PartialPlan,
    h: &Hierarchy,
    order: Order,
    f: &Flaw,
    c: crate::plan::CondId,
) -> u64 {
    let attr = plan.cond(c).attr;
    if order == Order::StaticChoicesLast
        && h.level(attr) == super::hierarchy::STATIC
        && resolvers_below(plan, f, 2).is_none()
    {
        return 0;
    }
    rank_attr(h, attr)
}

/// The live threats, unary conflicts and open conditions with their ranks, and the best rank present.
/// Listed as their identifiers (a [`Flaw`] is as large as a reservoir conflict: copying and sorting
/// hundreds of them at every step showed in the profile); [`ranked`] makes the flaws.
type Ranked<T> = Vec<(T, u64)>;
type RankedFlaws = (
    Ranked<(EventId, LinkId)>,
    Ranked<(UsageId, UsageId)>,
    Ranked<CondId>,
    u64,
);
fn ranked_flaws(plan: &mut PartialPlan, h: &Hierarchy, order: Order) -> RankedFlaws {
    let threats: Ranked<(EventId, LinkId)> = plan
        .live_threats()
        .into_iter()
        .map(|(event, link)| {
            let rank = rank_attr(h, plan.cond(plan.link(link).cond).attr);
            ((event, link), rank)
        })
        .collect();
    // Conditions that take any value wait until no other open condition is left (see `open_condition`).
    let (any, mut open): (Vec<_>, Vec<_>) = plan
        .open_conditions()
        .partition(|&c| plan.cond_takes_any(c));
    if open.is_empty() {
        open = any;
    }
    let open: Ranked<CondId> = open
        .into_iter()
        .map(|c| (c, rank_open(plan, h, order, &Flaw::OpenCondition(c), c)))
        .collect();
    let top = threats
        .iter()
        .map(|&(_, r)| r)
        .chain(open.iter().map(|&(_, r)| r))
        .max();
    // Unary conflicts rank below every other flaw but a static condition's: listed (a pass over them all)
    // only when nothing ranks above them, the only case the selection looks at them.
    let unary: Ranked<(UsageId, UsageId)> = if top.is_some_and(|t| t > RANK_UNARY) {
        Vec::new()
    } else {
        plan.live_unary_conflicts()
            .into_iter()
            .map(|pair| (pair, RANK_UNARY))
            .collect()
    };
    let top = top
        .into_iter()
        .chain(unary.iter().map(|&(_, r)| r))
        .max()
        .unwrap_or(0);
    (threats, unary, open, top)
}

/// The open conditions among `open` at rank `top` or above, most urgent (least latest time of the condition)
/// first, then most recent: the order the selection examines them in.
fn open_candidates(
    plan: &PartialPlan,
    open: Ranked<CondId>,
    top: u64,
) -> Vec<(i64, std::cmp::Reverse<u32>, Flaw, u64)> {
    let mut candidates: Vec<(i64, std::cmp::Reverse<u32>, u64)> = open
        .into_iter()
        .filter(|&(_, rank)| rank >= top)
        .map(|(c, rank)| (plan.stn.ub(plan.cond(c).from), std::cmp::Reverse(c.0), rank))
        .collect();
    candidates.sort_by_key(|&(u, r, _)| (u, r));
    candidates
        .into_iter()
        .map(|(u, r, rank)| (u, r, Flaw::OpenCondition(CondId(r.0)), rank))
        .collect()
}

/// The threats, then the unary conflicts, as flaws with their ranks (the order the selection examines
/// them in).
fn ranked(
    threats: Ranked<(EventId, LinkId)>,
    unary: Ranked<(UsageId, UsageId)>,
) -> impl Iterator<Item = (Flaw, u64)> {
    let threats = threats
        .into_iter()
        .map(|((event, link), rank)| (Flaw::Threat { event, link }, rank));
    let unary = unary
        .into_iter()
        .map(|((a, b), rank)| (Flaw::UnaryConflict { a, b }, rank));
    threats.chain(unary)
}

/// The selected flaw and its ordered resolvers; `None` when the plan has no flaw (a solution).
///
/// Forced conflicts were mostly applied by [`propagate_forced`] at the end of the previous step, so only
/// the flaws at the best rank present need their resolvers listed (listing them costs ordering queries);
/// reservoirs that cannot reach that rank are not even checked this step. The selection is the least
/// key over the flaws considered (the first of equal keys); open conditions are examined first because
/// they usually win, and the other flaws' resolvers are only counted as far as could still beat the best
/// found so far ([`resolvers_below`]) — the choice is the one listing every flaw's resolvers would make.
pub fn pick(plan: &mut PartialPlan, h: &Hierarchy, order: Order) -> Option<(Flaw, Vec<Resolver>)> {
    let (threats, unary, open, top) = ranked_flaws(plan, h, order);
    let reservoirs = plan.reservoir_conflicts_of(|r| u64::from(h.resource_level(r)) * 2 > top);
    let mut best = Best { best: None };
    // Open conditions at the best rank in the order the key ranks equal counts (most urgent, then most
    // recent); the scan stops at the first zero-commitment one, which no later one can beat
    // but by being a dead end — found at the next step anyway.
    let candidates = open_candidates(plan, open, top);
    for (i, (urgency, std::cmp::Reverse(recency), f, rank)) in candidates.into_iter().enumerate() {
        let pos = (2, i);
        let key_of = |n| key_n(rank, n, false, true, 3, urgency, recency);
        // At least 2: whether the scan stops here (forced) must be known exactly.
        let limit = best.limit(pos, key_of).max(2);
        // None: at least `limit` (≥ 2) resolvers, neither forced nor better than the best.
        if let Some(rs) = resolvers_below(plan, &f, limit) {
            let forced = zero_commitment(&rs);
            best.consider(key(rank, &rs, true, 3, urgency, recency), pos, f, rs);
            if forced {
                break;
            }
        }
    }
    for (i, c) in reservoirs.into_iter().enumerate() {
        let f = Flaw::Reservoir(c);
        let rs = resolvers(plan, &f);
        let rank = rank_reservoir(plan, h, &f);
        best.consider(key(rank, &rs, false, 2, 0, 0), (1, i), f, rs);
    }
    for (i, (f, rank)) in ranked(threats, unary).enumerate() {
        if rank < top {
            continue;
        }
        let kind = if matches!(f, Flaw::Threat { .. }) {
            0
        } else {
            1
        };
        let pos = (0, i);
        // Threat and unary resolvers only order or bind: none inserts an action.
        let limit = best.limit(pos, |n| key_n(rank, n, false, false, kind, 0, 0));
        if let Some(rs) = resolvers_below(plan, &f, limit) {
            best.consider(key(rank, &rs, false, kind, 0, 0), pos, f, rs);
        }
    }
    best.best.map(|(_, _, f, mut rs)| {
        refine(plan, &f, &mut rs, order == Order::StaticChoicesLast);
        (f, rs)
    })
}

/// Applies, within the current planning step, every conflict (threat, unary-resource conflict) that has
/// exactly one resolver and that resolver only adds a constraint — a forced move, so no choice point is
/// needed. A conflict left without any resolver makes the step fail (the caller
/// restores the node and tries its next resolver). Without this each of the quadratically many forced
/// orderings of a tour would be a planning step of its own, each re-examining the whole flaw set.
pub fn propagate_forced(
    plan: &mut PartialPlan,
    h: &Hierarchy,
    order: Order,
) -> Result<(), crate::plan::PlanError> {
    // One pass over the threats, then one over the unary conflicts (a full re-scan per application would
    // cost more than it prunes). Each candidate is examined in the current network, constraints applied
    // earlier in the pass included: its resolvers first, and only when fewer than two remain whether it
    // is still a conflict — one that can be resolved in two ways is not forced, resolved for good or not,
    // and its verdict waits for a listing of the live flaws. Nearly all of them can while the tour is
    // being built (~n² unary conflicts): this asks two ordering queries of those instead of four.
    for i in plan.threat_candidates() {
        let (event, link) = plan.threat_pair(i);
        let f = Flaw::Threat { event, link };
        let Some(rs) = resolvers_below(plan, &f, 2) else {
            continue;
        };
        if plan.threat_live(i) == crate::plan::ThreatCheck::Threat {
            apply_forced(plan, &f, &rs)?;
        }
    }
    for i in plan.unary_candidates() {
        let (a, b) = plan.unary_pair(i);
        let f = Flaw::UnaryConflict { a, b };
        let Some(rs) = resolvers_below(plan, &f, 2) else {
            continue;
        };
        if plan.unary_live(i) == Some(true) {
            apply_forced(plan, &f, &rs)?;
        }
    }
    forward_check_statics(plan, h, order)
}

/// Forward checking of the static conditions left open by [`Order::StaticChoicesLast`] (the other
/// order takes them first): they only constrain bindings, so one the bindings made unsupportable is a
/// dead end now, and one left with a single fact is linked to it (which may bind variables further —
/// checked at the next step's pass).
pub(super) fn forward_check_statics(
    plan: &mut PartialPlan,
    h: &Hierarchy,
    order: Order,
) -> Result<(), crate::plan::PlanError> {
    if order != Order::StaticChoicesLast {
        return Ok(());
    }
    let statics: Vec<crate::plan::CondId> = plan
        .open_conditions()
        .filter(|&c| h.level(plan.cond(c).attr) == super::hierarchy::STATIC)
        .collect();
    for c in statics {
        let f = Flaw::OpenCondition(c);
        match resolvers_below(plan, &f, 2).as_deref() {
            Some([]) => return Err(crate::plan::PlanError::DeadEnd(plan.flaw_text(&f))),
            Some([r]) if !r.inserts() => super::resolvers::apply(plan, r)?,
            _ => {}
        }
    }
    Ok(())
}

/// Fails on a flaw without resolver, applies the only resolver of a flaw that has one (unless it inserts
/// an action: that is a choice of the selection's).
pub(super) fn apply_forced(
    plan: &mut PartialPlan,
    f: &Flaw,
    rs: &[Resolver],
) -> Result<(), crate::plan::PlanError> {
    match rs {
        [] => Err(crate::plan::PlanError::DeadEnd(plan.flaw_text(f))),
        [r] if !r.inserts() => super::resolvers::apply(plan, r),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    /// The selection before it counted resolvers lazily: every considered flaw's resolvers listed, the
    /// first least key kept. The lazy [`pick`] must choose exactly as it does.
    fn pick_reference(plan: &mut PartialPlan, h: &Hierarchy) -> Option<(Flaw, Vec<Resolver>)> {
        let (threats, unary, open, top) = ranked_flaws(plan, h, Order::Hierarchy);
        let mut best: Option<(Key, Flaw, Vec<Resolver>)> = None;
        let mut consider = |key: Key, f: Flaw, rs: Vec<Resolver>| {
            if best.as_ref().is_none_or(|(k, _, _)| key < *k) {
                best = Some((key, f, rs));
            }
        };
        for (f, rank) in ranked(threats, unary) {
            if rank < top {
                continue;
            }
            let kind = if matches!(f, Flaw::Threat { .. }) {
                0
            } else {
                1
            };
            let rs = resolvers(plan, &f);
            consider(key(rank, &rs, false, kind, 0, 0), f, rs);
        }
        for c in plan.reservoir_conflicts_of(|r| u64::from(h.resource_level(r)) * 2 > top) {
            let f = Flaw::Reservoir(c);
            let rs = resolvers(plan, &f);
            let rank = rank_reservoir(plan, h, &f);
            consider(key(rank, &rs, false, 2, 0, 0), f, rs);
        }
        let candidates = open_candidates(plan, open, top);
        for (urgency, std::cmp::Reverse(recency), f, rank) in candidates {
            let rs = resolvers(plan, &f);
            let forced = zero_commitment(&rs);
            consider(key(rank, &rs, true, 3, urgency, recency), f, rs);
            if forced {
                break;
            }
        }
        best.map(|(_, f, mut rs)| {
            refine(plan, &f, &mut rs, false);
            (f, rs)
        })
    }

    /// On generated rover grids and the shipped problems, at every step of the search, the lazy
    /// selection equals the exhaustive one (flaw and ordered resolvers).
    #[test]
    fn lazy_pick_equals_exhaustive() {
        let (rover, problems) = crate::planner::test_problems::rover_problems();
        for p in problems {
            let root = PartialPlan::new(rover.clone(), Arc::new(p)).expect("root plan");
            let mut search = crate::planner::Search::new(root);
            let mut compared = 0;
            for _ in 0..2_000 {
                // The root's forced conflicts are applied by the search's first selection.
                if !search.stack.is_empty() {
                    let mut lazy = search.plan.clone();
                    let mut full = search.plan.clone();
                    let h = &search.hierarchy;
                    assert_eq!(
                        pick(&mut lazy, h, Order::Hierarchy),
                        pick_reference(&mut full, h)
                    );
                    compared += 1;
                }
                if search.step() != crate::planner::StepOutcome::Progress {
                    break;
                }
            }
            assert!(search.next_is_solution(), "the search solves the problem");
            assert!(compared > 10);
        }
    }
}
