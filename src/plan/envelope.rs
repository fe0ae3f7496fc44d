//! Reservoir conflicts (seed 1 §2.2 "resource conflicts"; Laborie & Ghallab 1995) detected by a **sound
//! level envelope over the partial order**, not on one schedule.
//!
//! Each usage is a change of the level at a timepoint: a consumption `−q` at `at`, a production `+q`, a
//! borrowing (`use`) `−q` at its start and `+q` at its end. At each decrease `i`, the lowest level any
//! schedule can reach just after `i` is at least
//!
//! `L0 + Σ_{increases j necessarily < i} q_min(j) − Σ_{decreases j possibly ≤ i (i included)} q_max(j)`,
//!
//! and at each increase `i`, the highest level is at most
//!
//! `L0 + Σ_{increases j possibly ≤ i (i included)} q_max(j) − Σ_{decreases j necessarily < i} q_min(j)`.
//!
//! (Changes at the same instant are taken in their worst order, as the checker does.)
//!
//! Levels only change at these instants, so if every bound is within `[0, capacity]` every schedule of the
//! partial plan (every instantiation of the quantities) keeps the level inside: no conflict is missed.
//! A violation names the checkpoint and the usages whose ordering is still open — the resolvers.

use super::order::{necessarily_after, possibly_after};
use super::{NTerm, PartialPlan, UsageId, UsageKind};
use crate::model::ResourceId;
use crate::stn::Timepoint;

/// A reservoir whose level may leave `[0, capacity]`.
#[derive(Clone, Debug, PartialEq)]
pub struct ReservoirConflict {
    pub resource: ResourceId,
    /// The usage at whose instant the level may leave its bounds.
    pub at: UsageId,
    pub point: Timepoint,
    /// `true`: the level may exceed the capacity (over-production); `false`: it may drop below 0.
    pub overflow: bool,
    /// The pessimistic level bound at `point`.
    pub level: f64,
    pub capacity: f64,
    /// Decreases (usages, timepoints) possibly but not necessarily (strictly) before `point`.
    pub open_decreases: Vec<(UsageId, Timepoint)>,
    /// Increases possibly but not necessarily before `point`.
    pub open_increases: Vec<(UsageId, Timepoint)>,
    /// Increases necessarily before `point` (or at it) whose quantity is not fixed: counted at their
    /// minimum in a shortage, they can be made to produce more.
    pub short_producers: Vec<UsageId>,
}

/// Numeric tolerance on levels.
const EPS: f64 = 1e-6;

struct Change {
    usage: UsageId,
    at: Timepoint,
    up: bool,
    lo: f64,
    hi: f64,
}

/// The first checkpoint (earliest lower bound) where reservoir `r`'s envelope leaves `[0, capacity]`.
pub fn reservoir_conflict(plan: &PartialPlan, r: ResourceId) -> Option<ReservoirConflict> {
    let setup = plan.problem.resource(r)?;
    let l0 = setup.level;
    // The lowest capacity of the availability profile: sound whatever the checkpoint's time.
    let capacity = if setup.profile.is_empty() {
        plan.domain.resource(r).capacity
    } else {
        setup
            .profile
            .iter()
            .map(|&(_, c)| c)
            .fold(f64::INFINITY, f64::min)
    };
    let mut changes: Vec<Change> = Vec::new();
    for &u in plan.usages_of(r) {
        let us = plan.usage(u);
        if plan.action(us.action).removed {
            continue;
        }
        let (lo, hi) = match us.quantity {
            NTerm::Var(v) => plan.numeric.bounds(v),
            NTerm::Const(c) => (c, c),
        };
        let mut push = |at, up| {
            changes.push(Change {
                usage: u,
                at,
                up,
                lo,
                hi,
            })
        };
        match us.kind {
            UsageKind::Consume { at } => push(at, false),
            UsageKind::Produce { at } => push(at, true),
            UsageKind::Use { from, to } => {
                push(from, false);
                push(to, true);
            }
        }
    }
    let stn = &plan.stn;
    let mut order: Vec<usize> = (0..changes.len()).collect();
    order.sort_by_key(|&i| (stn.lb(changes[i].at), i));
    for &i in &order {
        let ci = &changes[i];
        let mut level = l0;
        let mut open_dec = Vec::new();
        let mut open_inc = Vec::new();
        let mut short_producers = Vec::new();
        for (j, cj) in changes.iter().enumerate() {
            let nec = j == i || necessarily_after(stn, cj.at, ci.at, 1);
            let poss = nec || possibly_after(stn, cj.at, ci.at, 0);
            if ci.up {
                if cj.up && poss {
                    level += cj.hi;
                } else if !cj.up && nec {
                    level -= cj.lo;
                }
            } else if cj.up && nec {
                level += cj.lo;
                if cj.lo < cj.hi {
                    short_producers.push(cj.usage);
                }
            } else if !cj.up && poss {
                level -= cj.hi;
            }
            if poss && !nec {
                if cj.up {
                    open_inc.push((cj.usage, cj.at));
                } else {
                    open_dec.push((cj.usage, cj.at));
                }
            }
        }
        let violated = if ci.up {
            level > capacity + EPS
        } else {
            level < -EPS
        };
        if violated {
            return Some(ReservoirConflict {
                resource: r,
                at: ci.usage,
                point: ci.at,
                overflow: ci.up,
                level,
                capacity,
                open_decreases: open_dec,
                open_increases: open_inc,
                short_producers,
            });
        }
    }
    None
}
