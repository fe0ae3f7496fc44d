//! What the executive did, cycle by cycle (the trace of seed 1 Fig. 6, and the `--report` JSON).

use serde::{Deserialize, Serialize};

use super::capacity::CapacityOutcome;
use super::outcome::{AbortReason, FateReason};
use super::replan_record::{AttemptEnd, AttemptRecord, ReplanOutcome};
use super::report_timing::Timing;
use super::resource_report::LevelVerdict;
use mavtempo_temporal::model::Time;
use mavtempo_vehicle::ReportStatus;

/// What a cycle's repair part was doing when its budget ran out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum RepairWork {
    /// Repairing *ExecutingPlan*.
    #[serde(rename = "in progress")]
    Repairing,
    /// A new goal's insertion attempt (src/executive/src/exec/goal_insertion.rs).
    #[serde(rename = "inserting a new goal")]
    Inserting,
}

impl std::fmt::Display for RepairWork {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            RepairWork::Repairing => "in progress",
            RepairWork::Inserting => "inserting a new goal",
        })
    }
}

/// A report's status as the vehicle layer prints it (`nominal`, `failed`, `interrupted`).
mod status_text {
    use mavtempo_vehicle::ReportStatus;

    pub fn serialize<S: serde::Serializer>(s: &ReportStatus, ser: S) -> Result<S::Ok, S::Error> {
        ser.collect_str(s)
    }

    pub fn deserialize<'de, D: serde::Deserializer<'de>>(d: D) -> Result<ReportStatus, D::Error> {
        let text = <String as serde::Deserialize>::deserialize(d)?;
        [
            ReportStatus::Nominal,
            ReportStatus::Interrupted,
            ReportStatus::Failed,
        ]
        .into_iter()
        .find(|s| s.to_string() == text)
        .ok_or_else(|| serde::de::Error::custom(format!("unknown report status `{text}`")))
    }
}

/// One entry of the trace.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum TraceEvent {
    Launch {
        action: String,
        vid: u64,
        /// The window `[lb, ub]` of the action's end in the plan when it started (ms since origin; no
        /// upper bound: `None`): the Gantt chart's planned window.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        planned_end_ms: Option<(Time, Option<Time>)>,
    },
    Stop {
        action: String,
        vid: u64,
    },
    Report {
        action: String,
        #[serde(with = "status_text")]
        status: ReportStatus,
        timing: Timing,
        /// Why a failed or interrupted action ended so, as the vehicle said.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        reason: Option<String>,
    },
    Level {
        resource: String,
        level: f64,
        lb: f64,
        ub: f64,
        verdict: LevelVerdict,
    },
    /// A goal request mapped to the domain: its insertion attempt follows.
    GoalReceived {
        goal: String,
    },
    GoalAccepted {
        goal: String,
    },
    /// The plan leaves less of a resource than the fault the configuration declares it must absorb
    /// (`[exec.reserve]`): a fault that size would exhaust it (src/executive/src/exec/reserve.rs).
    ReserveShort {
        resource: String,
        /// The lowest level the plan may reach.
        lowest: f64,
        reserve: f64,
    },
    GoalRejected {
        goal: String,
        reason: FateReason,
    },
    GoalAchieved {
        goal: String,
    },
    /// Withdrawn by its ground station (src/executive/src/exec/cancel.rs).
    GoalCancelled {
        goal: String,
        reason: FateReason,
    },
    Capacity {
        resource: String,
        capacity: f64,
        outcome: CapacityOutcome,
    },
    Postponed {
        action: String,
    },
    Timeout {
        timepoint: String,
    },
    RepairStep {
        steps: u64,
        outcome: RepairWork,
    },
    RepairDone {
        steps: u64,
    },
    Abort {
        reason: AbortReason,
    },
    /// One attempt of a complete replanning (seed 1 §3.6): the goals it planned for, its planning steps,
    /// how its search ended, and why a plan it found was not adopted.
    Replan(AttemptRecord),
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
    /// The operator took control (a mode the companion did not command, a disarm): nothing is commanded
    /// until it is handed back.
    Paused {
        why: String,
    },
    /// Control handed back: the plan is made again from where the vehicle is.
    Resumed {
        how: String,
    },
    /// The vehicle is not where the plan has it: the plan starts from its position, a new place.
    Elsewhere {
        distance_m: f64,
        place: String,
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
    /// Set when this record stands for a run of cycles with no event ([`super::cycle_log`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub idle: Option<IdleRun>,
}

