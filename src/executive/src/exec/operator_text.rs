//! Reasons in the operator's words (issue 30 item 6): one line, what happened to the goal or the mission in
//! the vehicle's terms, with numbers and units, for STATUSTEXT, stdout and the page. The planner's detail —
//! the [`std::fmt::Display`] of [`FateReason`] and [`AbortReason`] — stays in the trace and the report for
//! engineers.

use super::goal_request::Rejection;
use super::outcome::{AbortReason, FateReason};

/// Mission time in seconds, as the operator reads it.
fn secs(ms: i64) -> String {
    format!("{:.0} s", ms as f64 / 1000.0)
}

/// The kind of dead end a planner detail names, in the operator's words: what ran out.
fn what_ran_out(detail: &str) -> &'static str {
    let d = detail.to_ascii_lowercase();
    if d.contains("battery") || d.contains("energy") || d.contains("numeric") {
        "not enough battery to get there and back to the goals held"
    } else if d.contains("negative cycle") || d.contains("temporal") || d.contains("window") {
        "no time to get there within its window while keeping the goals held"
    } else if d.contains("image") || d.contains("storage") || d.contains("memory") {
        "no room left for its pictures"
    } else {
        "no way to fit it in with the goals held"
    }
}

/// What a search cut by its budget last ran into, without claiming it is what makes the goal impossible.
fn obstacle(detail: &str) -> &'static str {
    match what_ran_out(detail) {
        "not enough battery to get there and back to the goals held" => "the battery",
        "no time to get there within its window while keeping the goals held" => "a time window",
        "no room left for its pictures" => "the storage",
        _ => "the goals held",
    }
}

impl AbortReason {
    /// Why execution stopped, in the operator's words.
    pub fn operator_text(&self) -> String {
        match self {
            AbortReason::CapacityAltered { resource } => format!("the {resource} capacity changed"),
            AbortReason::ReportTooLate { action } => format!("{action} ended later than planned"),
            AbortReason::ReportInconsistent { action, .. } => {
                format!("{action} ended outside its planned time")
            }
            AbortReason::LevelOutOfBounds { resource, level } => {
                format!("{resource} at {level:.1} is outside what the plan allows")
            }
            AbortReason::NotExecutable { now_ms, .. } => {
                format!("the plan could no longer run at {}", secs(*now_ms))
            }
            AbortReason::RepairDiverged { .. } | AbortReason::RepairFailed { .. } => {
                "the plan could not be repaired".to_string()
            }
            AbortReason::CannotInstantiate { action, .. } => {
                format!("{action} could not be started")
            }
            AbortReason::StartRefused { action, error } => {
                format!("the vehicle refused to start {action}: {error}")
            }
            AbortReason::StartInconsistent { action, .. } => {
                format!("{action} started outside its planned time")
            }
            AbortReason::LaunchBanned { ban, .. } | AbortReason::InstanceBanned { ban } => {
                ban.clone()
            }
            AbortReason::PlanChurn(c) => c.to_string(),
            AbortReason::Timeout { timepoint } => format!("{timepoint} did not happen in time"),
            AbortReason::Unstated => "execution stopped".to_string(),
            AbortReason::ControlReturned { how } => format!("control handed back ({how})"),
            AbortReason::VehicleElsewhere { distance_m } => {
                format!("the vehicle is {distance_m:.0} m from where the plan has it")
            }
        }
    }
}

