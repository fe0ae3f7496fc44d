//! A new goal never costs the goals already held (issue 15): its insertion is a bounded plan repair beside
//! *ExecutingPlan*; when it fails the new goal is rejected first, with the planner's reason, the plan stays
//! as it was and no running action is stopped. Seed 1 Fig. 2's rover on MockVehicle and its manual clock.

use crate::support::picture_goal;
use crate::support::rover_mock;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::{Executive, Fate};
use mavtempo_executive::exec::outcome::FateReason;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_vehicle::goals::GoalBatch;
use mavtempo_vehicle::mock::Scripted;
use mavtempo_vehicle::{GoalRequest, GoalVerdict, VehicleEvent};
use picture_goal::picture;
use rover_mock::{
    assert_both_achieved, events, executive, executive_with, fate, launches, nominal_rover, run,
};

/// The nominal rover_two mission; `goal`, if any, is requested 10 s into the first move.
fn mission(goal: Option<GoalRequest>) -> mavtempo_executive::exec::mission::MissionReport {
    let mut ex = executive();
    let mut v = nominal_rover();
    let mut goal = goal;
    run(&mut ex, &mut v, move |v, at, task| {
        if task == "move" {
            if let Some(g) = goal.take() {
                v.at(at + 10_000, Scripted::Goals(vec![g]));
            }
        }
    })
}

/// The plan's actions (task and arguments) and goals: what a failed insertion must leave as it was.
fn plan_text(ex: &Executive) -> (Vec<String>, usize, usize) {
    let actions = ex
        .plan()
        .live_actions()
        .map(|a| ex.action_text(a))
        .collect();
    (
        actions,
        ex.plan().goals().len(),
        ex.plan().problem().goals.len(),
    )
}

/// The repair parts of cycles at `now` until the insertions are over (at most `max` cycles), answering the
/// uploads as a cycle does.
fn insertion_cycles(ex: &mut Executive, now: i64, max: usize) -> usize {
    for n in 1..=max {
        ex.repair_phase(now, &|| now);
        ex.answer_goal_batches();
        if ex.insertion_queue().is_empty() {
            return n;
        }
    }
    panic!("insertions still in progress after {max} cycles");
}

#[test]
fn a_far_goal_is_rejected_first_and_the_mission_goes_on_as_without_it() {
    let base = mission(None);
    assert_both_achieved(&base);
    for (east, north) in [(500.0, 0.0), (50_000.0, 0.0), (0.0, 3_000_000.0)] {
        let r = mission(Some(picture("g6", east, north, 1)));
        let what = format!("far goal at ({east}, {north}) m");
        // The goals held: as without the far goal, with the same actions launched.
        assert_eq!(r.end, base.end, "{what}: {:?}", r.goals);
        assert_eq!(
            (fate(&r, "g1"), fate(&r, "g2")),
            (Fate::Achieved, Fate::Achieved),
            "{what}: {:?}",
            r.goals
        );
        assert_eq!(launches(&r), launches(&base), "{what}");
        // The far goal: rejected, with the planner's reason.
        let g6 = r
            .goals
            .iter()
            .find(|g| g.name == "g6")
            .expect("g6 reported");
        assert_eq!(g6.fate, Fate::Rejected, "{what}");
        // (Or at once, with the figure, when its last leg alone needs more than a full battery.)
        assert!(
            matches!(
                &g6.reason,
                Some(
                    FateReason::InsertionFailed {
                        dead_end: Some(_),
                        ..
                    } | FateReason::InsertionTimedOut {
                        dead_end: Some(_),
                        ..
                    }
                )
            ) || matches!(&g6.reason, Some(FateReason::BeyondLimits { why })
                if why.starts_with("getting there needs")),
            "{what}: {:?}",
            g6.reason
        );
        // Nothing stopped, aborted or replanned that the mission without the far goal did not (the rover is
        // slower than its model on the first leg: that move is stopped at its latest end in both runs).
        let disruptions =
            |r: &mavtempo_executive::exec::mission::MissionReport| -> Vec<TraceEvent> {
                events(r)
                    .into_iter()
                    .map(|(_, e)| e)
                    .filter(|e| {
                        matches!(
                            e,
                            TraceEvent::Stop { .. }
                                | TraceEvent::Abort { .. }
                                | TraceEvent::Replan { .. }
                        )
                    })
                    .collect()
            };
        assert_eq!(disruptions(&r), disruptions(&base), "{what}");
        assert!(
            !disruptions(&r)
                .iter()
                .any(|e| matches!(e, TraceEvent::Abort { .. } | TraceEvent::Replan { .. })),
            "{what}"
        );
        assert_eq!(r.counters.replans, 0, "{what}");
        // Bounded: at most the insertion's cycles of μ·n steps.
        let cfg = rover_mock::rover_config();
        let per_cycle = (cfg.repair_max_steps.unwrap_or(0) as f64 * cfg.repair_share).ceil() as u64;
        assert!(
            r.counters.insertion_steps <= u64::from(cfg.goal_insertion_cycles) * per_cycle,
            "{what}: {} steps",
            r.counters.insertion_steps
        );
    }
}

