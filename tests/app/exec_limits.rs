//! Issue 30 item 2: `[limits] max_range_m` in the vehicle configuration. A picture goal uploaded 2 km from
//! home (Fig. 2 on the built-in SITL, over sockets, stepped) is rejected by the cycle that receives it,
//! before any planning, with the distance and the limit; a goal within the range is received as before.

use mavtempo::cli::demo::{run_demo, DemoSetup, TimedUpload, UploadItems};
use mavtempo::exec::trace::TraceEvent;

fn limited_config() -> std::path::PathBuf {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/config/demo-rover.toml"
    ))
    .expect("shipped config");
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("limits-500.toml");
    std::fs::write(&path, format!("{text}\n[limits]\nmax_range_m = 500\n")).expect("written");
    path
}

/// The first goal rejection of the run and the cycle it is in.
fn first_rejection(
    run: &mavtempo::cli::demo::DemoRun,
) -> (&mavtempo::exec::trace::CycleRecord, String) {
    run.report
        .cycles
        .iter()
        .find_map(|c| {
            c.events.iter().find_map(|e| match e {
                TraceEvent::GoalRejected { reason, .. } => Some((c, reason.to_string())),
                _ => None,
            })
        })
        .expect("the far goal is rejected")
}

#[test]
fn a_goal_beyond_the_range_is_rejected_in_the_cycle_it_arrives_with_the_distance() {
    let setup = DemoSetup {
        config: Some(limited_config()),
        upload: false,
        timed_upload: Some(TimedUpload {
            at_ms: 30_000,
            items: UploadItems::PicturesAt(vec![(2_000.0, 0.0), (20.0, 10.0)]),
        }),
        ..DemoSetup::default()
    };
    let run = run_demo(&setup, &mut |_| {}, &mut |_| {}).unwrap_or_else(|e| panic!("demo: {e}"));
    let (cycle, reason) = first_rejection(&run);
    assert_eq!(reason, "2.0 km from home, beyond the 500 m range");
    // The same cycle received the near goal: the far one never reached the planner.
    assert!(
        cycle
            .events
            .iter()
            .any(|e| matches!(e, TraceEvent::GoalReceived { .. })),
        "{:?}",
        cycle.events
    );
    assert!(
        run.timed_upload
            .as_deref()
            .is_some_and(|a| a.contains("beyond the 500 m range")),
        "{:?}",
        run.timed_upload
    );
}

/// With no range in the configuration, a goal 3 km away is still rejected when it arrives, with the figure:
/// the least its last leg alone consumes (from the nearest place, p5, 2,960 m at 0.5 %/m) is more than a
/// full battery — no search, no planner dead end.
#[test]
fn a_goal_no_battery_can_reach_is_rejected_at_once_with_what_it_needs() {
    let setup = DemoSetup {
        upload: false,
        timed_upload: Some(TimedUpload {
            at_ms: 30_000,
            items: UploadItems::PicturesAt(vec![(3_000.0, 0.0)]),
        }),
        ..DemoSetup::default()
    };
    let run = run_demo(&setup, &mut |_| {}, &mut |_| {}).unwrap_or_else(|e| panic!("demo: {e}"));
    let (cycle, reason) = first_rejection(&run);
    assert_eq!(reason, "getting there needs 1,480 % of the battery");
    assert!(
        !cycle
            .events
            .iter()
            .any(|e| matches!(e, TraceEvent::GoalReceived { .. })),
        "never inserted: {:?}",
        cycle.events
    );
}
