//! The [`Pacer`]s of a mission: how time passes between cycles. A live vehicle's clock (possibly a SITL at a
//! speed-up), a SITL stepped by hand (deterministic, as fast as the machine goes), or MockVehicle's manual
//! clock (tests).

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use super::cycle::mission_time as since;
use super::interrupt::Interrupt;
use super::mission::Pacer;
use crate::model::Time;
use crate::vehicle::link::LinkCounts;
use crate::vehicle::{MavlinkVehicle, MockVehicle, Vehicle, VehicleEvent};

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
        let left =
            (until - since(v.now_ms(), self.origin_ms)).max(1) as f64 / self.speedup.max(1e-3);
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

    fn promised(&self) -> u64 {
        self.promised.load(Ordering::Acquire)
    }
}

/// The in-process SITL on a manual clock: the executive's time is the simulator's; waiting steps the
/// simulator. The exchange is reproducible run after run: before a step, the simulator has handled every
/// frame the companion produced and the companion every frame the simulator sent (nothing in flight, frame
/// counts on both sides agree); after the step, the companion has handled everything the step produced; a
/// goal upload the gate was told about reaches the executive before the next step. Every wait is bounded by
/// `settle` of wall time (then a warning, and the run goes on, no longer reproducible, with short waits).
pub struct SitlStepPacer {
    pub sim: std::sync::Arc<sitl::SimHandle>,
    pub runtime: tokio::runtime::Handle,
    pub origin_ms: u64,
    /// Largest step, ms of sim time (what happens inside a step is seen at its end).
    pub max_step_ms: u64,
    /// Wall-time bound of each wait for the link to settle or for a promised upload.
    pub settle: Duration,
    pub gate: std::sync::Arc<StepGate>,
    /// Set once a wait ran out: the link is broken or stalled, later waits are kept short (a stalled link
    /// must not cost `settle` per cycle).
    stalled: std::cell::Cell<bool>,
}

/// The bound of the waits once the link has stalled.
const STALLED_WAIT: Duration = Duration::from_millis(20);

impl SitlStepPacer {
    /// Steps of at most `max_step_ms`, waits bounded by `settle` of wall time.
    pub fn new(
        sim: std::sync::Arc<sitl::SimHandle>,
        runtime: tokio::runtime::Handle,
        origin_ms: u64,
        max_step_ms: u64,
        settle: Duration,
        gate: std::sync::Arc<StepGate>,
    ) -> Self {
        SitlStepPacer {
            sim,
            runtime,
            origin_ms,
            max_step_ms,
            settle,
            gate,
            stalled: std::cell::Cell::new(false),
        }
    }

    fn bound(&self) -> Duration {
        if self.stalled.get() {
            STALLED_WAIT.min(self.settle)
        } else {
            self.settle
        }
    }

    /// Waits until nothing is in flight between the companion and the simulator: the companion has handled
    /// every frame the simulator sent and the simulator every frame the companion produced, with the
    /// simulator's count read again last (a reply to the companion's last frames would show there).
    fn settle<V: LinkCounted>(&self, v: &V) -> bool {
        let deadline = Instant::now() + self.bound();
        loop {
            let sim_sent = self.sim.frames_sent();
            let link = v.link_counts();
            let sim_received = self.sim.frames_received();
            if link.received == sim_sent
                && sim_received == link.sent
                && self.sim.frames_sent() == sim_sent
            {
                return true;
            }
            if Instant::now() >= deadline {
                self.stalled.set(true);
                tracing::warn!(
                    sim_sent,
                    sim_received,
                    link_sent = link.sent,
                    link_received = link.received,
                    "sitl step: the link did not settle; the run is no longer reproducible"
                );
                return false;
            }
            std::thread::sleep(Duration::from_micros(50));
        }
    }

    /// Settles the link, steps the simulator by `dt_ms` and settles the link again (events stay in the
    /// vehicle's channel). Returns the new sim time.
    pub fn step_settled<V: LinkCounted>(&self, v: &V, dt_ms: u64) -> Result<u64, sitl::SimError> {
        self.settle(v);
        let t = self
            .runtime
            .block_on(self.sim.step(Duration::from_millis(dt_ms)))?;
        self.settle(v);
        Ok(t)
    }

    /// Waits (bounded) until the goal batches the gate was promised are in the executive's channel (not
    /// taken: the next cycle integrates them with the rest).
    fn promised<V: LinkCounted>(&self, v: &V) {
        let deadline = Instant::now() + self.bound();
        while v.link_counts().goal_batches < self.gate.promised() {
            if Instant::now() >= deadline {
                self.stalled.set(true);
                tracing::warn!("sitl step: a promised goal upload did not arrive; stepping on");
                self.gate.cancel_goal_batch();
                return;
            }
            std::thread::sleep(Duration::from_micros(200));
        }
    }
}

impl<V: Vehicle + LinkCounted> Pacer<V> for SitlStepPacer {
    fn origin_ms(&self) -> u64 {
        self.origin_ms
    }

    fn now(&self, _v: &V) -> Time {
        since(self.sim.now_ms(), self.origin_ms)
    }

    fn wait(&mut self, v: &mut V, until: Time) -> Option<VehicleEvent> {
        // What the last cycle's commands caused, and a promised upload, come first, at the current sim time.
        self.settle(v);
        self.promised(v);
        if let Some(e) = v.try_event() {
            return Some(e);
        }
        let target = self.origin_ms + until.max(0) as u64;
        let dt = target
            .saturating_sub(self.sim.now_ms())
            .clamp(1, self.max_step_ms);
        if let Err(e) = self.step_settled(v, dt) {
            tracing::warn!("sitl step: {e}");
            return None;
        }
        v.try_event()
    }
}
