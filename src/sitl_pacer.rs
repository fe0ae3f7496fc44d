//! The in-process SITL on a manual clock, as a [`Pacer`]: deterministic missions as fast as the machine
//! goes (`demo`, `soak`, `run --sim`). It lives above the executive because it drives the `sitl` crate.

use std::time::Duration;

use crate::exec::clock::{wall_clock, SharedClock};
use crate::exec::cycle::mission_time as since;
use crate::exec::mission::Pacer;
use crate::exec::pacer::{LinkCounted, StepGate};
use crate::model::Time;
use crate::vehicle::{Vehicle, VehicleEvent};

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
    /// The companion's clock the waits are bounded on (a `ManualClock` in tests).
    wall: SharedClock,
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
            wall: wall_clock(),
        }
    }

    /// The clock that bounds the waits for the link (a `ManualClock` in tests).
    pub fn with_wall_clock(mut self, wall: SharedClock) -> Self {
        self.wall = wall;
        self
    }

    /// The end of a wait bounded by [`Self::bound`], µs on the companion's clock.
    fn deadline_us(&self) -> u64 {
        let bound = self.bound().as_micros().min(u64::MAX as u128) as u64;
        self.wall.now_us().saturating_add(bound)
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
        let deadline = self.deadline_us();
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
            if self.wall.now_us() >= deadline {
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
        let deadline = self.deadline_us();
        while v.link_counts().goal_batches < self.gate.promised() {
            if self.wall.now_us() >= deadline {
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
