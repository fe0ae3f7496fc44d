//! The Vehicle trait: the executive's only view of a vehicle.

use std::time::Duration;

use super::goals::{GoalBatch, GoalCancel};
use super::types::{
    ActionReport, ActionStart, CapacityChange, LinkStatus, ResourceLevel, VehicleActionId,
};

/// Why a command to the vehicle could not even be issued (its outcome comes later, as a report).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum VehicleError {
    #[error("no binding for task `{0}` in the vehicle configuration")]
    UnknownTask(String),
    #[error("action {0} is already running")]
    AlreadyRunning(VehicleActionId),
    #[error("action {0} is not running")]
    NotRunning(VehicleActionId),
    #[error("task `{task}`: {reason}")]
    BadArguments { task: String, reason: String },
    #[error("vehicle link closed")]
    Closed,
    /// A mode the companion did not command, or a disarm: the operator has the vehicle.
    #[error("the operator has the vehicle: nothing is commanded until control is handed back")]
    Yielded,
}

/// Seed 1 §2.1: `START a p_a i_a`, `END i_a`, and the messages coming back.
pub trait Vehicle {
    /// `START a p_a i_a`.
    fn start(&mut self, action: ActionStart) -> Result<(), VehicleError>;
    /// `START` of a motion whose end the next action needs still (a picture): it ends once the vehicle is
    /// within its acceptance radius and still, not as it enters the radius. A vehicle that cannot tell
    /// starts it as any other.
    fn start_still(&mut self, action: ActionStart) -> Result<(), VehicleError> {
        self.start(action)
    }
    /// `END i_a`: stop an action (preemptive ones at their end; any running one when execution is aborted);
    /// an `Interrupted` report follows.
    fn stop(&mut self, id: VehicleActionId) -> Result<(), VehicleError>;
    /// The next pending event, without waiting.
    fn try_event(&mut self) -> Option<VehicleEvent>;
    /// The next event, waiting at most `timeout` (a mock never waits: it has a manual clock).
    fn wait_event(&mut self, timeout: Duration) -> Option<VehicleEvent>;
    /// The vehicle's clock in ms (SYSTEM_TIME / time_boot_ms on a live link): the executive's time.
    fn now_ms(&self) -> u64;
    /// Where the vehicle is, metres east and north of home, if it knows (the report's track).
    fn position(&self) -> Option<(f64, f64)> {
        None
    }
    /// How long the autopilot has been silent: time since its last HEARTBEAT (wall time on a live link, the
    /// manual clock on a mock). `None` until one is heard, or for a vehicle that cannot fall silent.
    fn silence(&self) -> Option<Duration> {
        None
    }
    /// How long ago [`Vehicle::now_ms`] last moved (wall time): a vehicle that stopped sending its time
    /// leaves the companion to keep the mission's clock. `None`: the clock cannot go stale (a mock).
    fn clock_age(&self) -> Option<Duration> {
        None
    }
}

/// Everything a vehicle tells the executive.
#[derive(Debug)]
pub enum VehicleEvent {
    Report(ActionReport),
    Resource(ResourceLevel),
    Capacity(CapacityChange),
    /// A goal list from a ground station, waiting for the executive's verdicts.
    Goals(GoalBatch),
    /// A ground station withdraws goals it uploaded, waiting for the executive to confirm.
    Cancel(GoalCancel),
    Link(LinkStatus),
    /// The companion yields to the operator, or control was handed back.
    Authority(super::authority::AuthorityEvent),
}
