//! Where the vehicle is after an action that did not end as planned is a first-class place (issue 31,
//! "rejections are true"): a move reported done the instant it started (already within its waypoint
//! radius), a stopped move whose report comes after its latest end, an AUV survey or leg cut short away
//! from where it was going — in each case the next moves are planned from where the vehicle is, and no
//! goal is rejected as "no plan achieves it even alone". Deterministic: MockVehicle on its manual clock.

use crate::support::rover_mock;
use mavtempo_testkit::mapping;
use mavtempo_testkit::stops;

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::{Executive, Fate};
use mavtempo_executive::exec::mission::{run_mission, MissionOptions, MissionReport};
use mavtempo_executive::exec::pacer::MockPacer;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_temporal::lang::{load_domain, parse_problem};
use mavtempo_temporal::model::{Position, Value};
use mavtempo_temporal::plan::{PartialPlan, STerm};
use mavtempo_temporal::planner::{Budget, Search, StepOutcome};
use mavtempo_vehicle::mock::Outcome;
use mavtempo_vehicle::{Enu, MockVehicle, StateValue};
use rover_mock::{events, fate, launches, rover_config, run};

/// An executive over the planner's plan for `problem` (text) in the shipped `domain`.
fn executive(domain: &str, problem: &str, cfg: ExecConfig) -> Executive {
    let d = load_domain(Path::new(domain)).expect("shipped domain loads");
    let p = parse_problem("test", problem, &d).expect("problem parses");
    let root = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mut search = Search::new(root);
    assert_eq!(search.run(Budget::steps(50_000)), StepOutcome::Solved);
    let plan = search.into_plan();
    let mapping = if domain.contains("auv") {
        mapping::auv(&plan)
    } else {
        mapping::rover(&plan)
    };
    Executive::new(plan, cfg).with_mapping(mapping)
}

/// Every goal rejected, with its reason.
fn rejections(r: &MissionReport) -> Vec<String> {
    events(r)
        .into_iter()
        .filter_map(|(_, e)| match e {
            TraceEvent::GoalRejected { .. } => Some(format!("{e:?}")),
            _ => None,
        })
        .collect()
}

/// Seed 62288017's targets: t0 and t1 1.4 m apart, t2 30 m away.
const CLOSE_PAIR: &str = "problem close; domain rover; horizon 20min;
object base: location at (0, 0);
object t0: location at (5, 12);
object t1: location at (4, 13);
object t2: location at (21, -16);
initial {
    AT_ROBOT() = base; ROBOT_STATUS() = STILL; PTU_POS() = FORWARD; MVT_INIT() = T; PTU_INIT() = T;
    PICTURE(*) = false; COMMUNICATED(*) = false; VISIBLE() = NONE;
}
resource STORAGE: level 3, capacity 3;
resource BATTERY: level 100, capacity 100;
goal g0 priority 2 { hold(PICTURE(t0): true, (st, et)); }
goal g1 priority 1 { hold(PICTURE(t1): true, (st, et)); }
goal g2 priority 1 { hold(PICTURE(t2): true, (st, et)); }
";

fn picturing_rover() -> MockVehicle {
    let mut v = MockVehicle::new();
    v.set_level("BATTERY", 100.0).set_level("STORAGE", 3.0);
    v.script("move_ptu", Outcome::nominal(3_000));
    v.script("take_picture", Outcome::nominal(8_000));
    v
}

#[test]
fn a_move_reported_done_as_it_starts_leaves_the_rover_at_its_target() {
    let mut ex = executive(repo!("domains/rover/rover.ixt"), CLOSE_PAIR, rover_config());
    let mut v = picturing_rover();
    // base → t0 takes its time; t0 → t1 (1.4 m, within the waypoint radius) is done the instant it
    // starts; the move to t2 takes its time again.
    v.script("move", Outcome::nominal(30_000));
    v.script("move", Outcome::nominal(0));
    v.script("move", Outcome::nominal(80_000));
    let r = run(&mut ex, &mut v, |_, _, _| {});
    assert_eq!(rejections(&r), Vec::<String>::new());
    for g in ["g0", "g1", "g2"] {
        assert_eq!(fate(&r, g), Fate::Achieved, "{g}: {:?}", r.goals);
    }
    // The move after the instant one starts where that one ended, not from somewhere unknown.
    let moves: Vec<String> = launches(&r)
        .into_iter()
        .filter(|a| a.starts_with("move("))
        .collect();
    assert_eq!(moves.len(), 3, "{moves:?}");
    let second_to = moves[1]
        .trim_end_matches(')')
        .rsplit(", ")
        .next()
        .unwrap_or("");
    assert!(
        moves[2].starts_with(&format!("move({second_to}, ")),
        "{moves:?}"
    );
}

/// Two targets 19 m and 28 m from base.
const TWO_TARGETS: &str = "problem two; domain rover; horizon 30min;
object base: location at (0, 0);
object p1: location at (18, -6);
object p2: location at (24, 16);
initial {
    AT_ROBOT() = base; ROBOT_STATUS() = STILL; PTU_POS() = FORWARD; MVT_INIT() = T; PTU_INIT() = T;
    PICTURE(*) = false; COMMUNICATED(*) = false; VISIBLE() = NONE;
}
resource STORAGE: level 3, capacity 3;
resource BATTERY: level 90, capacity 100;
goal g1 priority 1 { hold(PICTURE(p1): true, (st, et)); }
goal g2 priority 1 { hold(PICTURE(p2): true, (st, et)); }
";

