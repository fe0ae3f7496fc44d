//! Ordering queries on the STN used by flaw detection, with a cheap test on the timepoints' bounds before the
//! exact (shortest-path) query. All answers are exact: the bounds only decide the cases they can prove.

use crate::stn::{Stn, Time, Timepoint};

/// Whether `b − a ≥ k` holds in every solution (`k` = 0: a ≤ b, 1: a < b).
pub fn necessarily_after(stn: &Stn, a: Timepoint, b: Timepoint, k: Time) -> bool {
    if a == b {
        return k <= 0;
    }
    if stn.lb(b).saturating_sub(stn.ub(a)) >= k {
        return true;
    }
    if stn.ub(b).saturating_sub(stn.lb(a)) < k {
        return false;
    }
    stn.distance_below(b, a, 1 - k)
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
