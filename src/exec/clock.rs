//! Time is injected (DESIGN "Time is injected"): the executive reads the time from a [`Clock`], the vehicle's
//! clock in live runs (so a SITL at 200× drives the executive at 200×), a [`ManualClock`] in tests.

use std::cell::Cell;

use crate::model::Time;
use crate::vehicle::Vehicle;

/// The executive's time, in ms relative to the plan's origin.
pub trait Clock {
    fn now(&self) -> Time;
}

/// A clock moved by hand (deterministic tests).
#[derive(Debug, Default)]
pub struct ManualClock {
    now: Cell<Time>,
}

impl ManualClock {
    pub fn new(now: Time) -> Self {
        ManualClock {
            now: Cell::new(now),
        }
    }

    pub fn set(&self, t: Time) {
        self.now.set(t);
    }

    pub fn advance(&self, dt: Time) {
        self.now.set(self.now.get() + dt);
    }
}

impl Clock for ManualClock {
    fn now(&self) -> Time {
        self.now.get()
    }
}

/// The vehicle's clock (SYSTEM_TIME / time_boot_ms on a MAVLink link), shifted so that the plan's origin
/// is the vehicle time at which the mission started.
pub struct VehicleClock<'a, V: Vehicle> {
    pub vehicle: &'a V,
    pub origin_ms: u64,
}

impl<V: Vehicle> Clock for VehicleClock<'_, V> {
    fn now(&self) -> Time {
        super::cycle::mission_time(self.vehicle.now_ms(), self.origin_ms)
    }
}
