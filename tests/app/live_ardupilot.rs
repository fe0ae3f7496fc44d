//! The shipped ArduPilot configuration (config/ardupilot-rover.toml) against the built-in SITL behaving as
//! a stock ArduPilot Rover (tests/fixtures/exec/ardupilot-hold.toml: the SITL's ArduPilot profile plus a
//! foreign HOLD in the middle of the second move, handed back by GUIDED 12 s later), over real sockets,
//! stepped: started right after the autopilot's boot, the companion waits for a fix and the operator's
//! arming (it never arms: `[authority] arm = "operator"`); pictures end on CAMERA_FEEDBACK; a goal file is
//! uploaded by a ground station during the run; the companion yields during the HOLD and the mission goes
//! on after it is handed back.

use crate::support::live_run;

use mavtempo::exec::trace::TraceEvent;
use mavtempo::vehicle::ReportStatus;

#[test]
fn a_rover_mission_on_the_ardupilot_profile_waits_for_the_operator_and_yields_to_a_foreign_hold() {
    let run = live_run::run(
        "config/ardupilot-rover.toml",
        "tests/fixtures/exec/ardupilot-hold.toml",
        "config/goals/example.plan",
        150_000,
    );

    // Started right after boot: the companion waits for the fix, then for the operator, who arms at 25 s
    // (the scenario's ground station); it never sends ARM itself.
    let ready = run.ready.as_ref().expect("the run waited for readiness");
    assert!(
        ready.fix_after_ms.is_some_and(|ms| ms >= 9_000),
        "{ready:?}"
    );
    assert!(
        ready.armed_after_ms.is_some_and(|ms| ms >= 20_000),
        "{ready:?}"
    );

    let events: Vec<&TraceEvent> = run.report.cycles.iter().flat_map(|c| &c.events).collect();
    let reports = |task: &str, status: ReportStatus| live_run::reports(&events, task, status);
    // Pictures confirmed by CAMERA_FEEDBACK alone (the profile sends no CAMERA_IMAGE_CAPTURED).
    assert!(reports("take_picture(", ReportStatus::Nominal) >= 3);
    assert_eq!(reports("take_picture(", ReportStatus::Failed), 0);
    // The foreign HOLD pauses the executive: the move ends interrupted, nothing is launched or stopped
    // until GUIDED is restored; then moves are launched and end nominally.
    let paused_at = events
        .iter()
        .position(|e| matches!(e, TraceEvent::Paused { why } if why.contains("HOLD")))
        .expect("the HOLD pauses");
    let resumed_at = paused_at
        + events[paused_at..]
            .iter()
            .position(|e| matches!(e, TraceEvent::Resumed { how } if how.contains("GUIDED")))
            .expect("GUIDED resumes");
    let during = &events[paused_at..resumed_at];
    assert!(
        !during
            .iter()
            .any(|e| matches!(e, TraceEvent::Launch { .. } | TraceEvent::Stop { .. })),
        "nothing commanded while paused: {during:?}"
    );
    assert!(
        events[paused_at.saturating_sub(3)..=resumed_at]
            .iter()
            .any(|e| matches!(e, TraceEvent::Report { action, status, .. }
            if action.starts_with("move(") && *status == ReportStatus::Interrupted)),
        "the move ends where the vehicle stopped: {:?}",
        &events[paused_at.saturating_sub(3)..(resumed_at + 3).min(events.len())]
    );
    let pause_ms = |i: usize| {
        run.report
            .cycles
            .iter()
            .scan(0, |n, c| {
                *n += c.events.len();
                Some((*n, c.time_ms))
            })
            .find(|&(n, _)| n > i)
            .map(|(_, t)| t)
    };
    let (p, r) = (pause_ms(paused_at), pause_ms(resumed_at));
    assert!(
        p.zip(r).is_some_and(|(p, r)| r - p >= 10_000),
        "the pause lasts as long as the HOLD: {p:?} .. {r:?}"
    );
    let nominal_moves_after = events[resumed_at..]
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
    live_run::assert_settled(fates, 4);
    assert!(
        run.timed_upload
            .as_deref()
            .is_some_and(|a| a.contains("upload accepted")),
        "{:?}",
        run.timed_upload
    );
}
