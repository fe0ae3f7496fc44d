//! What ties the plan to this vehicle: the vehicle time of the plan's origin, the domain's names given a
//! vehicle meaning, where the vehicle may go, and its observed moving/still attribute. Set once the vehicle
//! is known (the builder, the mission's start); read by message integration and the act part.

use mavtempo_temporal::model::{AttrId, ObjectId, Time};
use mavtempo_vehicle::limits::Limits;

use crate::mapping::DomainMapping;

#[derive(Default)]
pub(crate) struct VehicleBinding {
    /// The vehicle time (ms) of the plan's origin.
    origin_ms: u64,
    /// Empty until set: positions are then ignored and uploaded goals rejected.
    pub(crate) mapping: DomainMapping,
    /// Where the vehicle may go: goals at places outside are refused at intake.
    limits: Option<Limits>,
    /// `[state] moving`: the attribute and its still value (src/executive/src/exec/still.rs).
    still: Option<(AttrId, ObjectId)>,
}

impl VehicleBinding {
    pub(crate) fn set_origin(&mut self, ms: u64) {
        self.origin_ms = ms;
    }

    pub(crate) fn origin_ms(&self) -> u64 {
        self.origin_ms
    }

    /// A vehicle time (ms) as mission time, within `[0, now]`.
    pub(crate) fn mission_time_until(&self, vehicle_ms: u64, now: Time) -> Time {
        (vehicle_ms.saturating_sub(self.origin_ms) as Time).clamp(0, now)
    }

    /// Empty limits are none.
    pub(crate) fn set_limits(&mut self, limits: Option<Limits>) {
        self.limits = limits.filter(|l| !l.is_empty());
    }

    pub(crate) fn limits(&self) -> Option<&Limits> {
        self.limits.as_ref()
    }

    pub(crate) fn set_still(&mut self, still: Option<(AttrId, ObjectId)>) {
        self.still = still;
    }

    pub(crate) fn still(&self) -> Option<(AttrId, ObjectId)> {
        self.still
    }
}