impl FateReason {
    /// Why a goal was rejected, cancelled or is still pending, in the operator's words.
    pub fn operator_text(&self) -> String {
        match self {
            FateReason::Unmapped(e) => e.to_string(),
            FateReason::Acceptance(Rejection::Window { .. }) => {
                "its start window and duration cannot fit the plan".to_string()
            }
            FateReason::Acceptance(Rejection::TooLate { now_ms, achiev_ms }) => format!(
                "its start window closes before the vehicle can get there (it needs {} from {})",
                secs(*achiev_ms),
                secs(*now_ms)
            ),
            FateReason::Acceptance(Rejection::Running { .. }) => {
                "it conflicts with what the vehicle is doing now".to_string()
            }
            FateReason::NotExecutable { now_ms, .. } => {
                format!("the plan could not take it at {}", secs(*now_ms))
            }
            FateReason::InsertionFailed { failure, dead_end } => {
                what_ran_out(&format!("{failure} {}", dead_end.as_deref().unwrap_or(""))).to_string()
            }
            // Cut by its budget, the search proved nothing: no claim that the goal cannot be achieved.
            FateReason::InsertionTimedOut {
                cycles, dead_end, ..
            } => format!(
                "no plan found for it within {cycles} cycles of search, which does not prove there is none (the search last ran into {})",
                obstacle(dead_end.as_deref().unwrap_or(""))
            ),
            FateReason::HorizonPassed => "the mission's end has passed".to_string(),
            FateReason::WindowPassed {
                now_ms,
                achieve_ms,
                window,
            } => format!(
                "its window {window} closed before the vehicle could get there (it needs {} from {})",
                secs(*achieve_ms),
                secs(*now_ms)
            ),
            FateReason::Unreachable { why, .. } => format!(
                "no plan achieves it even alone ({})",
                what_ran_out(why)
            ),
            FateReason::NeedsBanned { ban, .. } | FateReason::InstanceBanned { ban } => ban.clone(),
            FateReason::PlanChurn(c) => c.to_string(),
            FateReason::ReplanBudgetSpent { abort, .. } => format!(
                "dropped when the plan was rebuilt after \"{}\": no plan found in time",
                abort.operator_text()
            ),
            FateReason::Abandoned { abort, .. } => format!(
                "dropped to keep the other goals when the plan was rebuilt after \"{}\"",
                abort.operator_text()
            ),
            FateReason::NoPlanFound { .. } => "no plan found for it".to_string(),
            FateReason::OtherKept { reason, kept } => {
                format!("{}; the plan for {kept} is kept", reason.operator_text())
            }
            FateReason::Inserting => "being inserted into the plan".to_string(),
            FateReason::CycleLimit => "the mission's cycle limit was reached".to_string(),
            FateReason::TimeLimit => "the mission's time limit was reached".to_string(),
            FateReason::Interrupted { signal } => format!("the mission was interrupted ({signal})"),
            FateReason::Cancelled { by } => by.clone(),
            FateReason::BeyondLimits { why } => why.clone(),
            FateReason::VehicleLost { silent_s } => {
                format!("the vehicle was lost: no heartbeat for {silent_s} s")
            }
            FateReason::ClosedWhilePaused { closed_ms, .. } => format!(
                "its window closed at {} while the operator had the vehicle",
                secs(*closed_ms)
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planner_internals_stay_out_of_operator_texts() {
        let r = FateReason::InsertionFailed {
            failure: "search exhausted".into(),
            dead_end: Some(
                "inserting move for open condition AT_ROBOT() = g7_loc of take_picture#29: inconsistent numeric constraints"
                    .into(),
            ),
        };
        assert_eq!(
            r.operator_text(),
            "not enough battery to get there and back to the goals held"
        );
        let w = FateReason::WindowPassed {
            now_ms: 400_000,
            achieve_ms: 60_000,
            window: "[0 s, 300 s]".into(),
        };
        assert_eq!(
            w.operator_text(),
            "its window [0 s, 300 s] closed before the vehicle could get there (it needs 60 s from 400 s)"
        );
        // A search cut by its budget is said to be so, not that the goal cannot be achieved.
        let cut = FateReason::InsertionTimedOut {
            cycles: 8,
            steps: 400,
            dead_end: Some("move: inconsistent numeric constraints".into()),
        };
        assert_eq!(
            cut.operator_text(),
            "no plan found for it within 8 cycles of search, which does not prove there is none (the search last ran into the battery)"
        );
        let t = FateReason::Acceptance(Rejection::Window {
            error: "negative cycle of 2 edges, total -128280".into(),
        });
        assert!(
            !t.operator_text().contains("cycle"),
            "{}",
            t.operator_text()
        );
    }
}