#[test]
fn a_failed_insertion_leaves_the_plan_as_it_was_and_says_why() {
    let mut ex = executive();
    let before = plan_text(&ex);
    // 198 m east of p4: its last leg needs 99 % of the battery, less than a full one (so it is searched
    // for), more than the mission can spare.
    let (batch, mut rx) = GoalBatch::new(vec![picture("g6", 232.0, 0.0, 1)]);
    ex.integrate(VehicleEvent::Goals(batch), 0);
    insertion_cycles(&mut ex, 0, 3);
    match rx.try_recv().expect("answered").as_slice() {
        // In the operator's words (the planner's detail is in the goal's fate, below).
        [GoalVerdict::Rejected(r)] => {
            assert_eq!(
                r,
                "not enough battery to get there and back to the goals held"
            )
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(plan_text(&ex), before);
    assert!(ex.abort().is_none());
    assert!(
        ex.goal_fates().iter().any(|f| f.name == "g6"
            && f.fate == Fate::Rejected
            // The executive's bounded search (never worded as a proof), its last dead end the battery.
            && matches!(&f.reason, Some(FateReason::InsertionFailed { failure, dead_end: Some(d) })
                if failure.contains("repeated insertions fails") && d.contains("BATTERY"))),
        "{:?}",
        ex.goal_fates()
    );
}

/// An insertion longer than the cycle in which the upload arrived: the upload is answered "verdict to
/// follow" at once, the verdict comes later; past `goal_insertion_cycles` the goal is rejected.
#[test]
fn an_insertion_longer_than_a_cycle_is_answered_then_decided() {
    let slow = |cycles| ExecConfig {
        // μ·n = 1 step per cycle.
        repair_max_steps: Some(1),
        goal_insertion_cycles: cycles,
        ..rover_mock::rover_config()
    };
    // p3 (24, 6) is reachable: accepted after some cycles.
    let mut ex = executive_with(slow(200));
    let (batch, mut rx, mut later) = GoalBatch::with_later(vec![
        picture("g6", 24.0, 6.0, 1),
        picture("g7", 1.0, 1.0, 1),
    ]);
    ex.integrate(VehicleEvent::Goals(batch), 0);
    ex.repair_phase(0, &|| 0);
    ex.answer_goal_batches();
    assert_eq!(
        rx.try_recv().expect("answered after the first cycle"),
        vec![GoalVerdict::Inserting, GoalVerdict::Inserting]
    );
    let cycles = insertion_cycles(&mut ex, 0, 400);
    assert!(cycles > 1);
    let mut verdicts = Vec::new();
    while let Ok(v) = later.try_recv() {
        verdicts.push(v);
    }
    assert_eq!(
        verdicts,
        vec![(0, GoalVerdict::Accepted), (1, GoalVerdict::Accepted)]
    );
    assert!(
        !ex.has_unanswered_uploads(),
        "settled uploads are forgotten"
    );
    // With a single cycle, the same goal is rejected and the plan kept.
    let mut ex = executive_with(slow(1));
    let before = plan_text(&ex);
    let (batch, mut rx) = GoalBatch::new(vec![picture("g6", 24.0, 6.0, 1)]);
    ex.integrate(VehicleEvent::Goals(batch), 0);
    insertion_cycles(&mut ex, 0, 1);
    match rx.try_recv().expect("answered").as_slice() {
        [GoalVerdict::Rejected(r)] => {
            assert!(r.starts_with("no plan found for it within 1 cycles"), "{r}")
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(plan_text(&ex), before);
}

/// Goals wait for their insertion one at a time, the highest priority first, and a far one among them
/// costs only itself.
#[test]
fn new_goals_are_inserted_highest_priority_first_each_on_its_own() {
    let mut ex = executive();
    let goals = vec![
        picture("g6", 24.0, 6.0, 1),
        picture("g7", 50_000.0, 0.0, 3),
        picture("g8", 34.0, 0.0, 2),
    ];
    let (batch, mut rx, mut later) = GoalBatch::with_later(goals);
    ex.integrate(VehicleEvent::Goals(batch), 0);
    // g7's last leg alone needs more than a full battery: refused as it arrives, never queued.
    let order: Vec<&str> = ex.insertion_queue();
    assert_eq!(order, ["g8", "g6"]);
    insertion_cycles(&mut ex, 0, 10);
    // Answered after the first cycle; the verdicts of the goals then still waiting follow.
    let mut verdicts = rx.try_recv().expect("answered");
    while let Ok((i, v)) = later.try_recv() {
        verdicts[i] = v;
    }
    assert!(
        matches!(verdicts[1], GoalVerdict::Rejected(_)),
        "{verdicts:?}"
    );
    assert_eq!(
        (&verdicts[0], &verdicts[2]),
        (&GoalVerdict::Accepted, &GoalVerdict::Accepted)
    );
    let decided: Vec<String> = ex
        .pending_events()
        .iter()
        .filter_map(|e| match e {
            TraceEvent::GoalAccepted { goal } | TraceEvent::GoalRejected { goal, .. } => {
                Some(goal.clone())
            }
            _ => None,
        })
        .collect();
    assert_eq!(decided, ["g7", "g8", "g6"]);
}

/// A goal whose insertion was cut by its cycles (which proves nothing) is tried again once the situation
/// changed — here a minute later — with twice the cycles, and accepted; its rejection is withdrawn.
#[test]
fn a_goal_cut_by_its_insertion_budget_is_tried_again_and_accepted() {
    let one_cycle = ExecConfig {
        // 12 steps a cycle: short of what the first, depth-first, attempt needs.
        repair_max_steps: Some(20),
        goal_insertion_cycles: 1,
        ..rover_mock::rover_config()
    };
    let mut ex = executive_with(one_cycle);
    let (batch, mut rx) = GoalBatch::new(vec![picture("g6", 24.0, 6.0, 1)]);
    ex.integrate(VehicleEvent::Goals(batch), 0);
    insertion_cycles(&mut ex, 0, 1);
    assert!(matches!(
        rx.try_recv().expect("answered").as_slice(),
        [GoalVerdict::Rejected(_)]
    ));
    let fate = |ex: &Executive| {
        ex.goal_fates()
            .into_iter()
            .filter(|f| f.name == "g6")
            .map(|f| f.fate)
            .collect::<Vec<_>>()
    };
    assert_eq!(fate(&ex), [Fate::Rejected]);
    assert_eq!(ex.parked_goals().collect::<Vec<_>>(), ["g6"]);
    // Nothing changed yet: it waits.
    ex.repair_phase(1_000, &|| 1_000);
    assert!(ex.insertion_queue().is_empty());
    // A minute later it is tried again, with more cycles, and accepted.
    let cycles = insertion_cycles(&mut ex, 61_000, 10);
    assert!(cycles >= 2, "{cycles}");
    assert_eq!(fate(&ex), [Fate::Pending]);
    assert!(ex.parked_goals().next().is_none());
    let (actions, _, _) = plan_text(&ex);
    assert!(
        actions.iter().any(|a| a == "take_picture(p3)"),
        "{actions:?}"
    );
}
