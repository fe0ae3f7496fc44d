//! A report's arrival time against its end timepoint (seed 1 §3.3 "Report"): inside `[et_lb, et_ub]` it fixes
//! `et = t`; too late, the plan is not executable any more (timeout); too early, a new end timepoint set to t
//! is created, constrained before the timepoints that had to follow the old one, and the old one is relaxed.

use crate::model::Time;
use crate::plan::{ActionId, PartialPlan, PlanError};
use crate::stn::Timepoint;

/// When the report came.
#[derive(Copy, Clone, Eq, PartialEq, Debug, serde::Serialize, serde::Deserialize)]
pub enum Timing {
    InBounds,
    TooLate,
    TooEarly,
}

pub fn timing(plan: &PartialPlan, a: ActionId, t: Time) -> Timing {
    let et = plan.action(a).end;
    if t < plan.stn.lb(et) {
        Timing::TooEarly
    } else if t > plan.stn.ub(et) {
        Timing::TooLate
    } else {
        Timing::InBounds
    }
}

/// Integrates the report's time; `Ok(false)` when the plan is not executable any more (too late).
///
/// Too early: the old timepoint's constraints are removed (relaxed) and the timepoint is executed at t,
/// then constrained before every timepoint that directly followed it. Reusing the timepoint's identity for
/// the new end keeps the action's end events attached to it; the network is recomputed by the STN.
pub fn integrate(plan: &mut PartialPlan, a: ActionId, t: Time) -> Result<bool, PlanError> {
    let (st, et) = (plan.action(a).start, plan.action(a).end);
    match timing(plan, a, t) {
        Timing::TooLate => Ok(false),
        Timing::InBounds => {
            plan.stn.execute(et, t)?;
            Ok(true)
        }
        Timing::TooEarly => {
            let origin = plan.stn.origin();
            let followers: Vec<(Timepoint, Time)> = plan
                .stn
                .constraints_of(et)
                .filter_map(|(_, k)| {
                    (k.from == et && k.to != et && k.to != origin && k.to != st && k.lb >= 0)
                        .then_some((k.to, k.lb))
                })
                .filter(|&(s, _)| !plan.stn.is_executed(s))
                .collect();
            plan.stn.relax_timepoint(et);
            plan.stn.execute(et, t)?;
            for (s, lb) in followers {
                plan.stn.add_constraint(et, s, lb.max(0), crate::stn::INF)?;
            }
            plan.recompute_candidates();
            Ok(true)
        }
    }
}
