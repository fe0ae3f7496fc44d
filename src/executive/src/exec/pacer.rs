//! The [`Pacer`]s of a mission: how time passes between cycles. A live vehicle's clock (possibly a SITL at a
//! speed-up) or MockVehicle's manual clock (tests). The SITL stepped by hand (deterministic, as fast as the
//! machine goes) drives the `sitl` crate, so it is the application's (`mavtempo::sitl_pacer`).

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use super::cycle::mission_time as since;
use super::interrupt::Interrupt;
use super::mission::Pacer;
use mavtempo_temporal::model::Time;
use mavtempo_vehicle::link::LinkCounts;
use mavtempo_vehicle::{MavlinkVehicle, MockVehicle, Vehicle, VehicleEvent};

/// MockVehicle's manual clock: waiting jumps to the next scripted event or to `until`.
#[derive(Debug, Default)]
pub struct MockPacer {
    /// The vehicle time (ms) of the plan's origin.
    pub origin_ms: u64,
}

impl Pacer<MockVehicle> for MockPacer {
    fn origin_ms(&self) -> u64 {
        self.origin_ms
    }
    fn now(&self, v: &MockVehicle) -> Time {
        since(v.now_ms(), self.origin_ms)
    }

    fn wait(&mut self, v: &mut MockVehicle, until: Time) -> Option<VehicleEvent> {
        if let Some(e) = v.try_event() {
            return Some(e);
        }
        let until = self.origin_ms + until.max(0) as u64;
        let to = v.next_due_ms().map_or(until, |d| d.min(until));
        v.advance_to(to);
        v.try_event()
    }
}

/// A live vehicle: the executive's time is the vehicle's clock (SYSTEM_TIME / time_boot_ms), the wait a
/// blocking receive. `speedup` converts the vehicle's ms into wall ms (a SITL at 100× needs 10 ms of wall
/// time for a second). A vehicle that stops sending its time (silent, vanished) does not stop the mission's
/// clock: once the vehicle's clock has not moved for `stale_after` of wall time, mission time runs on the
/// companion's wall clock (times `speedup`) from the vehicle's last time, and never goes back when the
/// vehicle's clock comes back behind it.
#[derive(Debug)]
pub struct LivePacer {
    pub origin_ms: u64,
    pub speedup: f64,
    pub stale_after: Duration,
    /// The latest mission time given: the clock never goes back.
    last: std::cell::Cell<Time>,
}

impl LivePacer {
    pub fn new(origin_ms: u64, speedup: f64, stale_after: Duration) -> Self {
        LivePacer {
            origin_ms,
            speedup,
            stale_after,
            last: std::cell::Cell::new(0),
        }
    }

    /// The vehicle's time, or the companion's estimate of it while the vehicle's clock is stale.
    fn vehicle_ms<V: Vehicle>(&self, v: &V) -> u64 {
        let ms = v.now_ms();
        match v.clock_age() {
            Some(age) if age > self.stale_after => {
                ms.saturating_add((age.as_secs_f64() * 1000.0 * self.speedup.max(1e-3)) as u64)
            }
            _ => ms,
        }
    }
}

impl<V: Vehicle> Pacer<V> for LivePacer {
    fn origin_ms(&self) -> u64 {
        self.origin_ms
    }
    fn now(&self, v: &V) -> Time {
        let t = since(self.vehicle_ms(v), self.origin_ms).max(self.last.get());
        self.last.set(t);
        t
    }

    fn wait(&mut self, v: &mut V, until: Time) -> Option<VehicleEvent> {
        v.wait_event(self.wall_left(v, until))
    }

    fn wait_or_interrupt(
        &mut self,
        v: &mut V,
        until: Time,
        interrupt: &Interrupt,
    ) -> Option<VehicleEvent> {
        // In slices: a timestep at 1× is a second or more of wall time, too long to ignore a signal.
        let deadline = Instant::now() + self.wall_left(v, until);
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            if let Some(e) = v.wait_event(left.min(INTERRUPT_POLL)) {
                return Some(e);
            }
            if interrupt.requested().is_some() || Instant::now() >= deadline {
                return None;
            }
        }
    }
}

/// How often a live wait looks for an interrupt.
const INTERRUPT_POLL: Duration = Duration::from_millis(50);

impl LivePacer {
    /// The wall time until mission time `until`.
    fn wall_left<V: Vehicle>(&self, v: &V, until: Time) -> Duration {
        let left = (until - Pacer::now(self, v)).max(1) as f64 / self.speedup.max(1e-3);
        Duration::from_micros((left * 1000.0).ceil() as u64)
    }
}

/// Counts of the frames a vehicle exchanged with its autopilot (see [`MavlinkVehicle::link_counts`]).
pub trait LinkCounted {
    fn link_counts(&self) -> LinkCounts;
}

impl LinkCounted for MavlinkVehicle {
    fn link_counts(&self) -> LinkCounts {
        MavlinkVehicle::link_counts(self)
    }
}

/// Goal uploads from outside the simulator (a ground station's, started by the caller) that the stepped
/// simulator waits for before moving on, so that they reach the executive at a fixed sim time: the batches
/// promised so far, compared with those the vehicle link handed to the executive.
#[derive(Debug, Default)]
pub struct StepGate {
    promised: AtomicU64,
}

impl StepGate {
    /// One more goal batch is on its way to the executive (an upload was started).
    pub fn expect_goal_batch(&self) {
        self.promised.fetch_add(1, Ordering::AcqRel);
    }

    /// A promised batch will not come (its upload failed before reaching the executive).
    pub fn cancel_goal_batch(&self) {
        let _ = self
            .promised
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |n| n.checked_sub(1));
    }

    pub fn promised(&self) -> u64 {
        self.promised.load(Ordering::Acquire)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavtempo_vehicle::{ActionId, ActionStart, VehicleError};

    /// A vehicle whose clock stopped at `ms`, `age` ago.
    struct Stopped {
        ms: u64,
        age: Duration,
    }

    impl Vehicle for Stopped {
        fn start(&mut self, _: ActionStart) -> Result<(), VehicleError> {
            Ok(())
        }
        fn stop(&mut self, _: ActionId) -> Result<(), VehicleError> {
            Ok(())
        }
        fn try_event(&mut self) -> Option<VehicleEvent> {
            None
        }
        fn wait_event(&mut self, _: Duration) -> Option<VehicleEvent> {
            None
        }
        fn now_ms(&self) -> u64 {
            self.ms
        }
        fn clock_age(&self) -> Option<Duration> {
            Some(self.age)
        }
    }

    #[test]
    fn a_stale_vehicle_clock_is_carried_on_by_the_companion_and_never_goes_back() {
        let p = LivePacer::new(1_000, 10.0, Duration::from_secs(3));
        let mut v = Stopped {
            ms: 121_000,
            age: Duration::from_secs(1),
        };
        // Fresh enough: the vehicle's own time.
        assert_eq!(p.now(&v), 120_000);
        // Stale: its last time plus the wall time since, at the speed-up.
        v.age = Duration::from_secs(4);
        assert_eq!(p.now(&v), 160_000);
        // The vehicle speaks again with a time behind the estimate: the clock holds, then follows it.
        v = Stopped {
            ms: 150_000,
            age: Duration::ZERO,
        };
        assert_eq!(p.now(&v), 160_000);
        v.ms = 171_000;
        assert_eq!(p.now(&v), 170_000);
    }
}
