//! Issue 30 item 7: a move ends still where the next action needs the vehicle still. The domain says
//! which: take_picture holds `ROBOT_STATUS(): STILL`, the `[state] moving` attribute of the vehicle
//! configuration; a causal link from a move's end to such a hold makes the executive start the move with
//! `start_still`. A move followed by a move (or by a goal that only asks to be there) is started as before.

use mavtempo_testkit::mapping;

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::Executive;
use mavtempo_executive::exec::mission::{run_mission, MissionOptions};
use mavtempo_executive::exec::pacer::MockPacer;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_temporal::lang::{load_domain, parse_problem};
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_temporal::planner::{Budget, Search, StepOutcome};
use mavtempo_vehicle::mock::Outcome;
use mavtempo_vehicle::observed::Flag;
use mavtempo_vehicle::MockVehicle;

/// A picture of p1, then be at p4: move(base, p1) serves the picture, move(p1, p4) only the place.
const PROBLEM: &str = "problem still; domain rover; horizon 30min;
object base: location at (0, 0);
object p1: location at (10, 4);
object p4: location at (34, 0);
initial {
    AT_ROBOT() = base; ROBOT_STATUS() = STILL; PTU_POS() = FORWARD; MVT_INIT() = T; PTU_INIT() = T;
    PICTURE(*) = false; COMMUNICATED(*) = false; VISIBLE() = NONE;
}
resource STORAGE: level 3, capacity 3;
resource BATTERY: level 90, capacity 100;
goal g1 priority 1 { hold(PICTURE(p1): true, (st, et)); st in [0, 30min]; achieve 25s; }
goal g2 priority 1 { hold(AT_ROBOT(): p4, (st, et)); st in [0, 30min]; achieve 5s; }
";

/// The moves launched (task line of the mock's log with its action id) and which of them were still.
fn run(still: Option<&Flag>) -> Vec<(String, bool)> {
    let d = load_domain(Path::new(repo!("domains/rover/rover.ixt"))).expect("rover loads");
    let p = parse_problem("still.ixt", PROBLEM, &d).expect("problem");
    let root = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mut search = Search::new(root);
    assert_eq!(search.run(Budget::steps(20_000)), StepOutcome::Solved);
    let plan = search.into_plan();
    let mapping = mapping::rover(&plan);
    let cfg = ExecConfig {
        timestep_ms: 1_300,
        repair_max_steps: Some(500),
        ..ExecConfig::default()
    };
    let mut ex = Executive::new(plan, cfg)
        .with_mapping(mapping)
        .with_still_state(still);
    let mut v = MockVehicle::new();
    v.set_level("BATTERY", 90.0).set_level("STORAGE", 3.0);
    v.script("move", Outcome::nominal(25_000).with_level("BATTERY", 84.6));
    v.script("move", Outcome::nominal(55_000).with_level("BATTERY", 72.3));
    v.script("move_ptu", Outcome::nominal(3_000));
    v.script(
        "take_picture",
        Outcome::nominal(8_000).with_level("STORAGE", 2.1),
    );
    let opts = MissionOptions {
        time_limit_ms: 30 * 60_000,
        ..MissionOptions::default()
    };
    let r = run_mission(
        &mut ex,
        &mut v,
        &mut MockPacer::default(),
        &opts,
        &mut |_, _| {},
    );
    r.cycles
        .iter()
        .flat_map(|c| &c.events)
        .filter_map(|e| match e {
            TraceEvent::Launch { action, vid, .. } if action.starts_with("move(") => {
                Some((action.clone(), v.still_starts.contains(vid)))
            }
            _ => None,
        })
        .collect()
}

#[test]
fn a_move_before_a_picture_ends_still_and_a_move_to_a_place_does_not() {
    let flag = Flag {
        attribute: "ROBOT_STATUS".into(),
        yes: "MOVING".into(),
        no: "STILL".into(),
    };
    assert_eq!(
        run(Some(&flag)),
        vec![
            ("move(base, p1)".to_string(), true),
            ("move(p1, p4)".to_string(), false),
        ]
    );
    // No `[state] moving` (or `end_still = false`): every move ends within its radius, as before.
    assert!(run(None).iter().all(|(_, still)| !still));
}
