//! The shipped PX4 configuration (config/px4-rover.toml) against the built-in SITL behaving as a stock PX4
//! SIH rover (tests/fixtures/exec/px4-return.toml: the SITL's PX4 profile plus an operator taking control
//! with Return in the middle of the second move and handing it back with Hold 12 s later), over real
//! sockets, stepped: started right after the autopilot's boot, the companion waits for PX4's pre-arm checks
//! and estimator (no EKF_STATUS_REPORT is asked for: PX4 denies it) and the operator's arming; moves go as
//! DO_REPOSITION in MAV_FRAME_GLOBAL_INT (PX4 answers any other frame 9); pictures are the companion's own
//! (PX4 SIH has no camera); a goal file is uploaded during the run; the companion yields during Return and
//! resumes on Hold.

use crate::support::live_run;

use mavtempo::exec::trace::TraceEvent;
use mavtempo::vehicle::ReportStatus;

#[test]
fn a_rover_mission_on_the_px4_profile_moves_in_global_int_and_yields_to_return() {
    let run = live_run::run(
        "config/px4-rover.toml",
        "tests/fixtures/exec/px4-return.toml",
        "config/goals/px4-example.plan",
        150_000,
    );

    // The operator arms at 10 s, after the profile's 5 s of rejections; the companion never sends ARM.
    let ready = run.ready.as_ref().expect("the run waited for readiness");
    assert!(
        ready.armed_after_ms.is_some_and(|ms| ms >= 8_000),
        "{ready:?}"
    );

    let events: Vec<&TraceEvent> = run.report.cycles.iter().flat_map(|c| &c.events).collect();
    let reports = |task: &str, status: ReportStatus| live_run::reports(&events, task, status);
    // Every move PX4 took (a frame it refuses would fail them all with UNSUPPORTED_MAV_FRAME).
    let failed_moves: Vec<_> = events
        .iter()
        .filter(|e| {
            matches!(e, TraceEvent::Report { action, status, reason, .. }
            if action.starts_with("move(") && *status == ReportStatus::Failed
                && reason.as_deref().is_some_and(|r| r.contains("refused")))
        })
        .collect();
    assert!(failed_moves.is_empty(), "{failed_moves:?}");
    assert!(reports("take_picture(", ReportStatus::Nominal) >= 3);

    // Return pauses the executive; Hold (the companion's own mode on PX4) resumes it.
    let paused_at = events
        .iter()
        .position(|e| matches!(e, TraceEvent::Paused { why } if why.contains("Return")))
        .unwrap_or_else(|| panic!("Return pauses: {events:?}"));
    let resumed_at = paused_at
        + events[paused_at..]
            .iter()
            .position(|e| matches!(e, TraceEvent::Resumed { how } if how.contains("Hold")))
            .expect("Hold resumes");
    let during = &events[paused_at..resumed_at];
    assert!(
        !during
            .iter()
            .any(|e| matches!(e, TraceEvent::Launch { .. } | TraceEvent::Stop { .. })),
        "nothing commanded while paused: {during:?}"
    );
    let nominal_moves_after = events[resumed_at..]
        .iter()
        .filter(|e| matches!(e, TraceEvent::Report { action, status, .. } if action.starts_with("move(") && *status == ReportStatus::Nominal))
        .count();
    assert!(nominal_moves_after >= 2, "the mission goes on after Hold");

    // Every goal settled, each rejection with its reason; most of the mission achieved.
    let fates = &run.report.goals;
    live_run::assert_settled(fates, 4);
    assert!(
        run.timed_upload
            .as_deref()
            .is_some_and(|a| a.contains("upload accepted")),
        "{:?}",
        run.timed_upload
    );
}
