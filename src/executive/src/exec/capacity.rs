//! Capacity alteration (seed 1 §3.3): an exogenous event changed a resource's capacity by q. The capacity is
//! updated; if the plan is not executable any more, execution is aborted; otherwise plan repair is requested
//! after a decrease, or after an increase of a reservoir.

use std::sync::Arc;

use super::executable::{flawed_actions, plan_executable};
use super::ledger::ResourceLedger;
use mavtempo_temporal::model::{ResourceId, ResourceKind, Time};
use mavtempo_temporal::plan::{ActionId, PartialPlan};

/// What the executive does next.
#[derive(Copy, Clone, Eq, PartialEq, Debug, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CapacityOutcome {
    Abort,
    Repair,
    Nothing,
}

impl std::fmt::Display for CapacityOutcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            CapacityOutcome::Abort => "abort",
            CapacityOutcome::Repair => "repair",
            CapacityOutcome::Nothing => "nothing",
        })
    }
}

/// Sets r's capacity to `capacity` from time t on; the ledger's level and the problem's are clipped to it.
pub fn alter(
    plan: &mut PartialPlan,
    ledger: &mut ResourceLedger,
    r: ResourceId,
    capacity: f64,
    t: Time,
    running: &[ActionId],
) -> CapacityOutcome {
    let mut problem = (**plan.problem()).clone();
    let Some(setup) = problem.resources.get_mut(r.index()) else {
        return CapacityOutcome::Nothing;
    };
    let old = setup.capacity_at(t);
    setup.profile.retain(|&(from, _)| from < t);
    setup.profile.push((t, capacity));
    ledger.clip_to_capacity(&mut problem, r, capacity);
    plan.set_resource_problem(Arc::new(problem));
    let flawed = flawed_actions(plan);
    if !plan_executable(running, &flawed) {
        CapacityOutcome::Abort
    } else if capacity < old || plan.domain().resource(r).kind == ResourceKind::Reservoir {
        CapacityOutcome::Repair
    } else {
        CapacityOutcome::Nothing
    }
}
