//! A reported resource level l_r against `[RscL_lb, RscL_ub]` (seed 1 §3.3 "Resource level").
//!
//! - in bounds: consistent; in case (1) the level becomes exact, `RscL_t(r) = l_r`;
//! - `l_r < RscL_lb`, over-consumption: a consumption `c = RscL_lb − l_r` is added; case (1):
//!   `RscL_t(r) = RscL_lb` (so the new level is `l_r`); case (2): seed 1 says `L_t^past(r) = lev_lb^past`
//!   (worst case); here the past level is `l_r` less the running actions' productions, so that their
//!   consumption still to come is not taken as spent (a vehicle drains while it moves; see
//!   docs/departures.md);
//! - `l_r > RscL_ub`, over-production: a production `p = l_r − RscL_ub`; case (1): `RscL_t(r) = RscL_ub`
//!   (new level `l_r`); case (2): `L_t^past(r) = lev_ub^past`.
//!
//! The plan stays executable in case (1); in case (2) conflicts may involve running actions (the caller
//! checks Definition 5 and aborts). When executable, repair is requested after an over-consumption and after
//! an over-production of a reservoir.
//!
//! The added consumption / production happens at t, before every future usage, so it is folded into the
//! aggregated past level (the one proposition the executed usages are aggregated into, §3.4).

use super::resource_bounds::{LevelBounds, LevelCase};
use mavtempo_temporal::model::ResourceKind;

/// The verdict on one reported level.
#[derive(Copy, Clone, PartialEq, Debug, serde::Serialize, serde::Deserialize)]
pub enum LevelVerdict {
    Consistent,
    OverConsumption { c: f64 },
    OverProduction { p: f64 },
}

impl std::fmt::Display for LevelVerdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LevelVerdict::Consistent => f.write_str("as planned"),
            LevelVerdict::OverConsumption { c } => write!(f, "{c:.2} more used than planned"),
            LevelVerdict::OverProduction { p } => write!(f, "{p:.2} more produced than planned"),
        }
    }
}

/// What integrating a level does to the plan.
#[derive(Copy, Clone, PartialEq, Debug, serde::Serialize)]
pub struct LevelUpdate {
    pub verdict: LevelVerdict,
    /// The new aggregated past level `[lev_lb^past, lev_ub^past]`, including the added usage.
    pub past: (f64, f64),
    /// Case (2) with a mismatch: conflicts may involve running actions, Definition 5 must be re-checked.
    pub check_executable: bool,
    /// Plan repair requested (if the plan is executable).
    pub repair: bool,
}

/// Default numeric tolerance on levels.
pub const EPS: f64 = mavtempo_temporal::model::LEVEL_TOLERANCE;

/// `tol`: the vehicle's resolution (e.g. a battery reported in whole percents): a level within `tol` of
/// the bounds is in them.
pub fn integrate_level(b: &LevelBounds, l_r: f64, kind: ResourceKind, tol: f64) -> LevelUpdate {
    let exact = b.case == LevelCase::Exact;
    if l_r < b.lb - tol {
        let c = b.lb - l_r;
        // Case (1): RscL_t = RscL_lb then minus c, i.e. l_r. Case (2): the running actions' usages are
        // counted at their start, but a vehicle drains as it goes: none of what they still use may be in
        // the reading, so the past level is l_r less their productions (new bounds [l_r − used, l_r]),
        // not seed 1's lev_lb^past − c, which takes it all as spent and meets every later reading of the
        // same drain as one more over-consumption (one repair per battery percent).
        let max = b.ub - b.past_ub;
        let lvl = if exact { l_r } else { l_r - max.max(0.0) };
        LevelUpdate {
            verdict: LevelVerdict::OverConsumption { c },
            past: (lvl, lvl),
            check_executable: !exact,
            repair: true,
        }
    } else if l_r > b.ub + tol {
        let p = l_r - b.ub;
        let lvl = if exact { l_r } else { b.past_ub + p };
        LevelUpdate {
            verdict: LevelVerdict::OverProduction { p },
            past: (lvl, lvl),
            check_executable: !exact,
            repair: kind == ResourceKind::Reservoir,
        }
    } else {
        LevelUpdate {
            verdict: LevelVerdict::Consistent,
            past: if exact {
                (l_r, l_r)
            } else {
                (b.past_lb, b.past_ub)
            },
            check_executable: false,
            repair: false,
        }
    }
}
