//! The shipped ArduPilot configuration (config/ardupilot-rover.toml) against the built-in SITL behaving as
//! a stock ArduPilot Rover (tests/fixtures/exec/ardupilot-hold.toml: the SITL's ArduPilot profile plus a
//! foreign HOLD in the middle of the second move), over real sockets, stepped: started right after the
//! autopilot's boot, the companion waits for a fix and arming; pictures end on CAMERA_FEEDBACK; a goal file
//! is uploaded by a ground station during the run; the mission goes on after the HOLD.

use std::path::PathBuf;

use mavtempo::cli::demo::{run_demo, DemoSetup, TimedUpload, UploadItems};
use mavtempo::exec::executive::Fate;
use mavtempo::exec::trace::TraceEvent;
use mavtempo::vehicle::ReportStatus;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn a_rover_mission_on_the_ardupilot_profile_waits_for_readiness_and_survives_a_foreign_hold() {
    let setup = DemoSetup {
        config: Some(root().join("config/ardupilot-rover.toml")),
        scenario: Some(root().join("tests/fixtures/exec/ardupilot-hold.toml")),
        upload: false,
        timed_upload: Some(TimedUpload {
            at_ms: 150_000,
            items: UploadItems::File(root().join("config/goals/example.plan")),
        }),
        ..DemoSetup::default()
    };
    let run = run_demo(&setup, &mut |_| {}, &mut |_| {}).unwrap_or_else(|e| panic!("demo: {e}"));

    // Started right after boot: arming is refused for the profile's 20 s, then accepted.
    let ready = run.ready.as_ref().expect("the run waited for readiness");
    assert!(ready.ready);
    assert!(
        ready.fix_after_ms.is_some_and(|ms| ms >= 9_000),
        "{ready:?}"
    );
    assert!(
        ready.armed_after_ms.is_some_and(|ms| ms >= 20_000),
        "{ready:?}"
    );
    assert!(ready.arm_attempts > 1, "{ready:?}");
    assert!(
        ready.refusals.iter().any(|r| r.contains("Arm:")),
        "the autopilot's reasons are kept: {ready:?}"
    );

    let events: Vec<&TraceEvent> = run.report.cycles.iter().flat_map(|c| &c.events).collect();
    let reports = |task: &str, status: ReportStatus| {
        events
            .iter()
            .filter(|e| {
                matches!(e, TraceEvent::Report { action, status: s, .. }
                    if action.starts_with(task) && *s == status)
            })
            .count()
    };
    // Pictures confirmed by CAMERA_FEEDBACK alone (the profile sends no CAMERA_IMAGE_CAPTURED).
    assert!(reports("take_picture(", ReportStatus::Nominal) >= 3);
    assert_eq!(reports("take_picture(", ReportStatus::Failed), 0);
    // The foreign HOLD failed a move; moves were launched and ended nominally after it.
    let failed_at = events
        .iter()
        .position(|e| matches!(e, TraceEvent::Report { action, status, .. } if action.starts_with("move(") && *status == ReportStatus::Failed))
        .expect("the HOLD fails a move");
    let nominal_moves_after = events[failed_at..]
        .iter()
        .filter(|e| matches!(e, TraceEvent::Report { action, status, .. } if action.starts_with("move(") && *status == ReportStatus::Nominal))
        .count();
    assert!(
        nominal_moves_after >= 2,
        "the mission goes on after the HOLD"
    );

    // Every goal settled, each rejection with its reason; most of the mission achieved.
    let fates = &run.report.goals;
    assert!(
        fates.len() >= 6,
        "the upload's goals have fates too: {fates:?}"
    );
    for g in fates {
        match g.fate {
            Fate::Achieved => {}
            Fate::Rejected => assert!(g.reason.is_some(), "{g:?}"),
            _ => panic!("not settled: {g:?}"),
        }
    }
    let achieved = fates.iter().filter(|g| g.fate == Fate::Achieved).count();
    assert!(achieved >= 4, "{fates:?}");
    assert!(
        run.timed_upload
            .as_deref()
            .is_some_and(|a| a.contains("upload accepted")),
        "{:?}",
        run.timed_upload
    );
}
