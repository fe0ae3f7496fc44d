//! Why things ended as they did, typed so that callers and tests match on the case: why execution was
//! aborted ([`AbortReason`]) and why a goal has its fate ([`FateReason`]). Display gives the trace's texts.

use serde::{Deserialize, Serialize};

use super::goal_request::Rejection;
use mavtempo_temporal::model::Time;

/// Why execution was aborted (the cycle stops, a complete replanning follows, seed 1 §3.6).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, thiserror::Error)]
#[serde(tag = "cause", rename_all = "snake_case")]
pub enum AbortReason {
    /// §3.3 capacity alteration: the plan is not executable with the new capacity.
    #[error("capacity of {resource} altered")]
    CapacityAltered { resource: String },
    /// §3.3 report after its end's upper bound.
    #[error("report of {action} too late")]
    ReportTooLate { action: String },
    #[error("report of {action}: {error}")]
    ReportInconsistent { action: String, error: String },
    /// §3.3 resource level: Definition 5 fails after the level's constraint.
    #[error("{resource} level {level} outside the plan's bounds")]
    LevelOutOfBounds { resource: String, level: f64 },
    /// The repair tree's root: timepoints not executed yet cannot all be after now.
    #[error("plan not executable at {now_ms} ms: {error}")]
    NotExecutable { now_ms: Time, error: String },
    #[error("plan repair did not converge within {steps} steps")]
    RepairDiverged { steps: u64 },
    #[error("plan repair failed: {failure}{}", last_dead_end(dead_end))]
    RepairFailed {
        failure: String,
        dead_end: Option<String>,
    },
    #[error("cannot start {action}: {error}")]
    CannotInstantiate {
        action: String,
        error: super::instantiate::InstantiateError,
    },
    #[error("cannot start {action}: {error}")]
    StartRefused { action: String, error: String },
    #[error("start of {action}: {error}")]
    StartInconsistent { action: String, error: String },
    /// A banned action instance is due to start (src/executive/src/exec/failures.rs).
    #[error("{instance} is not launched again: {ban}")]
    LaunchBanned { instance: String, ban: String },
    /// An action instance failed the same way k times in a row: it is banned.
    #[error("{ban}: not tried again")]
    InstanceBanned { ban: String },
    #[error("{0}")]
    PlanChurn(PlanChurn),
    /// A timepoint's upper bound passed unexecuted.
    #[error("timeout on {timepoint}")]
    Timeout { timepoint: String },
    /// A complete replanning asked for with no abort recorded.
    #[error("execution aborted")]
    Unstated,
    /// The operator handed control back: the plan is made again from where the vehicle is.
    #[error("control handed back ({how})")]
    ControlReturned { how: String },
    /// The vehicle is not where the plan starts (src/executive/src/exec/authority.rs).
    #[error("the vehicle is {distance_m:.1} m from where the plan has it")]
    VehicleElsewhere { distance_m: f64 },
}

/// `; the last dead end: …` or nothing.
fn last_dead_end(d: &Option<String>) -> String {
    d.as_ref()
        .map_or(String::new(), |d| format!("; the last dead end: {d}"))
}

/// Too many plan changes within a minute of mission time, and the most failing instance meanwhile.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanChurn {
    pub changes: usize,
    /// The instance that failed (else was launched) most meanwhile and how many times.
    pub failing: Option<(String, usize)>,
    /// `failed` or `launched`: what `failing` did that many times.
    #[serde(default = "failed")]
    pub how: String,
}

fn failed() -> String {
    "failed".to_string()
}

impl std::fmt::Display for PlanChurn {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the plan changed {} times within a minute of mission time",
            self.changes
        )?;
        if let Some((inst, k)) = &self.failing {
            write!(f, "; {inst} {} {k} times meanwhile", self.how)?;
        }
        Ok(())
    }
}

