//! The executive's cycle against MockVehicle with the manual clock (deterministic): launches, reports in
//! bounds / early / late, late-preemptive stops, postponement, goal requests, capacity alteration.

use mavtempo_testkit::mapping;
use mavtempo_testkit::stops;

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::cycle::CycleOutcome;
use mavtempo_executive::exec::executive::{Executive, Fate};
use mavtempo_executive::exec::goal_request::Rejection;
use mavtempo_executive::exec::outcome::{AbortReason, FateReason};
use mavtempo_executive::exec::report_timing::Timing;
use mavtempo_executive::exec::resource_report::LevelVerdict;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_temporal::lang::load_problem_and_domain;
use mavtempo_temporal::model::{Goal, GoalOrigin, Time, TimeInterval, Value};
use mavtempo_temporal::plan::{ActionId, PartialPlan};
use mavtempo_vehicle::mock::{Outcome, Scripted};
use mavtempo_vehicle::{CapacityChange, Enu, MockVehicle};

/// fig2's world without its goals, and one goal: a picture of `loc`.
fn world(goal_loc: &str) -> PartialPlan {
    let (d, mut p) = load_problem_and_domain(Path::new(repo!("domains/rover/problems/fig2.ixt")))
        .expect("fig2 loads");
    let attr = d.attr_id("PICTURE").expect("PICTURE");
    let mut g: Goal = p.goals[0].clone();
    g.name = "gb".into();
    g.attr = attr;
    g.args = vec![p.object_id(goal_loc).expect("loc")];
    g.value = Value::Obj(mavtempo_temporal::model::Domain::TRUE);
    g.start_window = TimeInterval::closed(0, 30 * 60_000);
    g.kind = GoalOrigin::External;
    p.goals = vec![g];
    PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan")
}

/// An executive over `plan` with the rover's mapping (config/demo-rover.toml).
fn executive(plan: PartialPlan) -> Executive {
    let mapping = mapping::rover(&plan);
    Executive::new(plan, cfg()).with_mapping(mapping)
}

fn insert(plan: &mut PartialPlan, task: &str, args: &[&str]) -> ActionId {
    let t = plan.domain().task_id(task).expect("task");
    let a = plan.insert_action(t).expect("insert");
    for (i, name) in args.iter().enumerate() {
        let v = plan.action(a).vars[i];
        let o = plan
            .problem()
            .object_id(name)
            .or_else(|| plan.domain().object_id(name))
            .expect("object");
        plan.bind_var(v, o).expect("bind");
    }
    plan.repropagate_action(a).expect("numeric");
    a
}

/// Supports every open condition by the most recent event that can establish it (a tiny greedy
/// completion for hand-built plans), then checks the plan is a solution.
fn support_all(plan: &mut PartialPlan) {
    let open: Vec<_> = plan.open_conditions().collect();
    for c in open {
        let attr = plan.cond(c).attr;
        let events: Vec<_> = plan.events_on(attr).iter().rev().copied().collect();
        let ok = events.into_iter().any(|e| {
            let lvl = plan.save();
            let ok = plan.add_link(e, c).is_ok();
            if !ok {
                plan.restore(lvl);
            }
            ok
        });
        assert!(ok, "no support for {}", plan.cond_text(c));
    }
    // Threats: the threatening event before the establisher, else after the protected interval.
    for (e, l) in plan.live_threats() {
        let at = plan.event(e).at;
        let est = plan.event(plan.link(l).event).at;
        let to = plan.cond(plan.link(l).cond).to;
        let lvl = plan.save();
        if plan
            .constrain(at, est, 1, mavtempo_temporal::stn::INF)
            .is_err()
        {
            plan.restore(lvl);
            plan.constrain(to, at, 1, mavtempo_temporal::stn::INF)
                .expect("threat resolvable");
        }
    }
    let flaws = plan.flaws();
    assert!(
        flaws.is_empty(),
        "{:?}",
        flaws.iter().map(|f| plan.flaw_text(f)).collect::<Vec<_>>()
    );
}

/// move_ptu(FORWARD, DOWN) then take_picture(base): a picture of the base.
fn picture_plan() -> PartialPlan {
    let mut plan = world("base");
    let m = insert(&mut plan, "move_ptu", &["FORWARD", "DOWN"]);
    let p = insert(&mut plan, "take_picture", &["base"]);
    plan.order(plan.action(m).end, plan.action(p).start)
        .expect("order");
    support_all(&mut plan);
    plan
}

