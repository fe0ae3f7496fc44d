//! The [`Pacer`]s of a mission: how time passes between cycles. A live vehicle's clock (possibly a SITL at a
//! speed-up), a SITL stepped by hand (deterministic, as fast as the machine goes), or MockVehicle's manual
//! clock (tests).

use std::time::{Duration, Instant};

use super::cycle::mission_time as since;
use super::mission::Pacer;
use crate::model::Time;
use crate::vehicle::{MockVehicle, Vehicle, VehicleEvent};

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
/// time for a second).
#[derive(Debug)]
pub struct LivePacer {
    pub origin_ms: u64,
    pub speedup: f64,
}

impl<V: Vehicle> Pacer<V> for LivePacer {
    fn origin_ms(&self) -> u64 {
        self.origin_ms
    }
    fn now(&self, v: &V) -> Time {
        since(v.now_ms(), self.origin_ms)
    }

    fn wait(&mut self, v: &mut V, until: Time) -> Option<VehicleEvent> {
        let left = (until - self.now(v)).max(1) as f64 / self.speedup.max(1e-3);
        v.wait_event(Duration::from_micros((left * 1000.0).ceil() as u64))
    }
}

/// The in-process SITL on a manual clock: the executive's time is the simulator's; waiting steps the
/// simulator, then lets the link deliver what the step produced (telemetry, reports) before the next cycle.
/// Deterministic up to the sockets, and as fast as the machine goes.
pub struct SitlStepPacer {
    pub sim: std::sync::Arc<sitl::SimHandle>,
    pub runtime: tokio::runtime::Handle,
    pub origin_ms: u64,
    /// Largest step, ms of sim time (what happens inside a step is seen at its end).
    pub max_step_ms: u64,
    /// The vehicle's clock comes from telemetry sent every this many ms of sim time.
    pub telemetry_period_ms: u64,
    /// How long (wall) to wait for the vehicle's clock to catch up with the sim after a step.
    pub settle: Duration,
}

impl<V: Vehicle> Pacer<V> for SitlStepPacer {
    fn origin_ms(&self) -> u64 {
        self.origin_ms
    }

    fn now(&self, _v: &V) -> Time {
        since(self.sim.now_ms(), self.origin_ms)
    }

    fn wait(&mut self, v: &mut V, until: Time) -> Option<VehicleEvent> {
        if let Some(e) = v.try_event() {
            return Some(e);
        }
        let target = self.origin_ms + until.max(0) as u64;
        let dt = target
            .saturating_sub(self.sim.now_ms())
            .clamp(1, self.max_step_ms);
        let sim_now = match self
            .runtime
            .block_on(self.sim.step(Duration::from_millis(dt)))
        {
            Ok(t) => t,
            Err(e) => {
                tracing::warn!("sitl step: {e}");
                return None;
            }
        };
        let deadline = Instant::now() + self.settle;
        loop {
            if let Some(e) = v.try_event() {
                return Some(e);
            }
            let caught_up = v.now_ms() + self.telemetry_period_ms > sim_now;
            if caught_up || Instant::now() >= deadline {
                return v.wait_event(Duration::from_millis(1));
            }
            if let Some(e) = v.wait_event(Duration::from_millis(2)) {
                return Some(e);
            }
        }
    }
}
