//! Assertions on the vehicle's reports shared by the tests: action reports (in memory and over sockets)
//! and goal-upload reports.
use mavtempo_vehicle::goal_client::GoalSendReport;
use mavtempo_vehicle::{ActionReport, ReportStatus};

/// `r` reports a failure whose reason names `why`.
pub fn assert_failed(r: &ActionReport, why: &str) {
    assert_eq!(r.status, ReportStatus::Failed, "{r:?}");
    assert!(
        r.reason.as_deref().unwrap_or("").contains(why),
        "reason should name {why:?}: {r:?}"
    );
}

/// The goal upload was refused: its failure names `failure` and one STATUSTEXT holds all of `text`.
pub fn assert_upload_refused(report: &GoalSendReport, failure: &str, text: &[&str]) {
    assert!(
        report.failure.as_deref().unwrap_or("").contains(failure),
        "{report:?}"
    );
    assert!(
        report
            .texts
            .iter()
            .any(|t| text.iter().all(|part| t.contains(part))),
        "{report:?}"
    );
}