/// The executive over `picture_plan` and a vehicle whose PTU move takes 3 s and whose picture does `picture`.
fn picture_run(picture: Outcome) -> (Executive, MockVehicle) {
    let ex = executive(picture_plan());
    let mut v = MockVehicle::new();
    v.script("move_ptu", Outcome::nominal(3_000));
    v.script("take_picture", picture);
    (ex, v)
}

fn cfg() -> ExecConfig {
    ExecConfig {
        timestep_ms: 1_000,
        repair_share: 0.6,
        replan_slack_ms: 1_000,
        repair_max_steps: Some(50),
        ..ExecConfig::default()
    }
}

/// Runs cycles every 500 ms of manual time until finished, aborted or `until`.
fn run(ex: &mut Executive, v: &mut MockVehicle, until: Time) -> (CycleOutcome, Time) {
    let mut t = 0;
    loop {
        v.advance_to(t as u64);
        let out = ex.cycle(v, t);
        if !matches!(out, CycleOutcome::Continue { .. }) || t >= until {
            return (out, t);
        }
        t += 500;
    }
}

fn events(ex: &Executive) -> Vec<(Time, TraceEvent)> {
    ex.cycles()
        .records()
        .iter()
        .flat_map(|c| c.events.iter().map(move |e| (c.time_ms, e.clone())))
        .collect()
}

fn launch_time(ex: &Executive, prefix: &str) -> Option<Time> {
    events(ex).into_iter().find_map(|(t, e)| match e {
        TraceEvent::Launch { action, .. } if action.starts_with(prefix) => Some(t),
        _ => None,
    })
}

#[test]
fn nominal_run_launches_in_order_and_achieves_the_goal() {
    let (mut ex, mut v) = picture_run(Outcome::nominal(8_000).with_level("STORAGE", 2.1));
    let (out, _) = run(&mut ex, &mut v, 60_000);
    assert_eq!(out, CycleOutcome::Finished);
    // Start timepoints at their lb: move_ptu's is 1 ms (after the initial state), so the first cycle after it.
    assert_eq!(launch_time(&ex, "move_ptu"), Some(500));
    // The picture as soon as the PTU is down (report at 3.5 s, start 1 ms later, next cycle).
    assert_eq!(launch_time(&ex, "take_picture"), Some(4_000));
    assert_eq!(ex.goal_fates()[0].fate, Fate::Achieved);
    // Both actions are past: they left the plan, their effects are in S_t.
    assert_eq!(ex.plan().num_actions(), 0);
    let r = ex.resource("STORAGE").unwrap();
    assert!(
        (ex.past_levels()[r.index()].0 - 2.1).abs() < 1e-9,
        "the level is exact after the report"
    );
}

#[test]
fn report_too_early_creates_a_new_end_and_the_goal_is_still_achieved() {
    // take_picture lasts at least 5 s; the report comes after 2 s.
    let (mut ex, mut v) = picture_run(Outcome::nominal(2_000).with_level("STORAGE", 2.1));
    let (out, _) = run(&mut ex, &mut v, 60_000);
    assert_eq!(out, CycleOutcome::Finished);
    let start = launch_time(&ex, "take_picture").expect("launched");
    assert!(events(&ex).iter().any(|(t, e)| *t == start + 2_000
        && matches!(
            e,
            TraceEvent::Report {
                timing: Timing::TooEarly,
                ..
            }
        )));
    assert_eq!(ex.goal_fates()[0].fate, Fate::Achieved);
}

#[test]
fn missing_report_of_a_non_preemptive_action_times_out() {
    let (mut ex, mut v) = picture_run(Outcome::nominal(60_000));
    let (out, t) = run(&mut ex, &mut v, 60_000);
    match out {
        CycleOutcome::Aborted(reason) => {
            assert!(matches!(reason, AbortReason::Timeout { .. }), "{reason}")
        }
        o => panic!("{o:?}"),
    }
    // take_picture lasts at most 20 s: the timeout is detected in the first cycle after start + 20 s.
    let start = launch_time(&ex, "take_picture").expect("launched");
    assert_eq!(t, start + 20_500);
}

#[test]
fn over_consumption_reported_is_integrated_and_repair_requested() {
    // The picture used 1.5 slots: below RscL_lb = 2.
    let (mut ex, mut v) = picture_run(Outcome::nominal(8_000).with_level("STORAGE", 1.5));
    let (out, _) = run(&mut ex, &mut v, 60_000);
    assert_eq!(out, CycleOutcome::Finished);
    assert!(events(&ex).iter().any(|(_, e)| matches!(
        e,
        TraceEvent::Level {
            verdict: LevelVerdict::OverConsumption { .. },
            ..
        }
    )));
    let r = ex.resource("STORAGE").unwrap();
    assert!((ex.past_levels()[r.index()].0 - 1.5).abs() < 1e-9);
}

