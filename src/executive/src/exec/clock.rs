//! The executive's clock (seed 1 §3.2: time is injected): mission time, ms since the plan's origin. The
//! mission loop reads its pacer (the vehicle's clock, a SITL's, or a manual one); a cycle's plan repair
//! reads the vehicle's ([`VehicleClock`]), complete replanning the pacer's, to stop at their budgets (μ·ts,
//! the time limit l). Tests move a [`ManualClock`] by hand, or give a closure. [`WallClock`] is the
//! companion's own time, for the bounds that must hold whatever mission time does (a cycle's
//! `cycle_max_wall_ms`, a replanning's `replan_max_wall_ms`, a wait on a vehicle whose clock may stop, the
//! per-part timings): the executive and the pacers hold it as a [`SharedClock`], a `WallClock` in production
//! and a `ManualClock` in tests (docs/executive-state.md, "One clock").

use std::sync::atomic::{AtomicI64, Ordering};
use std::sync::Arc;

use mavtempo_temporal::model::Time;
use mavtempo_vehicle::Vehicle;

/// Mission time, ms since the plan's origin.
pub trait Clock {
    fn now(&self) -> Time;

    /// The same time in µs, for measuring the parts of a cycle; a clock with ms resolution says ms·1000.
    fn now_us(&self) -> u64 {
        self.now().max(0) as u64 * 1000
    }
}

/// A clock shared by whoever reads it (the executive, a pacer) and, in tests, the hand that moves it.
pub type SharedClock = Arc<dyn Clock + Send + Sync>;

/// The companion's own clock, started now: what production gives the executive and the pacers.
pub fn wall_clock() -> SharedClock {
    Arc::new(WallClock::start())
}

/// Any `Fn() -> Time` is a clock (e.g. `&|| 0`, a clock that does not move).
impl<F: Fn() -> Time> Clock for F {
    fn now(&self) -> Time {
        self()
    }
}

/// Vehicle ms → ms since the plan's origin (the vehicle time `origin_ms`).
pub fn mission_time(vehicle_ms: u64, origin_ms: u64) -> Time {
    vehicle_ms.saturating_sub(origin_ms).min(i64::MAX as u64) as Time
}

/// Mission time on a vehicle's clock (its last time, e.g. SYSTEM_TIME, or a mock's manual time).
pub struct VehicleClock<'a> {
    vehicle: &'a dyn Vehicle,
    origin_ms: u64,
}

impl<'a> VehicleClock<'a> {
    /// `origin_ms`: the vehicle time of the plan's origin.
    pub fn new(vehicle: &'a dyn Vehicle, origin_ms: u64) -> Self {
        VehicleClock { vehicle, origin_ms }
    }
}

impl Clock for VehicleClock<'_> {
    fn now(&self) -> Time {
        mission_time(self.vehicle.now_ms(), self.origin_ms)
    }
}

/// The companion's own time, ms since [`WallClock::start`]: what bounds a wait on a vehicle whose clock
/// may stop (a vanished link) and a cycle's or a replanning's computation, never what the plan is executed on.
#[derive(Clone, Copy, Debug)]
pub struct WallClock(std::time::Instant);

impl WallClock {
    pub fn start() -> Self {
        WallClock(std::time::Instant::now())
    }
}

impl Clock for WallClock {
    fn now(&self) -> Time {
        self.0.elapsed().as_millis().min(i64::MAX as u128) as Time
    }

    fn now_us(&self) -> u64 {
        self.0.elapsed().as_micros().min(u64::MAX as u128) as u64
    }
}

/// A clock moved by hand: it reads what it was last set to. Clones are handles on one clock, so a test
/// keeps one to move the clock that it gave the executive or a pacer.
#[derive(Clone, Debug, Default)]
pub struct ManualClock(Arc<AtomicI64>);

impl ManualClock {
    pub fn new(at: Time) -> Self {
        ManualClock(Arc::new(AtomicI64::new(at)))
    }

    pub fn set(&self, at: Time) {
        self.0.store(at, Ordering::SeqCst);
    }

    /// Moves the clock `by` ms on.
    pub fn advance(&self, by: Time) {
        let _ = self
            .0
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |t| {
                Some(t.saturating_add(by))
            });
    }

    /// This clock as the executive or a pacer holds it.
    pub fn shared(&self) -> SharedClock {
        Arc::new(self.clone())
    }
}

impl Clock for ManualClock {
    fn now(&self) -> Time {
        self.0.load(Ordering::SeqCst)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_manual_clock_reads_what_it_was_set_to_and_a_closure_is_a_clock() {
        let c = ManualClock::new(5);
        assert_eq!(c.now(), 5);
        c.advance(1_300);
        assert_eq!(c.now(), 1_305);
        c.set(42);
        let as_dyn: &dyn Clock = &c;
        assert_eq!(as_dyn.now(), 42);
        let fixed: &dyn Clock = &|| 7;
        assert_eq!(fixed.now(), 7);
    }

    #[test]
    fn a_shared_manual_clock_moves_for_every_holder() {
        let hand = ManualClock::new(0);
        let held = hand.shared();
        hand.advance(250);
        assert_eq!(held.now(), 250);
        assert_eq!(held.now_us(), 250_000);
    }
}
