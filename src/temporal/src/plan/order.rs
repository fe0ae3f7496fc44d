//! Ordering queries on the STN used by flaw detection, with a cheap test on the timepoints' bounds before the
//! exact (shortest-path) query. All answers are exact: the bounds only decide the cases they can prove.

use crate::stn::{Stn, Time, Timepoint};

/// Whether `b − a ≥ k` holds in every solution (`k` = 0: a ≤ b, 1: a < b).
pub fn necessarily_after(stn: &Stn, a: Timepoint, b: Timepoint, k: Time) -> bool {
    necessarily_after_by_bounds(stn, a, b, k).unwrap_or_else(|| stn.distance_below(b, a, 1 - k))
}

/// [`necessarily_after`] where the bounds decide it; `None` when only the distance `d(b, a) < 1 − k` can.
pub fn necessarily_after_by_bounds(stn: &Stn, a: Timepoint, b: Timepoint, k: Time) -> Option<bool> {
    if a == b {
        return Some(k <= 0);
    }
    if stn.lb(b).saturating_sub(stn.ub(a)) >= k {
        return Some(true);
    }
    if stn.ub(b).saturating_sub(stn.lb(a)) < k {
        return Some(false);
    }
    None
}

/// Whether `b − a ≥ k` is consistent with the network.
pub fn possibly_after(stn: &Stn, a: Timepoint, b: Timepoint, k: Time) -> bool {
    if a == b {
        return k <= 0;
    }
    if stn.ub(b).saturating_sub(stn.lb(a)) < k {
        return false;
    }
    if stn.lb(b).saturating_sub(stn.ub(a)) >= k {
        return true;
    }
    !stn.distance_below(a, b, k)
}
