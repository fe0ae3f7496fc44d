//! What the executive did, cycle by cycle (the trace of seed 1 Fig. 6, and the `--report` JSON).

use serde::Serialize;

use crate::model::Time;

/// One entry of the trace.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum TraceEvent {
    Launch {
        action: String,
        vid: u64,
    },
    Stop {
        action: String,
        vid: u64,
    },
    Report {
        action: String,
        status: String,
        timing: String,
    },
    Level {
        resource: String,
        level: f64,
        lb: f64,
        ub: f64,
        verdict: String,
    },
    /// A goal request mapped to the domain: its insertion attempt follows.
    GoalReceived {
        goal: String,
    },
    GoalAccepted {
        goal: String,
    },
    GoalRejected {
        goal: String,
        reason: String,
    },
    GoalAchieved {
        goal: String,
    },
    Capacity {
        resource: String,
        capacity: f64,
        outcome: String,
    },
    Postponed {
        action: String,
    },
    Timeout {
        timepoint: String,
    },
    RepairStep {
        steps: u64,
        outcome: String,
    },
    RepairDone {
        steps: u64,
    },
    Abort {
        reason: String,
    },
    Replan {
        attempt: u32,
        outcome: String,
    },
    LinksBroken {
        count: usize,
    },
    Interrupt {
        action: String,
        reason: String,
    },
}

/// One cycle: when it started, how long its phases took (µs of the executive's CPU), what happened.
#[derive(Clone, Debug, Default, Serialize)]
pub struct CycleRecord {
    pub index: u64,
    pub time_ms: Time,
    pub sense_us: u64,
    pub repair_us: u64,
    pub act_us: u64,
    pub events: Vec<TraceEvent>,
}

impl TraceEvent {
    /// One line of the human-readable trace.
    pub fn line(&self) -> String {
        match self {
            TraceEvent::Launch { action, vid } => format!("START {action} #{vid}"),
            TraceEvent::Stop { action, vid } => format!("END #{vid} ({action})"),
            TraceEvent::Report {
                action,
                status,
                timing,
            } => format!("report {action}: {status} ({timing})"),
            TraceEvent::Level {
                resource,
                level,
                lb,
                ub,
                verdict,
            } => format!("{resource} = {level:.2} in [{lb:.2}, {ub:.2}]: {verdict}"),
            TraceEvent::GoalReceived { goal } => {
                format!("goal {goal} received: inserting it into the plan")
            }
            TraceEvent::GoalAccepted { goal } => format!("goal {goal} accepted"),
            TraceEvent::GoalRejected { goal, reason } => format!("goal {goal} rejected: {reason}"),
            TraceEvent::GoalAchieved { goal } => format!("goal {goal} achieved"),
            TraceEvent::Capacity {
                resource,
                capacity,
                outcome,
            } => format!("capacity of {resource} now {capacity}: {outcome}"),
            TraceEvent::Postponed { action } => format!("postponed {action}"),
            TraceEvent::Timeout { timepoint } => format!("timeout on {timepoint}"),
            TraceEvent::RepairStep { steps, outcome } => {
                format!("plan repair: {steps} steps, {outcome}")
            }
            TraceEvent::RepairDone { steps } => format!("plan repaired in {steps} steps"),
            TraceEvent::Abort { reason } => format!("execution aborted: {reason}"),
            TraceEvent::Replan { attempt, outcome } => {
                format!("complete replanning, attempt {attempt}: {outcome}")
            }
            TraceEvent::LinksBroken { count } => format!("{count} causal links broken"),
            TraceEvent::Interrupt { action, reason } => format!("interrupt {action}: {reason}"),
        }
    }
}
