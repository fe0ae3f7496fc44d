//! A report's arrival time against its end timepoint (seed 1 §3.3 "Report"): inside `[et_lb, et_ub]` it fixes
//! `et = t`; too late, the plan is not executable any more (timeout); too early, a new end timepoint set to t
//! is created, constrained before the timepoints that had to follow the old one, and the old one is relaxed.

use mavtempo_temporal::model::Time;
use mavtempo_temporal::plan::{ActionId, PartialPlan, PlanError};

/// When the report came.
#[derive(Copy, Clone, Eq, PartialEq, Debug, serde::Serialize, serde::Deserialize)]
pub enum Timing {
    InBounds,
    TooLate,
    TooEarly,
}

impl std::fmt::Display for Timing {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Timing::InBounds => "in time",
            Timing::TooLate => "later than planned",
            Timing::TooEarly => "earlier than planned",
        })
    }
}

pub fn timing(plan: &PartialPlan, a: ActionId, t: Time) -> Timing {
    let et = plan.action(a).end;
    if t < plan.earliest(et) {
        Timing::TooEarly
    } else if t > plan.latest(et) {
        Timing::TooLate
    } else {
        Timing::InBounds
    }
}

/// Integrates the report's time; `Ok(false)` when the plan is not executable any more (too late).
///
/// Too early: the old timepoint's constraints are removed (relaxed) and the timepoint is executed at t,
/// then constrained before every timepoint that directly followed it
/// ([`PartialPlan::execute_end_early`]).
pub fn integrate(plan: &mut PartialPlan, a: ActionId, t: Time) -> Result<bool, PlanError> {
    let et = plan.action(a).end;
    match timing(plan, a, t) {
        Timing::TooLate => Ok(false),
        Timing::InBounds => {
            plan.execute_at(et, t)?;
            Ok(true)
        }
        Timing::TooEarly => {
            plan.execute_end_early(a, t)?;
            Ok(true)
        }
    }
}
