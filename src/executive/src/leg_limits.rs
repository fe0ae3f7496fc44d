//! The vehicle's limits as the planner sees them. Here, in the layer that knows both, so that the vehicle
//! crate knows nothing of the planner.

use std::sync::Arc;

use mavtempo_temporal::model::{LegLimits, Legs};
use mavtempo_vehicle::limits::Limits;
use mavtempo_vehicle::Enu;

/// [`Limits`] as the planner's [`LegLimits`]: whether it may plan a straight leg between two places.
#[derive(Debug)]
struct PlannerLimits(Limits);

impl LegLimits for PlannerLimits {
    fn allows(&self, a: (f64, f64), b: (f64, f64)) -> bool {
        self.0
            .check_leg(Enu::new(a.0, a.1, 0.0), Enu::new(b.0, b.1, 0.0))
            .is_ok()
    }
}

/// A problem's legs kept within `limits`.
pub fn legs_within(limits: &Limits) -> Legs {
    Legs(Some(Arc::new(PlannerLimits(limits.clone()))))
}
