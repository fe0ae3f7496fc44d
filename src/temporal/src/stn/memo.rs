//! Memory of the ordering queries answered "no shorter path" ([`Stn::distance_below`] false), so that asking
//! them again after the network grew costs the edges added since, not another search.
//!
//! A search proving `d(a, b) ≥ limit` proves it for the paths that avoid the origin (those through the
//! origin are priced by the bounds, `ub[b] − lb[a]`, always re-read). Constraints only ever *add* edges or
//! lower their weights (additions, tightenings — each logged as a new edge with a stamp), or take edges away
//! (restores, removals — distances only grow). So in the network of a later moment, a path a→b avoiding the
//! origin either uses only edges that existed at the proof (weight ≥ the proven bound) or uses some edge
//! u→v (weight w) logged since, and then weighs at least `d(a, u) + w + d(v, b)`, bounded below by the
//! current bounds (earliest and latest times are both solutions: `d(x, y) ≥ max(lb[y] − lb[x],
//! ub[y] − ub[x])`). When that bound still reaches the limit for every edge logged since, the answer stands.
//!
//! The one exception, a removed constraint made active again by a restore, clears the memory. Timepoints
//! removed by a restore and their identifiers reused are covered: every edge of a new timepoint is logged.
//! The memory is a cache: a clone of the network starts without it.

use std::cell::RefCell;
use std::collections::HashMap;

use super::network::Stn;
use super::{sat_add, Time, INF};

/// A logged edge u→v of weight w: a constraint added or tightened.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LoggedEdge {
    /// Increasing over the network's life (never reused after a restore).
    pub stamp: u64,
    /// The trail level when logged: the edge is undone by restoring any level below it.
    pub at: super::Level,
    pub u: u32,
    pub v: u32,
    pub w: Time,
}

#[derive(Clone, Copy, Debug)]
struct Proof {
    /// The last logged stamp when the bound was proven (or re-checked).
    stamp: u64,
    /// Every path a→b avoiding the origin weighs at least this much.
    lower: Time,
}

#[derive(Default)]
pub(crate) struct Memo(RefCell<HashMap<(u32, u32), Proof>>);

impl Clone for Memo {
    fn clone(&self) -> Self {
        Memo::default()
    }
}

impl std::fmt::Debug for Memo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Memo({} proofs)", self.0.borrow().len())
    }
}

/// A lower bound of `d(x, y)` from the bounds alone.
fn lower_bound(stn: &Stn, x: u32, y: u32) -> Time {
    if x == y {
        return 0;
    }
    let (lb, ub) = (&stn.lb, &stn.ub);
    let by_lb = sat_add(lb[y as usize], -lb[x as usize]);
    if ub[x as usize] < INF && ub[y as usize] < INF {
        by_lb.max(ub[y as usize] - ub[x as usize])
    } else {
        by_lb
    }
}

impl Memo {
    pub fn clear(&self) {
        self.0.borrow_mut().clear();
    }

    /// Whether the paths a→b avoiding the origin are known to weigh at least `limit` (re-checked against
    /// the edges logged since the proof).
    pub fn proves(&self, stn: &Stn, a: u32, b: u32, limit: Time) -> bool {
        let mut map = self.0.borrow_mut();
        let Some(proof) = map.get_mut(&(a, b)) else {
            return false;
        };
        if proof.lower < limit {
            return false;
        }
        let mut lower = proof.lower;
        for e in stn.log.iter().rev() {
            if e.stamp <= proof.stamp {
                break;
            }
            if e.u == 0 || e.v == 0 {
                continue; // not on a path avoiding the origin
            }
            let through = sat_add(
                sat_add(lower_bound(stn, a, e.u), e.w),
                lower_bound(stn, e.v, b),
            );
            lower = lower.min(through);
            if lower < limit {
                return false;
            }
        }
        *proof = Proof {
            stamp: stn.log_stamp,
            lower,
        };
        true
    }

    /// Records that the paths a→b avoiding the origin weigh at least `limit` now.
    pub fn record(&self, stn: &Stn, a: u32, b: u32, limit: Time) {
        self.0.borrow_mut().insert(
            (a, b),
            Proof {
                stamp: stn.log_stamp,
                lower: limit,
            },
        );
    }
}
