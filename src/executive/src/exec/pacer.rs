//! The [`Pacer`]s of a mission: how time passes between cycles. A live vehicle's clock (possibly a SITL at a
//! speed-up) or MockVehicle's manual clock (tests). The SITL stepped by hand (deterministic, as fast as the
//! machine goes) drives the `sitl` crate, so it is the application's (`mavtempo::sitl_pacer`).

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use super::clock::{mission_time as since, wall_clock, Clock, SharedClock, VehicleClock};
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
        VehicleClock::new(v, self.origin_ms).now()
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
/// vehicle's clock comes back behind it. A wait is bounded on the companion's clock (`wall`, a `WallClock`
/// unless [`LivePacer::with_wall_clock`] gives another).
pub struct LivePacer {
    pub origin_ms: u64,
    pub speedup: f64,
    pub stale_after: Duration,
    /// The latest mission time given: the clock never goes back.
    last: std::cell::Cell<Time>,
    wall: SharedClock,
}

impl std::fmt::Debug for LivePacer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LivePacer")
            .field("origin_ms", &self.origin_ms)
            .field("speedup", &self.speedup)
            .field("stale_after", &self.stale_after)
            .field("last", &self.last.get())
            .finish_non_exhaustive()
    }
}

impl LivePacer {
    pub fn new(origin_ms: u64, speedup: f64, stale_after: Duration) -> Self {
        LivePacer {
            origin_ms,
            speedup,
            stale_after,
            last: std::cell::Cell::new(0),
            wall: wall_clock(),
        }
    }

    /// The clock that bounds a wait (a `ManualClock` in tests).
    pub fn with_wall_clock(mut self, wall: SharedClock) -> Self {
        self.wall = wall;
        self
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
        self.wait_until(v, until, None)
    }

    fn wait_or_interrupt(
        &mut self,
        v: &mut V,
        until: Time,
        interrupt: &Interrupt,
    ) -> Option<VehicleEvent> {
        self.wait_until(v, until, Some(interrupt))
    }
}

/// How often a live wait looks for an interrupt: a timestep at 1× is a second or more of wall time, too
/// long to ignore a signal.
const INTERRUPT_POLL: Duration = Duration::from_millis(50);

/// The shortest wall wait while the vehicle's clock has not reached the wake-up time yet.
const CLOCK_POLL: Duration = Duration::from_millis(1);

/// How long past the expected wall time a wait holds for a vehicle clock that does not get there.
const CLOCK_GRACE: Duration = Duration::from_millis(500);

impl LivePacer {
    /// Returns at the first vehicle event, once mission time reaches `until`, or on an interrupt. Seed 1
    /// §3.2: the executive wakes when it has something to do. The vehicle's clock moves only when a frame
    /// carries it, so a wake-up due between two frames waits for the clock to get there rather than cycle
    /// again at an unchanged time (Dala at 10×: 362 idle cycles at one vehicle time before this loop).
    fn wait_until<V: Vehicle>(
        &self,
        v: &mut V,
        until: Time,
        interrupt: Option<&Interrupt>,
    ) -> Option<VehicleEvent> {
        // A clock that stops (a vanished vehicle under a pacer that never calls it stale) still gives the
        // executive its cycle, to notice the silence.
        let bound = self.wall_left(v, until) + CLOCK_GRACE;
        let give_up = self
            .wall
            .now_us()
            .saturating_add(bound.as_micros().min(u64::MAX as u128) as u64);
        loop {
            if Pacer::now(self, v) >= until || self.wall.now_us() >= give_up {
                return None;
            }
            let mut slice = self.wall_left(v, until).max(CLOCK_POLL);
            if interrupt.is_some() {
                slice = slice.min(INTERRUPT_POLL);
            }
            if let Some(e) = v.wait_event(slice) {
                return Some(e);
            }
            if interrupt.is_some_and(|i| i.requested().is_some()) {
                return None;
            }
        }
    }

