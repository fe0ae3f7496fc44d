//! Simple Temporal Network (STN): the temporal constraint manager shared by the planner, the executive and
//! the dispatcher.
//!
//! Timepoints are integer times (the product uses milliseconds) relative to an origin; binary constraints
//! `to − from ∈ [lb, ub]` with infinite bounds ([`INF`], `-INF`) and open bounds (one unit inside, see
//! [`open_lower`], [`open_upper`]). Every timepoint is implicitly after the origin (`t − origin ≥ 0`).
//!
//! What is kept up to date, and how:
//! - each timepoint's bounds `[lb, ub]` relative to the origin, maintained incrementally when a constraint is
//!   added or tightened, by Dijkstra over reduced costs with the current bounds as potentials; a negative
//!   cycle is detected when the propagation comes back to the constraint being added (Cesta & Oddi), and is
//!   reported with its constraints ([`Inconsistent`]) — the network is then left exactly as before;
//! - a trail: [`Stn::save`] returns a [`Level`], [`Stn::restore`] undoes everything done after it;
//! - relaxation ([`Stn::remove_constraint`]) by bounded recomputation of the bounds that depended on the
//!   removed constraint;
//! - [`Stn::distance`] on demand: a search, or two look-ups in the all-pairs matrix of the paths avoiding the
//!   origin when the planner asks for it ([`Stn::maintain_paths`], [`paths`]);
//! - execution of timepoints ([`Stn::execute`]) and the timepoints due at a time ([`Stn::due`]).
//!
//! [`Stnu`] adds contingent links (durations the world decides) and the dynamic-controllability check
//! (Morris 2014; [`dc_reference`] the classic fixpoint, its oracle); see docs/stnu.md.
//!
//! [`floyd_warshall`] solves the same network by the all-pairs method of IxTeT (test oracle, bench baseline).
//!
//! Identifiers ([`Timepoint`], [`ConstraintId`]) created after a [`Level`] are invalidated by restoring it and
//! are reused by later additions, as in any trail-based solver.

mod dc;
pub mod dc_reference;
mod distance;
mod error;
pub mod floyd_warshall;
mod memo;
mod network;
pub mod paths;
mod propagate;
mod relax;
mod settle;
mod stnu;
mod trail;

pub use error::{CycleEdge, EdgeSource, Inconsistent};
pub use network::Stn;
pub use stnu::{
    ContingentLink, DerivedEdge, Dispatchable, NotDc, Requirement, Stnu, StnuError, Wait,
};

/// A time or a duration, in integer units (milliseconds in the product).
pub type Time = i64;

/// +infinity. An upper bound `>= INF` is infinite, a lower bound `<= -INF` is minus infinity; arithmetic
/// saturates at ±INF.
pub const INF: Time = i64::MAX / 4;

/// Largest finite bound magnitude (2^50 ms, about 35,000 years): other bounds of a constraint are clamped into
/// `[-MAX_FINITE, MAX_FINITE]`, so that an upper bound of `-INF` is a (hugely negative) finite bound.
pub const MAX_FINITE: Time = 1 << 50;

/// A timepoint of the network. The origin is [`Stn::origin`].
#[derive(Copy, Clone, Eq, PartialEq, Ord, PartialOrd, Hash, Debug)]
pub struct Timepoint(pub(crate) u32);

impl Timepoint {
    /// Dense index (0 is the origin), usable to index side tables.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A constraint of the network, as returned by [`Stn::add_constraint`].
#[derive(Copy, Clone, Eq, PartialEq, Ord, PartialOrd, Hash, Debug)]
pub struct ConstraintId(pub(crate) u32);

impl ConstraintId {
    /// Dense index, usable to index side tables.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A trail level, returned by [`Stn::save`].
pub use backtrack::Level;

/// A binary constraint `to − from ∈ [lb, ub]`.
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug)]
pub struct Constraint {
    pub from: Timepoint,
    pub to: Timepoint,
    pub lb: Time,
    pub ub: Time,
}

/// The lower bound of an open interval `]a, ..`: one unit inside (`a + 1`); `-INF` stays `-INF`.
pub fn open_lower(a: Time) -> Time {
    if a <= -INF {
        -INF
    } else {
        sat_add(a, 1)
    }
}

/// The upper bound of an open interval `.., b[`: one unit inside (`b − 1`); `INF` stays `INF`.
pub fn open_upper(b: Time) -> Time {
    if b >= INF {
        INF
    } else {
        sat_add(b, -1)
    }
}

/// `a + b` clamped to `[-INF, INF]`; `INF` absorbs finite values (and wins over `-INF`).
pub(crate) fn sat_add(a: Time, b: Time) -> Time {
    if a >= INF || b >= INF {
        INF
    } else if a <= -INF || b <= -INF {
        -INF
    } else {
        (a + b).clamp(-INF, INF)
    }
}

/// Normalises a constraint's lower bound: `-INF` or finite in `[-MAX_FINITE, MAX_FINITE]`.
pub(crate) fn norm_lb(x: Time) -> Time {
    if x <= -INF {
        -INF
    } else {
        x.clamp(-MAX_FINITE, MAX_FINITE)
    }
}

/// Normalises a constraint's upper bound: `INF` or finite in `[-MAX_FINITE, MAX_FINITE]`.
pub(crate) fn norm_ub(x: Time) -> Time {
    if x >= INF {
        INF
    } else {
        x.clamp(-MAX_FINITE, MAX_FINITE)
    }
}

#[cfg(test)]
mod paths_tests;
#[cfg(test)]
mod stnu_tests;
#[cfg(test)]
mod tests;
