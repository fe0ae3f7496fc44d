//! The executive's reactions of seed 1 Fig. 2 on the rover, planned by the planner and executed by
//! `run_mission` against MockVehicle on its manual clock (deterministic): e1 a picture fails → plan repair
//! with a new picture; e2 a move too slow is stopped late-preemptively → the rover is at a new location
//! and plan repair moves it on from there; e3/e4 new goals requested during the mission → one accepted,
//! added by plan repair and achieved, one rejected by the acceptance test; e6 the battery drops while moving → a recharge enters the plan before the next
//! move. Problem: tests/fixtures/exec/rover_two.ixt (Fig. 2's world, goals g1 and g2).

use crate::support::rover_mock;
use mavtempo_testkit::stops;

use mavtempo_executive::exec::executive::Fate;
use mavtempo_executive::exec::goal_request::Rejection;
use mavtempo_executive::exec::mission::MissionEnd;
use mavtempo_executive::exec::outcome::FateReason;
use mavtempo_executive::exec::resource_report::LevelVerdict;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_vehicle::mock::{Outcome, Scripted};
use mavtempo_vehicle::ReportStatus;
use mavtempo_vehicle::{Enu, GoalKind, GoalLocation, GoalRequest, ResourceLevel};
use rover_mock::{
    assert_both_achieved, events, executive, fate, launches, moving_rover, nominal_rover, pictures,
    rover, run,
};

#[test]
fn nominal_mission_achieves_both_goals_without_repair() {
    let mut ex = executive();
    let mut v = nominal_rover();
    let r = run(&mut ex, &mut v, |_, _, _| {});
    assert_eq!(r.end, MissionEnd::Finished, "{:?}", r.goals);
    assert_both_achieved(&r);
    assert_eq!(r.counters.replans, 0);
    assert_eq!(launches(&r).len(), 7, "{:?}", launches(&r));
}

#[test]
fn e1_failed_picture_is_repaired_with_a_new_picture() {
    let mut ex = executive();
    let mut v = moving_rover();
    v.script("take_picture", Outcome::failed(8_000, "image not captured"));
    v.script(
        "take_picture",
        Outcome::nominal(8_000).with_level("STORAGE", 2.1),
    );
    let r = run(&mut ex, &mut v, |_, _, _| {});
    assert_eq!(r.end, MissionEnd::Finished, "{:?}", r.goals);
    let ev = events(&r);
    let failed_at = ev
        .iter()
        .find(|(_, e)| matches!(e, TraceEvent::Report { status, .. } if *status == ReportStatus::Failed))
        .map(|(t, _)| *t)
        .expect("the failure is reported");
    // Plan repair (not replanning) puts a second picture of the same target in the plan.
    assert!(ev
        .iter()
        .any(|(t, e)| *t >= failed_at && matches!(e, TraceEvent::RepairDone { .. })));
    assert_eq!(r.counters.replans, 0);
    let pictures = pictures(&r);
    assert_eq!(pictures.len(), 3, "{pictures:?}");
    assert_eq!(
        pictures[0], pictures[1],
        "the failed picture is taken again"
    );
    assert_both_achieved(&r);
}

/// A picture that hangs (seed 1 Fig. 2's e2): its end times out, execution is aborted and the camera is
/// stopped; the replanned mission takes that picture again before its goal counts as achieved. (Over
/// sockets, where the executive ends the cut-off picture itself before its report, tests/cli/cli_demo.rs checks
/// the same: g2's hung picture never counts as taken.)
#[test]
fn a_hung_picture_cut_off_by_an_abort_is_taken_again() {
    let mut ex = executive();
    let mut v = moving_rover();
    v.script("take_picture", Outcome::nominal(3_600_000));
    v.script(
        "take_picture",
        Outcome::nominal(8_000).with_level("STORAGE", 2.1),
    );
    v.script(
        "take_picture",
        Outcome::nominal(8_000).with_level("STORAGE", 1.2),
    );
    let r = run(&mut ex, &mut v, |_, _, _| {});
    let ev = events(&r);
    assert!(ev
        .iter()
        .any(|(_, e)| matches!(e, TraceEvent::Timeout { .. })));
    assert!(r.counters.replans >= 1);
    let pictures = pictures(&r);
    assert_eq!(pictures.len(), 3, "{pictures:?}");
    assert_eq!(pictures[0], pictures[1], "the hung picture is taken again");
    assert_both_achieved(&r);
}

