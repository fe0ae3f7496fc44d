//! What every soak mission must satisfy, checked on its report.

use serde::Serialize;

use crate::exec::executive::Fate;
use crate::exec::mission::{MissionEnd, MissionReport};
use crate::exec::outcome::{AbortReason, FateReason};
use crate::exec::trace::TraceEvent;

/// The most times one action instance (a task with its arguments) may be launched in a row without
/// completing nominally: retries of what failed. (The same instance done again after a success, e.g. the
/// pan-and-tilt unit turned down for each picture, is new work, not a retry.)
pub const MAX_STARTS: usize = 3;
/// How long past its horizon a mission may run, ms.
pub const END_MARGIN_MS: i64 = 60_000;

/// One invariant broken by one mission.
#[derive(Clone, Debug, Serialize)]
pub struct Violation {
    pub invariant: &'static str,
    pub seed: u64,
    pub detail: String,
}

/// The invariants of a finished mission (`horizon_ms`: its problem's horizon).
pub fn check(seed: u64, report: &MissionReport, horizon_ms: i64) -> Vec<Violation> {
    let mut out = Vec::new();
    let mut v = |invariant, detail: String| {
        out.push(Violation {
            invariant,
            seed,
            detail,
        })
    };
    if let MissionEnd::Error(e) = &report.end {
        v("no_error_exit", e.clone());
    }
    if report.end == MissionEnd::CycleLimit {
        v(
            "cycle_bound",
            format!(
                "{} cycles by {} s of mission time",
                report.cycle_times.count,
                report.duration_ms / 1000
            ),
        );
    }
    for g in &report.goals {
        match g.fate {
            Fate::Pending => v(
                "goal_settled",
                format!("{} still pending at the end ({:?})", g.name, report.end),
            ),
            Fate::Rejected if g.reason_text().trim().is_empty() => v(
                "rejected_with_reason",
                format!("{} rejected without a reason", g.name),
            ),
            _ => {}
        }
    }
    for e in report.cycles.iter().flat_map(|c| &c.events) {
        if let TraceEvent::GoalRejected { goal, reason } = e {
            if reason.to_string().trim().is_empty() {
                v(
                    "rejected_with_reason",
                    format!("{goal} rejected without a reason"),
                );
            }
        }
    }
    for (action, n) in report.launches_in_a_row() {
        if n > MAX_STARTS {
            v(
                "max_starts",
                format!("{action} started {n} times without completing"),
            );
        }
    }
    if report.duration_ms > horizon_ms + END_MARGIN_MS || report.end == MissionEnd::TimeLimit {
        v(
            "ends_in_time",
            format!(
                "ended ({:?}) at {} s, horizon {} s",
                report.end,
                report.duration_ms / 1000,
                horizon_ms / 1000
            ),
        );
    }
    out
}

/// The class of a rejection reason, for the summary's counts. A goal abandoned by the replanning that a
/// repeated failure or the plan-change bound caused is counted under that cause.
pub fn reason_class(reason: Option<&FateReason>) -> &'static str {
    let abort_class = |a: &AbortReason| match a {
        AbortReason::InstanceBanned { .. } | AbortReason::LaunchBanned { .. } => "repeated_failure",
        AbortReason::PlanChurn(_) => "plan_change_bound",
        _ => "replanning",
    };
    match reason.map(FateReason::cause) {
        Some(FateReason::InstanceBanned { .. } | FateReason::NeedsBanned { .. }) => {
            "repeated_failure"
        }
        Some(FateReason::PlanChurn(_)) => "plan_change_bound",
        Some(FateReason::WindowPassed { .. }) => "window_passed",
        Some(FateReason::HorizonPassed) => "horizon",
        Some(FateReason::Abandoned { abort, .. } | FateReason::ReplanBudgetSpent { abort, .. }) => {
            abort_class(abort)
        }
        Some(_) | None => "other",
    }
}
