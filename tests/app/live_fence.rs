//! Issue 30 item 2, the autopilot's fence, over sockets against the built-in SITL's ArduPilot profile
//! (tests/fixtures/exec/ardupilot-fence.toml: FENCE_ENABLE = 1, FENCE_TYPE = 6, FENCE_RADIUS = 200 m and an
//! exclusion circle on the straight way from p1 to p4), with config/ardupilot-rover.toml, stepped: the
//! companion reads the fence at readiness (MISSION_TYPE_FENCE download, FENCE_* parameters); a goal
//! beyond FENCE_RADIUS is rejected when it arrives; Fig. 2's initial plan, made before the fence was known,
//! drives `move(p1, p4)` through the exclusion circle: it is made again and no move crossing the fence is
//! ever launched, while p4's picture is still taken (the planner goes round, through another place).

use std::path::PathBuf;

use crate::support::live_run;

use mavtempo::cli::demo::{run_demo, DemoSetup, TimedUpload, UploadItems};
use mavtempo::exec::executive::Fate;
use mavtempo::exec::trace::TraceEvent;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn the_autopilots_fence_is_read_at_readiness_and_kept_at_intake_and_by_every_move() {
    let setup = DemoSetup {
        config: Some(root().join("config/ardupilot-rover.toml")),
        scenario: Some(root().join("tests/fixtures/exec/ardupilot-fence.toml")),
        upload: false,
        timed_upload: Some(TimedUpload {
            at_ms: 40_000,
            items: UploadItems::PicturesAt(vec![(250.0, 0.0)]),
        }),
        ..DemoSetup::default()
    };
    let run = run_demo(&setup, &mut |_| {}, &mut |_| {}).unwrap_or_else(|e| panic!("demo: {e}"));
    assert_eq!(
        run.fence.as_deref(),
        Some("the autopilot's fence: a 200 m circle around home, 1 circle(s)")
    );
    let events: Vec<&TraceEvent> = run.report.cycles.iter().flat_map(|c| &c.events).collect();
    // The goal 250 m away: beyond FENCE_RADIUS, rejected with the distance before any planning.
    let rejected: Vec<String> = events
        .iter()
        .filter_map(|e| match e {
            TraceEvent::GoalRejected { reason, .. } => Some(reason.to_string()),
            _ => None,
        })
        .collect();
    assert!(
        rejected
            .iter()
            .any(|r| r == "outside the autopilot's fence (250 m from home)"),
        "{rejected:?}"
    );
    // The initial plan's move(p1, p4) crosses the exclusion circle: the plan is made again before any launch.
    assert!(
        events
            .iter()
            .any(|e| matches!(e, TraceEvent::Abort { reason }
            if reason.to_string().contains("move(p1, p4) leaves the vehicle's limits"))),
        "{events:?}"
    );
    let launched = live_run::launched(events.iter().copied());
    assert!(
        launched.iter().any(|a| a.starts_with("move(")),
        "{launched:?}"
    );
    for crossing in ["move(p1, p4)", "move(p4, p1)"] {
        assert!(
            !launched.contains(&crossing),
            "{crossing} goes through the exclusion circle: {launched:?}"
        );
    }
    // Fig. 2's picture of p4 (g4) is still achieved, by another way there.
    let g4 = run
        .report
        .goals
        .iter()
        .find(|g| g.name == "g4")
        .expect("g4");
    assert_eq!(g4.fate, Fate::Achieved, "{:?}", run.report.goals);
}
