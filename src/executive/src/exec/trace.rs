//! What the executive did, cycle by cycle (the trace of seed 1 Fig. 6, and the `--report` JSON).

use serde::Serialize;

use super::replan::{AttemptEnd, ReplanOutcome};
use crate::model::Time;

/// One entry of the trace.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum TraceEvent {
    Launch {
        action: String,
        vid: u64,
        /// The window `[lb, ub]` of the action's end in the plan when it started (ms since origin; no
        /// upper bound: `None`): the Gantt chart's planned window.
        #[serde(skip_serializing_if = "Option::is_none")]
        planned_end_ms: Option<(Time, Option<Time>)>,
    },
    Stop {
        action: String,
        vid: u64,
    },
    Report {
        action: String,
        status: String,
        timing: String,
        /// Why a failed or interrupted action ended so, as the vehicle said.
        #[serde(skip_serializing_if = "Option::is_none")]
        reason: Option<String>,
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
    /// One attempt of a complete replanning (seed 1 §3.6): the goals it planned for, its planning steps,
    /// how its search ended, and why a plan it found was not adopted.
    Replan {
        attempt: u32,
        goals: Vec<String>,
        steps: u64,
        end: AttemptEnd,
        #[serde(skip_serializing_if = "Option::is_none")]
        not_adopted: Option<String>,
    },
    /// The end of a complete replanning: its outcome, the goals kept in the new plan and those it
    /// rejected (each also has its `goal_rejected` event with the reason).
    ReplanDone {
        outcome: ReplanOutcome,
        attempts: u32,
        steps: u64,
        kept: Vec<String>,
        rejected: Vec<String>,
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
            TraceEvent::Launch { action, vid, .. } => format!("START {action} #{vid}"),
            TraceEvent::Stop { action, vid } => format!("END #{vid} ({action})"),
            TraceEvent::Report {
                action,
                status,
                timing,
                reason,
            } => match reason {
                Some(why) => format!("report {action}: {status} ({timing}): {why}"),
                None => format!("report {action}: {status} ({timing})"),
            },
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
            TraceEvent::Replan {
                attempt,
                goals,
                steps,
                end,
                not_adopted,
            } => {
                let goals = names(goals);
                let what = match (end, not_adopted) {
                    (_, Some(why)) => format!("plan found in {steps} steps, not adopted: {why}"),
                    (AttemptEnd::Solved, None) => format!("plan found in {steps} steps"),
                    (end, None) => format!("no plan after {steps} steps ({end})"),
                };
                format!("complete replanning, attempt {attempt} (goals {goals}): {what}")
            }
            TraceEvent::ReplanDone {
                outcome,
                attempts,
                steps,
                kept,
                rejected,
            } => format!(
                "complete replanning done: {outcome} after {attempts} attempt(s), {steps} steps; \
                 goals kept: {}; rejected: {}",
                names(kept),
                names(rejected)
            ),
            TraceEvent::LinksBroken { count } => format!("{count} causal links broken"),
            TraceEvent::Interrupt { action, reason } => format!("interrupt {action}: {reason}"),
        }
    }
}

/// `g1, g3`, or `none`.
pub fn names(goals: &[String]) -> String {
    if goals.is_empty() {
        "none".into()
    } else {
        goals.join(", ")
    }
}