    /// The wall time until mission time `until`, from the vehicle's last clock carried on by the wall time
    /// since the frame that brought it (mission time itself waits for the next frame).
    fn wall_left<V: Vehicle>(&self, v: &V, until: Time) -> Duration {
        let speedup = self.speedup.max(1e-3);
        let carried = v
            .clock_age()
            .map_or(0, |age| (age.as_secs_f64() * 1000.0 * speedup) as u64);
        let now = since(v.now_ms().saturating_add(carried), self.origin_ms).max(self.last.get());
        let left = (until - now).max(0) as f64 / speedup;
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
    use mavtempo_vehicle::{ActionStart, VehicleActionId, VehicleError};

    /// A vehicle whose clock stopped at `ms`, `age` ago.
    struct Stopped {
        ms: u64,
        age: Duration,
    }

    impl Vehicle for Stopped {
        fn start(&mut self, _: ActionStart) -> Result<(), VehicleError> {
            Ok(())
        }
        fn stop(&mut self, _: VehicleActionId) -> Result<(), VehicleError> {
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

    /// A vehicle whose clock comes in frames every `frame_ms` of its time, at `speedup`, on a virtual wall
    /// clock that a wait moves on.
    struct Framed {
        wall_us: std::cell::Cell<u64>,
        frame_ms: u64,
        speedup: u64,
        waits: usize,
    }

    impl Framed {
        fn true_ms(&self) -> u64 {
            self.wall_us.get() * self.speedup / 1000
        }
    }

    impl Vehicle for Framed {
        fn start(&mut self, _: ActionStart) -> Result<(), VehicleError> {
            Ok(())
        }
        fn stop(&mut self, _: VehicleActionId) -> Result<(), VehicleError> {
            Ok(())
        }
        fn try_event(&mut self) -> Option<VehicleEvent> {
            None
        }
        fn wait_event(&mut self, timeout: Duration) -> Option<VehicleEvent> {
            self.waits += 1;
            self.wall_us
                .set(self.wall_us.get() + timeout.as_micros() as u64);
            None
        }
        fn now_ms(&self) -> u64 {
            self.true_ms() / self.frame_ms * self.frame_ms
        }
        fn clock_age(&self) -> Option<Duration> {
            let behind_ms = self.true_ms() - self.now_ms();
            Some(Duration::from_micros(behind_ms * 1000 / self.speedup))
        }
    }

    #[test]
    fn a_wake_up_between_two_clock_frames_waits_for_the_clock_to_get_there() {
        // Frames every second of vehicle time at 10x; the executive wants to wake 1 ms after the last frame.
        let mut v = Framed {
            wall_us: std::cell::Cell::new(5_000_000),
            frame_ms: 1000,
            speedup: 10,
            waits: 0,
        };
        let mut p = LivePacer::new(0, 10.0, Duration::from_secs(3));
        let now = Pacer::now(&p, &v);
        assert_eq!(now, 50_000);
        assert!(Pacer::wait(&mut p, &mut v, now + 1).is_none());
        // Back only once the vehicle's clock moved past the wake-up time, at the next frame: 100 ms of wall
        // time polled in CLOCK_POLL slices, no executive cycle in between.
        assert_eq!(Pacer::now(&p, &v), 51_000);
        assert!(v.waits <= 101, "{} waits", v.waits);
    }

    #[test]
    fn a_wait_on_a_vehicle_clock_that_stopped_gives_up_on_the_companion_clock() {
        // The vehicle's clock stopped at 10 s and is never called stale: the wait for 12 s (2 s of wall
        // time at 1x, plus the grace) ends on the companion's clock, a manual one moved 100 ms per read.
        let hand = super::super::clock::ManualClock::new(0);
        let ticking = hand.clone();
        let mut p = LivePacer::new(0, 1.0, Duration::from_secs(3600)).with_wall_clock(
            std::sync::Arc::new(move || {
                ticking.advance(100);
                ticking.now()
            }),
        );
        let mut v = Stopped {
            ms: 10_000,
            age: Duration::ZERO,
        };
        assert!(Pacer::wait(&mut p, &mut v, 12_000).is_none());
        let waited = hand.now();
        assert!((2_500..=2_700).contains(&waited), "{waited} ms");
        assert_eq!(Pacer::now(&p, &v), 10_000);
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
