//! Issue 30 item 5: the plan starts where the vehicle is. Fig. 2 with the simulated rover 55 m east of the
//! problem's `base` (over sockets, stepped): the executive compares the vehicle's position with the plan's
//! place of the vehicle, warns with the distance, and the first move starts from a new place there.

use mavtempo::cli::demo::{run_demo, DemoSetup};
use mavtempo::exec::trace::TraceEvent;

#[test]
fn a_vehicle_55_m_from_base_is_planned_from_where_it_is() {
    let setup = DemoSetup {
        upload: false,
        vehicle_offset_m: (55.0, 0.0),
        ..DemoSetup::default()
    };
    let run = run_demo(&setup, &mut |_| {}, &mut |_| {}).unwrap_or_else(|e| panic!("demo: {e}"));
    let events: Vec<&TraceEvent> = run.report.cycles.iter().flat_map(|c| &c.events).collect();
    let (distance, place) = events
        .iter()
        .find_map(|e| match e {
            TraceEvent::Elsewhere { distance_m, place } => Some((*distance_m, place.clone())),
            _ => None,
        })
        .expect("a warning names the distance");
    assert!((distance - 55.0).abs() < 2.0, "{distance}");
    let first_move = events
        .iter()
        .find_map(|e| match e {
            TraceEvent::Launch { action, .. } if action.starts_with("move(") => {
                Some(action.clone())
            }
            _ => None,
        })
        .expect("a move is launched");
    assert!(
        first_move.starts_with(&format!("move({place}, ")),
        "the first move starts from the vehicle's place {place}: {first_move}"
    );
    assert!(
        run.report
            .goals
            .iter()
            .any(|g| g.fate == mavtempo::exec::executive::Fate::Achieved),
        "{:?}",
        run.report.goals
    );
}

#[test]
fn a_vehicle_at_base_is_not_moved_in_the_plan() {
    let setup = DemoSetup {
        upload: false,
        ..DemoSetup::default()
    };
    let run = run_demo(&setup, &mut |_| {}, &mut |_| {}).unwrap_or_else(|e| panic!("demo: {e}"));
    assert!(!run
        .report
        .cycles
        .iter()
        .flat_map(|c| &c.events)
        .any(|e| matches!(e, TraceEvent::Elsewhere { .. })));
}
