//! The level of a resource at time t (seed 1 §3.1, eq. (1) and (2)).
//!
//! Case (1), no running action modifies r: the exact level `RscL_t(r) = Lev_t^past(r)` (eq. 1), a variable in
//! `[lev_lb^past, lev_ub^past]`. Case (2), some running action uses r: the past level plus the estimate of
//! eq. (2) for the running actions. The past actions that already left the plan are aggregated in
//! `past` (seed 1 §3.4: "executed resource propositions are aggregated in one proposition"); it starts as the
//! problem's initial level (the paper's C(r)).

use crate::id_vec::IdVec;
use mavtempo_temporal::model::{ResourceId, Time};
use mavtempo_temporal::plan::{ActionId, PartialPlan, UsageKind};

/// Which formula gives the level.
#[derive(Copy, Clone, Eq, PartialEq, Debug, serde::Serialize)]
pub enum LevelCase {
    /// Case (1): no running action modifies r; the level is exactly `Lev^past`.
    Exact,
    /// Case (2): at least one running action uses r; eq. (2) gives an estimate.
    Estimated,
}

/// `[RscL_lb, RscL_ub]` with the past part `[lev_lb^past, lev_ub^past]`.
#[derive(Copy, Clone, PartialEq, Debug, serde::Serialize)]
pub struct LevelBounds {
    pub case: LevelCase,
    pub past_lb: f64,
    pub past_ub: f64,
    pub lb: f64,
    pub ub: f64,
}

/// Eq. (1): `Lev_t^past(r) = C(r) + Σ ?q_p − Σ ?q_c` over productions / consumptions with `t_ub < t` whose
/// action is not running; `past` is the aggregate of the actions already removed from the plan.
pub fn past_level(
    plan: &PartialPlan,
    r: ResourceId,
    t: Time,
    running: &[ActionId],
    past: (f64, f64),
) -> (f64, f64) {
    // In time order: a saturating production adds at most up to the capacity.
    let mut changes: Vec<(Time, f64, f64, bool)> = Vec::new();
    for &u in plan.usages_of(r) {
        let us = plan.usage(u);
        if plan.action(us.action).removed || running.contains(&us.action) {
            continue;
        }
        let (qlo, qhi) = plan.numeric().term(us.quantity);
        match us.kind {
            UsageKind::Produce { at } if plan.latest(at) < t => {
                changes.push((plan.latest(at), qlo, qhi, us.saturating));
            }
            UsageKind::Consume { at } if plan.latest(at) < t => {
                changes.push((plan.latest(at), -qhi, -qlo, false));
            }
            _ => {}
        }
    }
    changes.sort_by_key(|c| c.0);
    let capacity = plan.domain().resource(r).capacity;
    changes
        .into_iter()
        .fold(past, |(lb, ub), (_, dlo, dhi, saturating)| {
            add(lb, ub, dlo, dhi, saturating, capacity)
        })
}

/// `[lb, ub] + [dlo, dhi]`, clipped at the capacity for a saturating production.
fn add(lb: f64, ub: f64, dlo: f64, dhi: f64, saturating: bool, capacity: f64) -> (f64, f64) {
    if saturating {
        ((lb + dlo).min(capacity), (ub + dhi).min(capacity))
    } else {
        (lb + dlo, ub + dhi)
    }
}

/// Eq. (2): `[lev_min^RA, lev_max^RA]`, what the running actions may have done to r so far: consumed up to
/// `q_max`, produced up to `q_max`, borrowed between `q_min` and `q_max`. `None` when no running action
/// uses r (case (1)).
pub fn running_estimate(
    plan: &PartialPlan,
    r: ResourceId,
    running: &[ActionId],
) -> Option<(f64, f64)> {
    let (mut min, mut max) = (0.0, 0.0);
    let mut any = false;
    for &u in plan.usages_of(r) {
        let us = plan.usage(u);
        if !running.contains(&us.action) || plan.action(us.action).removed {
            continue;
        }
        any = true;
        let (qlo, qhi) = plan.numeric().term(us.quantity);
        match us.kind {
            UsageKind::Consume { .. } => min -= qhi,
            UsageKind::Produce { .. } => max += qhi,
            UsageKind::Use { .. } => {
                min -= qhi;
                max -= qlo;
            }
        }
    }
    any.then_some((min, max))
}

/// `[RscL_lb, RscL_ub]` at t: case (1) `lev^past`, case (2) `lev^past + [lev_min^RA, lev_max^RA]`.
pub fn level_bounds(
    plan: &PartialPlan,
    r: ResourceId,
    t: Time,
    running: &[ActionId],
    past: (f64, f64),
) -> LevelBounds {
    let (past_lb, past_ub) = past_level(plan, r, t, running, past);
    match running_estimate(plan, r, running) {
        None => LevelBounds {
            case: LevelCase::Exact,
            past_lb,
            past_ub,
            lb: past_lb,
            ub: past_ub,
        },
        Some((min, max)) => LevelBounds {
            case: LevelCase::Estimated,
            past_lb,
            past_ub,
            lb: past_lb + min,
            ub: past_ub + max,
        },
    }
}

/// Folds the usages of a removed (past) action into the aggregate `past` of its resources (called when the
/// action leaves the plan, so eq. (1) keeps counting it).
pub fn fold_removed(plan: &PartialPlan, a: ActionId, past: &mut IdVec<ResourceId, (f64, f64)>) {
    for &u in &plan.action(a).usages {
        let us = plan.usage(u);
        let (qlo, qhi) = plan.numeric().term(us.quantity);
        let capacity = plan.domain().resource(us.resource).capacity;
        let Some(p) = past.get_mut(us.resource) else {
            continue;
        };
        *p = match us.kind {
            UsageKind::Produce { .. } => add(p.0, p.1, qlo, qhi, us.saturating, capacity),
            UsageKind::Consume { .. } => add(p.0, p.1, -qhi, -qlo, false, capacity),
            UsageKind::Use { .. } => *p,
        };
    }
}
