//! Nothing loops (src/executive/src/exec/failures.rs, settle.rs): an action failing the same way again and again, or a
//! task the vehicle refuses, is settled — its goals rejected with the true reason — instead of being
//! repaired or replanned for ever.

use crate::support::mission;
use crate::support::shopping;

use std::collections::BTreeMap;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::{Executive, Fate};
use mavtempo_executive::exec::mission::{MissionEnd, MissionReport};
use mavtempo_executive::exec::outcome::{AbortReason, FateReason};
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_vehicle::mock::Outcome;
use mavtempo_vehicle::MockVehicle;

fn shopping(k: u32) -> Executive {
    shopping::day_executive(ExecConfig {
        same_failure_limit: k,
        ..shopping::day_config()
    })
}

fn run(ex: &mut Executive, v: &mut MockVehicle) -> MissionReport {
    mission::run_mock(ex, v, 13 * 3_600_000)
}

fn launches(r: &MissionReport) -> BTreeMap<String, usize> {
    let mut n = BTreeMap::new();
    for e in r.cycles.iter().flat_map(|c| &c.events) {
        if let TraceEvent::Launch { action, .. } = e {
            *n.entry(action.clone()).or_default() += 1;
        }
    }
    n
}

fn fate<'a>(r: &'a MissionReport, goal: &str) -> &'a mavtempo_executive::exec::executive::GoalFate {
    r.goals
        .iter()
        .find(|g| g.name == goal)
        .unwrap_or_else(|| panic!("goal {goal} in the report"))
}

#[test]
fn an_action_failing_the_same_way_k_times_rejects_its_goal_with_that_failure() {
    for k in [2, 3] {
        let mut ex = shopping(k);
        let mut v = MockVehicle::new();
        v.script("go", Outcome::nominal(16 * 60_000));
        v.script("buy", Outcome::failed(60_000, "till closed"));
        let r = run(&mut ex, &mut v);
        assert_eq!(r.end, MissionEnd::Finished, "k={k}: {:?}", r.goals);
        let apple = fate(&r, "have_apple");
        assert_eq!(apple.fate, Fate::Rejected, "k={k}");
        assert!(
            matches!(&apple.reason, Some(FateReason::InstanceBanned { ban })
            if ban.contains("buy(apple, grocery)")
                && ban.contains("till closed")
                && ban.contains(&format!("{k} times in a row"))),
            "k={k}: {:?}",
            apple.reason
        );
        assert_eq!(launches(&r).get("buy(apple, grocery)"), Some(&(k as usize)));
        // The goal that did not need it is still achieved.
        assert_eq!(fate(&r, "at_home").fate, Fate::Achieved, "k={k}");
    }
}

#[test]
fn a_task_the_vehicle_refuses_is_not_replanned_for_ever() {
    let mut ex = shopping(3);
    let mut v = MockVehicle::new();
    // No script for `buy`: the vehicle refuses to start it (as a config without its binding would).
    v.script("go", Outcome::nominal(16 * 60_000));
    let r = run(&mut ex, &mut v);
    assert_eq!(r.end, MissionEnd::Finished, "{:?}", r.goals);
    let apple = fate(&r, "have_apple");
    assert_eq!(apple.fate, Fate::Rejected);
    assert!(
        matches!(&apple.reason, Some(FateReason::InstanceBanned { ban })
            if ban.contains("refused by the vehicle")),
        "{:?}",
        apple.reason
    );
    assert!(
        r.counters.replans <= 4,
        "{} replannings",
        r.counters.replans
    );
    assert!(launches(&r).values().all(|&n| n <= 3), "{:?}", launches(&r));
}

#[test]
fn a_failure_that_changes_is_bounded_by_the_plan_change_rate() {
    let mut ex = shopping::day_executive(ExecConfig {
        same_failure_limit: 100,
        max_plan_changes_per_min: 1,
        ..shopping::day_config()
    });
    let mut v = MockVehicle::new();
    v.script("go", Outcome::nominal(16 * 60_000));
    // A different failure each time: no streak, but the plan keeps changing.
    for i in 0..50 {
        v.script(
            "buy",
            Outcome::failed(1_000, &format!("error code {}", "x".repeat(i))),
        );
    }
    let r = run(&mut ex, &mut v);
    assert_eq!(r.end, MissionEnd::Finished, "{:?}", r.goals);
    let apple = fate(&r, "have_apple");
    assert_eq!(apple.fate, Fate::Rejected);
    assert!(
        matches!(apple.reason, Some(FateReason::PlanChurn(_))),
        "{:?}",
        apple.reason
    );
    assert!(launches(&r)
        .get("buy(apple, grocery)")
        .is_some_and(|&n| n < 10));
}

#[test]
fn a_plan_repair_that_does_not_converge_is_given_up_for_a_replanning() {
    // One step of repair per cycle, at most 3 in all: the repair after the failed `buy` needs more.
    let mut ex = shopping::day_executive(ExecConfig {
        repair_max_steps: Some(1),
        repair_share: 1.0,
        repair_episode_max_steps: 3,
        ..shopping::day_config()
    });
    let mut v = MockVehicle::new();
    v.script("go", Outcome::nominal(16 * 60_000));
    v.script("buy", Outcome::failed(60_000, "till closed"));
    v.script("buy", Outcome::nominal(60_000));
    let r = run(&mut ex, &mut v);
    let aborts: Vec<&AbortReason> = r
        .cycles
        .iter()
        .flat_map(|c| &c.events)
        .filter_map(|e| match e {
            TraceEvent::Abort { reason } => Some(reason),
            _ => None,
        })
        .collect();
    assert!(
        aborts
            .iter()
            .any(|a| matches!(a, AbortReason::RepairDiverged { .. })),
        "{aborts:?}"
    );
    assert!(r.counters.replans >= 1);
    assert_eq!(r.end, MissionEnd::Finished, "{:?}", r.goals);
    assert!(
        r.goals.iter().all(|g| g.fate != Fate::Pending),
        "{:?}",
        r.goals
    );
}