/// Consecutive cycles with no event, recorded as one: the record's `index` and `time_ms` are the first's,
/// its `sense_us`, `repair_us`, `act_us` the sums over the run.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct IdleRun {
    pub cycles: u64,
    pub last_index: u64,
    pub last_time_ms: Time,
    /// The longest cycle of the run (sense + repair + act), µs.
    pub max_us: u64,
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
            TraceEvent::ReserveShort {
                resource,
                lowest,
                reserve,
            } => format!(
                "warning: the plan may leave {resource} at {lowest:.1}, less than the declared fault size {reserve:.1}: a fault that size would exhaust it"
            ),
            TraceEvent::GoalRejected { goal, reason } => format!("goal {goal} rejected: {reason}"),
            TraceEvent::GoalCancelled { goal, reason } => {
                format!("goal {goal} cancelled: {reason}")
            }
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
            TraceEvent::Replan(AttemptRecord {
                attempt,
                goals,
                steps,
                end,
                not_adopted,
            }) => {
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
            TraceEvent::Paused { why } => {
                format!("PAUSED: {why}; the operator has the vehicle, nothing is commanded")
            }
            TraceEvent::Resumed { how } => format!("RESUMED: {how}"),
            TraceEvent::Elsewhere { distance_m, place } => format!(
                "the vehicle is {distance_m:.1} m from where the plan has it: the plan starts from its \
                 position ({place})"
            ),
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exec::goal_request::Rejection;
    use crate::exec::outcome::PlanChurn;
    use crate::mapping::MappingError;

    /// The report is read back into the same events (`mavtempo report RUN.json`), typed reasons included.
    #[test]
    fn events_read_back_as_written() {
        let abort = AbortReason::Timeout {
            timepoint: "end of take_picture(p2)".into(),
        };
        let events = vec![
            TraceEvent::Report {
                action: "move(a, b)".into(),
                status: ReportStatus::Interrupted,
                timing: Timing::TooEarly,
                reason: Some("stopped".into()),
            },
            TraceEvent::Level {
                resource: "STORAGE".into(),
                level: 1.5,
                lb: 2.0,
                ub: 2.0,
                verdict: LevelVerdict::OverConsumption { c: 0.5 },
            },
            TraceEvent::Capacity {
                resource: "STORAGE".into(),
                capacity: 1.0,
                outcome: CapacityOutcome::Abort,
            },
            TraceEvent::RepairStep {
                steps: 3,
                outcome: RepairWork::Inserting,
            },
            TraceEvent::Abort {
                reason: abort.clone(),
            },
            TraceEvent::GoalRejected {
                goal: "g2".into(),
                reason: FateReason::OtherKept {
                    reason: Box::new(FateReason::Abandoned {
                        abort,
                        end: AttemptEnd::TimeLimit,
                        steps: 31,
                    }),
                    kept: "g3".into(),
                },
            },
            TraceEvent::GoalRejected {
                goal: "g6".into(),
                reason: FateReason::Acceptance(Rejection::TooLate {
                    now_ms: 1,
                    achiev_ms: 2,
                }),
            },
            TraceEvent::GoalRejected {
                goal: "g7".into(),
                reason: FateReason::Unmapped(MappingError::NoHomeObject),
            },
            TraceEvent::Abort {
                reason: AbortReason::PlanChurn(PlanChurn {
                    changes: 4,
                    failing: Some(("buy(apple)".into(), 2)),
                    how: "failed".into(),
                }),
            },
            TraceEvent::Replan(AttemptRecord {
                attempt: 1,
                goals: vec!["g1".into()],
                steps: 9,
                end: AttemptEnd::Solved,
                not_adopted: None,
            }),
        ];
        let json = serde_json::to_string(&events).expect("serialized");
        let back: Vec<TraceEvent> = serde_json::from_str(&json).expect("read back");
        assert_eq!(back, events);
        // The texts the report's readers compare stay as they were.
        assert!(json.contains(r#""status":"interrupted""#), "{json}");
        assert!(json.contains(r#""timing":"TooEarly""#), "{json}");
        assert!(json.contains(r#""outcome":"abort""#), "{json}");
        assert!(
            json.contains(r#""outcome":"inserting a new goal""#),
            "{json}"
        );
    }
}