/// Why a goal has its fate: why it was rejected (at intake, by its insertion attempt, by the failure
/// memory, by a complete replanning) or why it is still pending.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, thiserror::Error)]
#[serde(tag = "cause", rename_all = "snake_case")]
pub enum FateReason {
    /// The request cannot be read as a domain goal (the config's `[mapping]`).
    #[error("{0}")]
    Unmapped(crate::mapping::MappingError),
    /// §3.3 goal request acceptance test.
    #[error("{0}")]
    Acceptance(Rejection),
    /// The executing plan could not root the insertion attempt.
    #[error("plan not executable at {now_ms} ms: {error}")]
    NotExecutable { now_ms: Time, error: String },
    /// The insertion attempt's search ended without a plan.
    #[error(
        "plan repair found no plan with it ({failure}{}); the plan is kept as it was",
        last_dead_end(dead_end)
    )]
    InsertionFailed {
        failure: String,
        dead_end: Option<String>,
    },
    /// The insertion attempt's cycles are spent.
    #[error(
        "plan repair did not insert it within {cycles} cycles ({steps} steps{}); the plan is kept as it was",
        last_dead_end(dead_end)
    )]
    InsertionTimedOut {
        cycles: u32,
        steps: u64,
        dead_end: Option<String>,
    },
    #[error("the mission's horizon has passed")]
    HorizonPassed,
    /// §3.6: its constraints are not coherent with the current time any more.
    #[error(
        "its window is no longer reachable at the current time ({:.1} s, d_achiev {:.1} s, start window {window})",
        *now_ms as f64 / 1000.0,
        *achieve_ms as f64 / 1000.0
    )]
    WindowPassed {
        now_ms: Time,
        achieve_ms: Time,
        window: String,
    },
    /// No plan achieves it even alone (src/temporal/src/planner/reachability.rs).
    #[error("goal {name} cannot be achieved: planned alone, {why}")]
    Unreachable { name: String, why: String },
    /// The replanning's plan needs a banned action instance.
    #[error("no plan without {action}: {ban}")]
    NeedsBanned { action: String, ban: String },
    /// An action it depended on is banned after repeated failures.
    #[error("{ban}")]
    InstanceBanned { ban: String },
    #[error("{0}")]
    PlanChurn(PlanChurn),
    /// §3.6 the replanning's step budget is spent.
    #[error(
        "abandoned by complete replanning after \"{abort}\": its {steps} steps are spent with no plan for the goals left"
    )]
    ReplanBudgetSpent { abort: AbortReason, steps: u64 },
    /// §3.6 no plan for every goal left: this one is dropped first.
    #[error(
        "abandoned by complete replanning after \"{abort}\": no plan for every remaining goal ({end}, {steps} steps); this one has the lowest priority, then the least flexibility"
    )]
    Abandoned {
        abort: AbortReason,
        end: AttemptEnd,
        steps: u64,
    },
    /// The last goal's search ran out.
    #[error("no plan found in {steps} steps ({end})")]
    NoPlanFound { end: AttemptEnd, steps: u64 },
    /// `reason`, while the plan found for goal `kept` alone is adopted.
    #[error("{reason}; the plan found for {kept} alone is kept")]
    OtherKept {
        reason: Box<FateReason>,
        kept: String,
    },
    /// Pending: its insertion attempt has not ended.
    #[error("insertion into the plan in progress")]
    Inserting,
    #[error("mission cycle limit reached")]
    CycleLimit,
    #[error("mission time limit reached")]
    TimeLimit,
    #[error("mission interrupted ({signal})")]
    Interrupted { signal: String },
    /// Its place is beyond the vehicle's limits (`[limits]`, the autopilot's fence).
    #[error("{why}")]
    BeyondLimits { why: String },
    /// Its window closed while the operator had the vehicle.
    #[error("its window closed at {:.1} s while the operator had the vehicle ({why})", *closed_ms as f64 / 1000.0)]
    ClosedWhilePaused { closed_ms: Time, why: String },
    /// Withdrawn by the ground station that uploaded it (src/executive/src/exec/cancel.rs).
    #[error("{by}")]
    Cancelled { by: String },
    /// The autopilot fell silent for the link timeout: nothing more can be done with it.
    #[error("vehicle lost: no heartbeat for {silent_s} s")]
    VehicleLost { silent_s: u64 },
}

impl FateReason {
    /// The reason itself, under the note that another goal's plan was kept.
    pub fn cause(&self) -> &FateReason {
        match self {
            FateReason::OtherKept { reason, .. } => reason.cause(),
            r => r,
        }
    }
}

/// A reason as the JSON report writes it: its text.
pub fn text<T: std::fmt::Display, S: serde::Serializer>(r: &T, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(r)
}

/// A fate's reason as the JSON report writes it: its text, empty when there is none.
pub fn reason_text<S: serde::Serializer>(r: &Option<FateReason>, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&r.as_ref().map_or(String::new(), |r| r.to_string()))
}

/// How a replanning attempt's search ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AttemptEnd {
    /// A flawless plan.
    Solved,
    /// Dead end: the search is exhausted.
    DeadEnd,
    /// The time limit l = T_end_ub − d was reached (and the next step was no backtrack raising it).
    TimeLimit,
    /// The attempt's hard step cap.
    StepCap,
    /// The attempt's share of the replanning's wall-time budget (`replan_max_wall_ms`).
    WallBudget,
    /// The attempt's plan reached `plan_max_actions` (its memory budget).
    SizeCap,
}

impl std::fmt::Display for AttemptEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            AttemptEnd::Solved => "solved",
            AttemptEnd::DeadEnd => "dead end",
            AttemptEnd::TimeLimit => "time limit l reached",
            AttemptEnd::StepCap => "step cap reached",
            AttemptEnd::WallBudget => "wall-time budget spent",
            AttemptEnd::SizeCap => "plan size cap reached",
        })
    }
}