#[test]
fn e2_slow_move_is_stopped_and_the_rover_moves_on_from_a_new_location() {
    let mut ex = executive();
    let mut v = rover();
    // The first move never arrives on its own (rough ground): stopped where it is, short of its target.
    v.script("move", Outcome::nominal(600_000));
    v.script("move", Outcome::nominal(14_000).with_level("BATTERY", 80.5));
    v.script("move", Outcome::nominal(28_500).with_level("BATTERY", 74.1));
    stops::move_stops_at(&mut v, Enu::new(13.0, -3.0, 0.0));
    v.script(
        "take_picture",
        Outcome::nominal(8_000).with_level("STORAGE", 2.1),
    );
    let r = run(&mut ex, &mut v, |_, _, _| {});
    let ev = events(&r);
    // Late-preemptive: END at ub − ts, before any timeout.
    let stop = ev
        .iter()
        .find_map(|(t, e)| match e {
            TraceEvent::Stop { action, .. } => Some((*t, action.clone())),
            _ => None,
        })
        .expect("the slow move is stopped");
    // The first move, whichever target the plan visits first.
    let target = stop
        .1
        .strip_prefix("move(base, ")
        .expect("the first move is stopped")
        .to_string();
    assert!(!ev
        .iter()
        .any(|(_, e)| matches!(e, TraceEvent::Timeout { .. })));
    // The next move starts from the new location object where the rover stopped.
    let l = launches(&r);
    let from_new = l
        .iter()
        .find(|a| a.starts_with("move(L"))
        .expect("a move from the new location");
    assert!(from_new.ends_with(&format!(", {target}")), "{from_new}");
    assert_eq!(r.counters.replans, 0);
    assert_both_achieved(&r);
}

#[test]
fn e3_e4_new_goals_accepted_and_achieved_or_rejected_by_the_acceptance_test() {
    let mut ex = executive();
    let mut v = moving_rover();
    v.script("move", Outcome::nominal(25_000).with_level("BATTERY", 68.0));
    v.script(
        "take_picture",
        Outcome::nominal(8_000).with_level("STORAGE", 2.1),
    );
    let goal = |name: &str, kind: GoalKind, place: &str, at: Enu, window_s: f64| GoalRequest {
        name: name.into(),
        kind,
        proposition: format!("{}({place})", kind.predicate()),
        location: Some(GoalLocation {
            name: place.into(),
            new: false,
            at,
            lat: 0.0,
            lon: 0.0,
        }),
        priority: 1,
        start_window_s: (0.0, window_s),
        duration_s: (0.0, f64::INFINITY),
        d_achiev_s: 60.0,
    };
    // g6: be back at the base at the end (a return the repair adds); g7: a picture of a new target that
    // must start within the first minute but needs 60 s: rejected by the acceptance test.
    let goals = vec![
        goal("g6", GoalKind::BeAt, "base", Enu::default(), 1_800.0),
        goal(
            "g7",
            GoalKind::PictureOf,
            "t7",
            Enu::new(30.0, -8.0, 0.0),
            60.0,
        ),
    ];
    let mut sent = false;
    let r = run(&mut ex, &mut v, move |v, at, task| {
        // During the first picture, about 47 s into the mission.
        if task == "take_picture" && !sent {
            sent = true;
            v.at(at + 2_000, Scripted::Goals(goals.clone()));
        }
    });
    let ev = events(&r);
    assert!(ev
        .iter()
        .any(|(_, e)| matches!(e, TraceEvent::GoalAccepted { goal } if goal == "g6")));
    assert!(ev
        .iter()
        .any(|(_, e)| matches!(e, TraceEvent::GoalRejected { goal, reason: FateReason::Acceptance(Rejection::TooLate { .. }) } if goal == "g7")));
    assert_eq!(fate(&r, "g6"), Fate::Achieved, "{:?}", r.goals);
    assert!(r.plan_changes.iter().any(|c| c.cause == "goal_added"));
    assert!(
        launches(&r)
            .iter()
            .any(|a| a.starts_with("move(") && a.ends_with(", base)")),
        "{:?}",
        launches(&r)
    );
    assert_both_achieved(&r);
}

#[test]
fn e6_battery_drop_while_moving_brings_a_recharge_before_the_next_move() {
    let mut ex = executive();
    let mut v = nominal_rover();
    // The planned recharge is the shortest (60 s, +5 %; early-preemptive, stopped at its earliest end):
    // it reports its level just before.
    v.script(
        "recharge_battery",
        Outcome::nominal(59_000).with_level("BATTERY", 8.0),
    );
    let mut first = true;
    let r = run(&mut ex, &mut v, move |v, at, task| {
        // 20 s into the first move the battery falls to 3 %: not enough for the second (6.4 %).
        if task == "move" && first {
            first = false;
            v.at(
                at + 20_000,
                Scripted::Resource(ResourceLevel {
                    resource: "BATTERY".into(),
                    level: 3.0,
                }),
            );
        }
    });
    let ev = events(&r);
    assert!(ev.iter().any(|(_, e)| matches!(
        e,
        TraceEvent::Level { resource, verdict, .. } if resource == "BATTERY" && matches!(verdict, LevelVerdict::OverConsumption { .. })
    )));
    let l = launches(&r);
    let recharge = l
        .iter()
        .position(|a| a.starts_with("recharge_battery"))
        .unwrap_or_else(|| panic!("a recharge is launched: {l:?}"));
    let second_move = l
        .iter()
        .rposition(|a| a.starts_with("move("))
        .expect("moves");
    assert!(recharge < second_move, "{l:?}");
    assert_both_achieved(&r);
}
