//! MockVehicle: scripted, deterministic, manual clock; every report kind and every event kind.

use mavtempo_testkit::stops;

use mavtempo_vehicle::mock::{Outcome, Scripted};
use mavtempo_vehicle::{
    ActionStart, Arg, CapacityChange, Enu, GoalKind, GoalRequest, LinkStatus, MockVehicle,
    ReportStatus, ResourceLevel, StateValue, Vehicle, VehicleError, VehicleEvent,
};

fn start(id: u64, task: &str) -> ActionStart {
    ActionStart {
        id,
        task: task.into(),
        args: vec![("to".into(), Arg::location("L2", Enu::new(10.0, 0.0, 0.0)))],
    }
}

fn drain(v: &mut MockVehicle) -> Vec<VehicleEvent> {
    std::iter::from_fn(|| v.try_event()).collect()
}

#[test]
fn nominal_report_arrives_at_its_time_with_final_levels() {
    let mut v = MockVehicle::new();
    v.set_level("battery", 90.0);
    v.script("move", Outcome::nominal(5000).with_level("battery", 80.0));
    v.start(start(1, "move")).expect("scripted");
    v.advance(4999);
    assert!(v.try_event().is_none());
    v.advance(1);
    let Some(VehicleEvent::Report(r)) = v.try_event() else {
        panic!("report expected")
    };
    assert_eq!(
        (r.id, r.status, r.time_ms),
        (1, ReportStatus::Nominal, 5000)
    );
    assert_eq!(
        r.resources,
        vec![ResourceLevel {
            resource: "battery".into(),
            level: 80.0
        }]
    );
    assert!(r.state.is_empty(), "nominal reports carry no state values");
}

#[test]
fn stop_gives_an_interrupted_report_with_the_state_and_no_later_report() {
    let mut v = MockVehicle::new();
    v.script("move", Outcome::nominal(5000));
    stops::move_stops_at(&mut v, Enu::new(4.0, 0.0, 0.0));
    v.start(start(1, "move")).expect("scripted");
    v.advance(2000);
    v.stop(1).expect("running");
    let Some(VehicleEvent::Report(r)) = v.try_event() else {
        panic!("report expected")
    };
    assert_eq!((r.status, r.time_ms), (ReportStatus::Interrupted, 2000));
    assert_eq!(
        r.state,
        vec![(
            "position".into(),
            StateValue::Position(Enu::new(4.0, 0.0, 0.0))
        )]
    );
    v.advance(10_000);
    assert!(
        v.try_event().is_none(),
        "the stopped action never reports again"
    );
    assert_eq!(v.stop(1), Err(VehicleError::NotRunning(1)));
    assert_eq!(
        v.log,
        vec!["0 START move 1".to_string(), "2000 END 1".to_string()]
    );
}

#[test]
fn failed_report_carries_reason_and_state_and_outcomes_queue_up() {
    let mut v = MockVehicle::new();
    v.script(
        "take_picture",
        Outcome::failed(100, "capture_result 0")
            .with_state("camera", StateValue::Symbol("off".into())),
    );
    v.script("take_picture", Outcome::nominal(300));
    v.start(start(1, "take_picture")).expect("scripted");
    v.start(start(2, "take_picture")).expect("scripted");
    v.advance(1000);
    let events = drain(&mut v);
    let reports: Vec<_> = events
        .iter()
        .filter_map(|e| match e {
            VehicleEvent::Report(r) => Some((r.id, r.status, r.reason.clone(), r.state.len())),
            _ => None,
        })
        .collect();
    assert_eq!(
        reports,
        vec![
            (1, ReportStatus::Failed, Some("capture_result 0".into()), 1),
            (2, ReportStatus::Nominal, None, 0)
        ]
    );
}

#[test]
fn exogenous_events_come_in_time_order() {
    let mut v = MockVehicle::new();
    let goal = GoalRequest {
        name: "g6".into(),
        kind: GoalKind::PictureOf,
        proposition: "picture_of(L6)".into(),
        location: None,
        priority: 2,
        start_window_s: (0.0, 500.0),
        duration_s: (0.0, f64::INFINITY),
        d_achiev_s: 60.0,
    };
    v.at(300, Scripted::Goals(vec![goal.clone()]));
    v.at(
        100,
        Scripted::Capacity(CapacityChange {
            resource: "storage".into(),
            capacity: 800.0,
            delta: -200.0,
        }),
    );
    v.at(
        200,
        Scripted::Resource(ResourceLevel {
            resource: "battery".into(),
            level: 40.0,
        }),
    );
    v.at(400, Scripted::Link(LinkStatus::Lost));
    v.advance_to(350);
    let events = drain(&mut v);
    assert!(matches!(&events[0], VehicleEvent::Capacity(c) if c.delta == -200.0));
    assert!(matches!(&events[1], VehicleEvent::Resource(r) if r.level == 40.0));
    assert!(matches!(&events[2], VehicleEvent::Goals(b) if b.goals == vec![goal.clone()]));
    assert_eq!(events.len(), 3);
    v.advance_to(400);
    assert!(matches!(
        v.try_event(),
        Some(VehicleEvent::Link(LinkStatus::Lost))
    ));
    assert_eq!(v.now_ms(), 400);
}

#[test]
fn unscripted_task_and_duplicate_id_are_refused() {
    let mut v = MockVehicle::new();
    assert_eq!(
        v.start(start(1, "fly")),
        Err(VehicleError::UnknownTask("fly".into()))
    );
    v.script("move", Outcome::nominal(10));
    v.start(start(1, "move")).expect("scripted");
    assert_eq!(
        v.start(start(1, "move")),
        Err(VehicleError::AlreadyRunning(1))
    );
}