#[test]
fn a_stopped_move_reported_after_its_latest_end_is_replanned_from_where_it_stopped() {
    let mut ex = executive(
        repo!("domains/rover/rover.ixt"),
        TWO_TARGETS,
        rover_config(),
    );
    let mut v = picturing_rover();
    // The first move never arrives on its own; stopped late-preemptively at ub − ts, the autopilot takes
    // 2 s to stop, so its report comes after the move's latest end: execution is aborted.
    v.script("move", Outcome::nominal(600_000));
    v.script("move", Outcome::nominal(30_000));
    v.stops_after(2_000);
    stops::move_stops_at(&mut v, Enu::new(9.0, 1.0, 0.0));
    let r = run(&mut ex, &mut v, |_, _, _| {});
    let ev = events(&r);
    assert!(
        ev.iter()
            .any(|(_, e)| matches!(e, TraceEvent::Abort { .. })),
        "the late report aborts execution"
    );
    assert_eq!(rejections(&r), Vec::<String>::new());
    assert_eq!(fate(&r, "g1"), Fate::Achieved, "{:?}", r.goals);
    assert_eq!(fate(&r, "g2"), Fate::Achieved, "{:?}", r.goals);
    // The replanned mission starts from the place made where the rover stopped.
    let l = launches(&r);
    assert!(
        l.iter().any(|a| a.starts_with("move(L")),
        "a move from the new place: {l:?}"
    );
}

/// Seed 62288033's AUV: two vents, every route both ways, back at the surface at the horizon.
const VENTS: &str = "problem vents2; domain auv; horizon 10320s;
object surface: location at (0, 0, 0);
object vent1: location at (-343, -28, -172);
object vent2: location at (152, 127, -128);
initial {
    AUV_AT() = surface;
    CONNECTED(*, *) = false;
    CONNECTED(surface, vent1) = true; CONNECTED(surface, vent2) = true;
    CONNECTED(vent1, surface) = true; CONNECTED(vent1, vent2) = true;
    CONNECTED(vent2, surface) = true; CONNECTED(vent2, vent1) = true;
    SURVEYED(*) = false; SAMPLED(*) = false;
}
goal sample_vent1 external priority 1 { hold(SAMPLED(vent1): true, (st, et)); }
goal sample_vent2 external priority 1 { hold(SAMPLED(vent2): true, (st, et)); }
goal at_surface internal priority 1 { hold(AUV_AT(): surface, (st, et)); st in [10320s, 10320s]; }
";

/// An AUV whose legs take `go_ms` each; surveys and samples take their 10 min.
fn auv(go_ms: u64) -> MockVehicle {
    let mut v = MockVehicle::new();
    v.script("go", Outcome::nominal(go_ms));
    v.script("survey", Outcome::nominal(600_000));
    v.script("sample", Outcome::nominal(600_000));
    v
}

fn auv_config() -> ExecConfig {
    ExecConfig {
        timestep_ms: 2_000,
        ..ExecConfig::default()
    }
}

fn run_auv(ex: &mut Executive, v: &mut MockVehicle) -> MissionReport {
    let opts = MissionOptions {
        time_limit_ms: 10_400_000,
        ..MissionOptions::default()
    };
    run_mission(ex, v, &mut MockPacer::default(), &opts, &mut |_, _| {})
}

#[test]
fn an_auv_whose_survey_fails_away_from_the_vent_goes_on_from_there_and_comes_back_up() {
    let mut ex = executive(repo!("domains/auv/auv.ixt"), VENTS, auv_config());
    // Where the second survey is: the vent the plan visits second.
    let plan = ex.plan().clone();
    let mut surveys: Vec<_> = plan
        .live_actions()
        .filter(|&a| plan.domain().task(plan.action(a).task).name == "survey")
        .collect();
    surveys.sort_by_key(|&a| plan.earliest(plan.action(a).start));
    let vent = surveys
        .get(1)
        .and_then(|&a| plan.bindings().value(STerm::Var(plan.action(a).vars[0])))
        .and_then(|val| match val {
            Value::Obj(o) => plan.problem().object(o).cloned(),
            _ => None,
        })
        .expect("the plan surveys a vent");
    let Some(Position::Local { east, north, up }) = vent.position else {
        panic!("vents have local positions")
    };
    // The first survey goes well; the second fails (navigation lost) 40 m east of its vent: the AUV is
    // at a new place.
    let mut v = auv(300_000);
    v.script(
        "survey",
        Outcome::failed(100_000, "Navigation failed").with_state(
            "position",
            StateValue::Position(Enu::new(east + 40.0, north, up)),
        ),
    );
    v.script("survey", Outcome::nominal(600_000));
    let r = run_auv(&mut ex, &mut v);
    assert_eq!(rejections(&r), Vec::<String>::new());
    for g in ["sample_vent1", "sample_vent2", "at_surface"] {
        assert_eq!(fate(&r, g), Fate::Achieved, "{g}: {:?}", r.goals);
    }
    // From the new place the AUV goes straight back to the vent it was surveying.
    let l = launches(&r);
    assert!(
        l.iter()
            .any(|a| a.starts_with("go(L") && a.ends_with(&format!(", {})", vent.name))),
        "a leg from the new place back to {}: {l:?}",
        vent.name
    );
}

#[test]
fn an_auv_stopped_on_its_way_is_brought_back_to_the_surface_from_there() {
    let mut ex = executive(repo!("domains/auv/auv.ixt"), VENTS, auv_config());
    // The first leg fails halfway, where the AUV reports it is; the others go as planned.
    let mut v = auv(300_000);
    v.script(
        "go",
        Outcome::failed(150_000, "Navigation failed").with_state(
            "position",
            StateValue::Position(Enu::new(60.0, 50.0, -60.0)),
        ),
    );
    v.script("go", Outcome::nominal(120_000));
    let r = run_auv(&mut ex, &mut v);
    assert_eq!(fate(&r, "at_surface"), Fate::Achieved, "{:?}", r.goals);
    assert_eq!(rejections(&r), Vec::<String>::new());
}
