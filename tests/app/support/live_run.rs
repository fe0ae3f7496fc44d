//! What the live runs against the built-in SITL's autopilot profiles (tests/app/live_ardupilot.rs,
//! tests/app/live_px4.rs) read from a mission report: reports of a task by status, and every goal settled.

use std::path::PathBuf;

use mavtempo::cli::demo::{run_demo, DemoRun, DemoSetup, TimedUpload, UploadItems};
use mavtempo::exec::executive::{Fate, GoalFate};
use mavtempo::exec::trace::TraceEvent;
use mavtempo::vehicle::ReportStatus;

/// The shipped `config` (relative to the repository) against the built-in SITL in `scenario`, stepped, with
/// the goal file `goals` uploaded by a ground station at `upload_at_ms`; the operator arms (the scenario
/// does): the run must have waited for it without sending ARM.
pub fn run(config: &str, scenario: &str, goals: &str, upload_at_ms: i64) -> DemoRun {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let setup = DemoSetup {
        config: Some(root.join(config)),
        scenario: Some(root.join(scenario)),
        upload: false,
        timed_upload: Some(TimedUpload {
            at_ms: upload_at_ms,
            items: UploadItems::File(root.join(goals)),
        }),
        ..DemoSetup::default()
    };
    let run = run_demo(&setup, &mut |_| {}, &mut |_| {}).unwrap_or_else(|e| panic!("demo: {e}"));
    let ready = run.ready.as_ref().expect("the run waited for readiness");
    assert!(ready.ready, "{ready:?}");
    assert_eq!(ready.arm_attempts, 0, "{ready:?}");
    run
}

/// The actions launched, in launch order.
pub fn launched<'a>(events: impl IntoIterator<Item = &'a TraceEvent>) -> Vec<&'a str> {
    events
        .into_iter()
        .filter_map(|e| match e {
            TraceEvent::Launch { action, .. } => Some(action.as_str()),
            _ => None,
        })
        .collect()
}

/// How many reports of actions of `task` (an action name's prefix, `"move("`) ended with `status`.
pub fn reports(events: &[&TraceEvent], task: &str, status: ReportStatus) -> usize {
    events
        .iter()
        .filter(|e| {
            matches!(e, TraceEvent::Report { action, status: s, .. }
                if action.starts_with(task) && *s == status)
        })
        .count()
}

/// Every goal achieved or rejected with its reason, at least `achieved` of them achieved.
pub fn assert_settled(fates: &[GoalFate], achieved: usize) {
    for g in fates {
        match g.fate {
            Fate::Achieved => {}
            Fate::Rejected => assert!(g.reason.is_some(), "{g:?}"),
            _ => panic!("not settled: {g:?}"),
        }
    }
    let n = fates.iter().filter(|g| g.fate == Fate::Achieved).count();
    assert!(n >= achieved, "{fates:?}");
}