#[test]
fn late_preemptive_move_is_stopped_at_ub_minus_ts() {
    let mut plan = world("p1");
    let m = insert(&mut plan, "move", &["base", "p1"]);
    let mut ex = {
        // No picture: only the move; its goal stays pending, the test looks at the stop.
        executive(plan)
    };
    let mut v = MockVehicle::new();
    // Far slower than the model (obstacles): the move would last 100 s.
    v.script("move", Outcome::nominal(100_000));
    stops::move_stops_at(&mut v, Enu::new(5.0, 2.0, 0.0));
    let (_, _) = run(&mut ex, &mut v, 40_000);
    // et_ub = start + √116 m / 0.3 m/s ≈ start + 35.9 s; t_exec = et_ub − ts.
    let start = launch_time(&ex, "move").expect("launched");
    let ub = start + 35_900;
    let stop = events(&ex).into_iter().find_map(|(t, e)| match e {
        TraceEvent::Stop { action, .. } => Some((t, action)),
        _ => None,
    });
    let (stop, stopped) = stop.expect("the move was stopped");
    // The action stopped is the move inserted above, not another one.
    assert_eq!(stopped, ex.action_text(m));
    // The first cycle (every 500 ms here) at or after t_exec, well before et_ub.
    assert!(
        stop >= ub - 1_000 && stop < ub - 1_000 + 500,
        "stopped at {stop}, ub {ub}"
    );
    // The reported position is no known location: a new location object, the robot's position in S_t.
    let at = ex.plan().domain().attr_id("AT_ROBOT").unwrap();
    let Some(Value::Obj(o)) = ex.state().get(&(at, vec![])) else {
        panic!("no position in S_t");
    };
    assert!(ex.plan().problem().object_name(o).starts_with('L'));
}

#[test]
fn goal_requests_accepted_and_rejected_through_the_vehicle() {
    let (mut ex, mut v) = picture_run(Outcome::nominal(8_000).with_level("STORAGE", 2.1));
    let req = |name: &str, window: (f64, f64)| mavtempo_vehicle::GoalRequest {
        name: name.into(),
        kind: mavtempo_vehicle::GoalKind::PictureOf,
        proposition: format!("picture_of({name})"),
        location: Some(mavtempo_vehicle::GoalLocation {
            name: "p2".into(),
            new: false,
            at: Enu::new(18.0, -6.0, 0.0),
            lat: 0.0,
            lon: 0.0,
        }),
        priority: 1,
        start_window_s: window,
        duration_s: (0.0, 0.0),
        d_achiev_s: 40.0,
    };
    v.at(
        1_000,
        Scripted::Goals(vec![req("g6", (0.0, 1800.0)), req("g7", (0.0, 20.0))]),
    );
    let _ = run(&mut ex, &mut v, 2_000);
    let fates = ex.goal_fates();
    assert!(
        fates.iter().any(
            |f| f.name == "g6" && f.fate != mavtempo_executive::exec::executive::Fate::Rejected
        ),
        "g6 accepted into the plan: {fates:?}"
    );
    // g7 never entered the plan: its fate says why.
    assert!(fates.iter().any(|f| f.name == "g7"
        && f.fate == mavtempo_executive::exec::executive::Fate::Rejected
        && matches!(
            f.reason,
            Some(FateReason::Acceptance(Rejection::TooLate { .. }))
        )));
    assert!(events(&ex).iter().any(|(_, e)| matches!(e,
        TraceEvent::GoalRejected { goal, .. } if goal == "g7")));
    // g6 is an open condition: plan repair was started on it (not an abort).
    assert!(ex.counters().repair_steps > 0, "no repair step");
    assert!(ex.abort().is_none(), "aborted: {:?}", ex.abort());
}

#[test]
fn capacity_drop_during_a_running_picture_aborts() {
    let (mut ex, mut v) = picture_run(Outcome::nominal(8_000));
    v.at(
        4_000,
        Scripted::Capacity(CapacityChange {
            resource: "STORAGE".into(),
            capacity: 0.5,
            delta: -2.5,
        }),
    );
    let (out, t) = run(&mut ex, &mut v, 60_000);
    assert!(matches!(out, CycleOutcome::Aborted(_)), "{out:?}");
    assert_eq!(t, 4_000);
}
