//! Seed 1 §3 rules of the executive, each on a hand-built rover plan (domains/rover, problem fig2) with the
//! manual time of the tests: no planner involved, so each rule is checked on its own.

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::exec::abstraction::{links_to_break, Hierarchy};
use mavtempo_executive::exec::capacity::{alter, CapacityOutcome};
use mavtempo_executive::exec::executable::{
    action_executable, flawed_actions, goal_achievable, plan_executable, timepoint_executable,
};
use mavtempo_executive::exec::goal_request::{request, Rejection};
use mavtempo_executive::exec::ledger::ResourceLedger;
use mavtempo_executive::exec::p_t::{classify, goals, remove_past, State};
use mavtempo_executive::exec::report_timing::{integrate, timing, Timing};
use mavtempo_executive::exec::resource_bounds::{fold_removed, level_bounds, LevelCase};
use mavtempo_executive::exec::resource_report::{integrate_level, LevelVerdict, EPS};
use mavtempo_temporal::lang::load_problem_and_domain;
use mavtempo_temporal::model::{
    Goal, GoalId, GoalOrigin, ObjectId, ResourceKind, TimeInterval, Value,
};
use mavtempo_temporal::plan::{ActionId, EventId, PartialPlan, STerm};

fn fig2() -> PartialPlan {
    let (d, p) = load_problem_and_domain(Path::new(repo!("domains/rover/problems/fig2.ixt")))
        .expect("fig2 loads");
    PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan")
}

fn obj(plan: &PartialPlan, name: &str) -> ObjectId {
    plan.problem().object_id(name).expect("object")
}

/// take_picture(?l = loc).
fn picture(plan: &mut PartialPlan, loc: &str) -> ActionId {
    let task = plan.domain().task_id("take_picture").expect("task");
    let a = plan.insert_action(task).expect("insert");
    let v = plan.action(a).vars[0];
    let o = obj(plan, loc);
    plan.bind_var(v, o).expect("bind");
    a
}

/// move(?from, ?to).
fn go(plan: &mut PartialPlan, from: &str, to: &str) -> ActionId {
    let task = plan.domain().task_id("move").expect("task");
    let a = plan.insert_action(task).expect("insert");
    let (v0, v1) = (plan.action(a).vars[0], plan.action(a).vars[1]);
    let (f, t) = (obj(plan, from), obj(plan, to));
    plan.bind_var(v0, f).expect("bind");
    plan.bind_var(v1, t).expect("bind");
    plan.repropagate_action(a).expect("numeric");
    a
}

fn event_on(plan: &PartialPlan, a: ActionId, attr: &str) -> EventId {
    let attr = plan.domain().attr_id(attr).expect("attr");
    *plan
        .action(a)
        .events
        .iter()
        .find(|&&e| plan.event(e).attr == attr)
        .expect("event")
}

fn storage(plan: &PartialPlan) -> mavtempo_temporal::model::ResourceId {
    plan.domain().resource_id("STORAGE").expect("STORAGE")
}

#[test]
fn definition_1_running_future_past_and_the_state_of_past_effects() {
    let mut plan = fig2();
    let m = go(&mut plan, "base", "p1");
    let p = picture(&mut plan, "p1");
    plan.order(plan.action(m).end, plan.action(p).start)
        .unwrap();
    assert_eq!(classify(&plan, 0).future, vec![m, p]);
    plan.execute_at(plan.action(m).start, 0).unwrap();
    let pt = classify(&plan, 1_000);
    assert_eq!((pt.running.clone(), pt.future.clone()), (vec![m], vec![p]));
    plan.execute_at(plan.action(m).end, 30_000).unwrap();
    assert_eq!(remove_past(&mut plan, 31_000), vec![m]);
    assert!(plan.action(m).removed);
    assert_eq!(classify(&plan, 31_000).future, vec![p]);
    // Its effect AT_ROBOT = p1 stays in S_t.
    let mut s = State::default();
    s.refresh(&plan, 31_000);
    let at = plan.domain().attr_id("AT_ROBOT").unwrap();
    let p1 = plan.problem().object_id("p1").unwrap();
    assert_eq!(s.get(&(at, vec![])), Some(Value::Obj(p1)));
    // G_t: all five goals still to achieve.
    assert_eq!(goals(&plan, 31_000).len(), 5);
}

#[test]
fn eq_1_and_2_resource_bounds_in_both_cases() {
    let mut plan = fig2();
    let r = storage(&plan);
    let p = picture(&mut plan, "p1");
    let past = (3.0, 3.0);
    let b = level_bounds(&plan, r, 0, &[], past);
    assert_eq!((b.case, b.lb, b.ub), (LevelCase::Exact, 3.0, 3.0));
    plan.execute_at(plan.action(p).start, 1_000).unwrap();
    let running = classify(&plan, 2_000).running;
    assert_eq!(running, vec![p]);
    // Case (2): the running picture may have consumed up to q_max = 1 slot so far.
    let b = level_bounds(&plan, r, 2_000, &running, past);
    assert_eq!(b.case, LevelCase::Estimated);
    assert!(
        (b.lb - 2.0).abs() < 1e-9 && (b.ub - 3.0).abs() < 1e-9,
        "{b:?}"
    );
    // Case (1) once it ended: eq. (1) counts its consumption ?size in [0.9, 1].
    plan.execute_at(plan.action(p).end, 8_000).unwrap();
    let b = level_bounds(&plan, r, 9_000, &[], past);
    assert_eq!(b.case, LevelCase::Exact);
    assert!(
        (b.lb - 2.0).abs() < 1e-9 && (b.ub - 2.1).abs() < 1e-9,
        "{b:?}"
    );
    // Removed from the plan, it is aggregated into the past level: same bounds.
    let mut levels = vec![(0.0, 0.0); plan.domain().resources.len()];
    levels[r.index()] = past;
    let mut agg = mavtempo_executive::id_vec::IdVec::from_items(levels);
    remove_past(&mut plan, 9_000);
    fold_removed(&plan, p, &mut agg);
    let b2 = level_bounds(
        &plan,
        r,
        9_000,
        &[],
        agg.get(r).copied().unwrap_or_default(),
    );
    assert!((b2.lb - b.lb).abs() < 1e-9 && (b2.ub - b.ub).abs() < 1e-9);
}

#[test]
fn section_3_3_levels_in_bounds_over_consumption_over_production() {
    let mut plan = fig2();
    let r = storage(&plan);
    let p = picture(&mut plan, "p1");
    plan.execute_at(plan.action(p).start, 0).unwrap();
    plan.execute_at(plan.action(p).end, 8_000).unwrap();
    let b = level_bounds(&plan, r, 9_000, &[], (3.0, 3.0));
    // In bounds, case (1): the level becomes exact.
    let u = integrate_level(&b, 2.1, ResourceKind::Reservoir, EPS);
    assert_eq!(u.verdict, LevelVerdict::Consistent);
    assert_eq!(u.past, (2.1, 2.1));
    assert!(!u.repair);
    // Over-consumption: c = RscL_lb − l_r, new level l_r, repair requested, plan still executable.
    let u = integrate_level(&b, 1.5, ResourceKind::Reservoir, EPS);
    match u.verdict {
        LevelVerdict::OverConsumption { c } => assert!((c - 0.5).abs() < 1e-9),
        v => panic!("{v:?}"),
    }
    assert_eq!(u.past, (1.5, 1.5));
    assert!(u.repair && !u.check_executable);
    // Over-production of a reservoir: p = l_r − RscL_ub, repair requested.
    let u = integrate_level(&b, 2.5, ResourceKind::Reservoir, EPS);
    match u.verdict {
        LevelVerdict::OverProduction { p } => assert!((p - 0.4).abs() < 1e-9),
        v => panic!("{v:?}"),
    }
    assert!(u.repair);
    // Case (2), then Definition 5 must be re-checked. The running picture's consumption may not be in the
    // reading yet (docs/departures.md): the past level is the reading itself (nothing running produces),
    // so the bounds become [l_r − its consumption, l_r].
    let q = picture(&mut plan, "p2");
    plan.execute_at(plan.action(q).start, 9_000).unwrap();
    let b = level_bounds(&plan, r, 10_000, &[q], (3.0, 3.0));
    let l_r = b.lb - 0.4;
    let u = integrate_level(&b, l_r, ResourceKind::Reservoir, EPS);
    assert!(u.check_executable && u.repair);
    assert!((u.past.0 - l_r).abs() < 1e-9, "{u:?}");
    // As sense.rs posts it: the usages the bounds still count are taken back out of the aggregate.
    let agg = (u.past.0 - (b.past_lb - 3.0), u.past.1 - (b.past_ub - 3.0));
    let after = level_bounds(&plan, r, 10_000, &[q], agg);
    assert!((after.ub - l_r).abs() < 1e-9, "{after:?}");
    assert!(
        (after.lb - (l_r - (b.past_lb - b.lb))).abs() < 1e-9,
        "{after:?}"
    );
}

#[test]
fn section_3_3_report_in_bounds_too_early_too_late() {
    // take_picture lasts 5 to 20 s.
    let mut plan = fig2();
    let p = picture(&mut plan, "p1");
    let g1 = plan.goals()[0].cond;
    let e = event_on(&plan, p, "PICTURE");
    plan.add_link(e, g1).unwrap();
    plan.execute_at(plan.action(p).start, 0).unwrap();
    assert_eq!(timing(&plan, p, 10_000), Timing::InBounds);
    assert_eq!(timing(&plan, p, 25_000), Timing::TooLate);
    assert_eq!(timing(&plan, p, 2_000), Timing::TooEarly);
    let mut late = plan.clone();
    assert!(!integrate(&mut late, p, 25_000).unwrap());
    let mut ok = plan.clone();
    assert!(integrate(&mut ok, p, 10_000).unwrap());
    assert_eq!(
        ok.temporal_network().executed_at(ok.action(p).end),
        Some(10_000)
    );
    // Too early: the end is now 2 s, the old constraints relaxed, the goal still after it.
    assert!(integrate(&mut plan, p, 2_000).unwrap());
    let et = plan.action(p).end;
    assert_eq!(plan.temporal_network().executed_at(et), Some(2_000));
    assert!(plan.temporal_network().lb(plan.goals()[0].st) >= 2_000);
}

#[test]
fn definitions_2_to_5_executable_timepoint_goal_action_plan() {
    let mut plan = fig2();
    let p = picture(&mut plan, "p1");
    let e = event_on(&plan, p, "PICTURE");
    let g1 = plan.goals()[0].cond;
    plan.add_link(e, g1).unwrap();
    let st_g = plan.goals()[0].st;
    // The goal's start must wait for the picture's end (its direct predecessor).
    assert!(!timepoint_executable(plan.temporal_network(), st_g, 30_000));
    assert!(!goal_achievable(&plan, GoalId(0), 30_000));
    // The picture has open conditions (AT_ROBOT, PTU_POS, ...): not executable (Definition 4).
    let flawed = flawed_actions(&mut plan);
    assert!(flawed.contains(&p));
    assert!(timepoint_executable(
        plan.temporal_network(),
        plan.action(p).start,
        0
    ));
    assert!(!action_executable(&plan, p, 0, &flawed));
    // Definition 5: the plan is executable while the flawed action is not running, not once it runs.
    assert!(plan_executable(&[], &flawed));
    assert!(!plan_executable(&[p], &flawed));
    plan.execute_at(plan.action(p).start, 0).unwrap();
    plan.execute_at(plan.action(p).end, 10_000).unwrap();
    assert!(timepoint_executable(plan.temporal_network(), st_g, 10_000));
    assert!(goal_achievable(&plan, GoalId(0), 10_000));
    // Outside [T_lb, T_ub]: g3's start window ends at 8 min.
    let st3 = plan.goals()[2].st;
    assert!(!timepoint_executable(
        plan.temporal_network(),
        st3,
        9 * 60_000
    ));
}

fn picture_goal(plan: &PartialPlan, name: &str, loc: &str, window_s: (i64, i64)) -> Goal {
    let attr = plan.domain().attr_id("PICTURE").unwrap();
    Goal {
        name: name.into(),
        kind: GoalOrigin::External,
        priority: 1,
        attr,
        args: vec![plan.problem().object_id(loc).unwrap()],
        value: Value::Obj(mavtempo_temporal::model::Domain::TRUE),
        start_window: TimeInterval::closed(window_s.0 * 1000, window_s.1 * 1000),
        duration: TimeInterval::closed(0, 0),
        achieve: 40_000,
    }
}

#[test]
fn section_3_3_goal_request_accepted_rejected_and_ordered_after_running_actions() {
    let mut plan = fig2();
    let n = plan.goals().len();
    // Accepted: open window; it becomes an open condition.
    let g = picture_goal(&plan, "g6", "p2", (0, 1800));
    let id = request(&mut plan, g, 600_000, &[]).expect("accepted");
    assert_eq!(plan.goals().len(), n + 1);
    assert!(
        plan.temporal_network().lb(plan.goals()[n].st) >= 640_000,
        "st^g ≥ t + d_achiev"
    );
    assert_eq!(plan.problem().goals[id.index()].name, "g6");
    // Rejected: st^g − origin ≤ 10 min, but now is 9.5 min and d_achiev is 40 s.
    let g = picture_goal(&plan, "g7", "p3", (0, 600));
    let r = request(&mut plan, g, 570_000, &[]);
    assert!(matches!(r, Err(Rejection::TooLate { .. })), "{r:?}");
    assert_eq!(
        plan.goals().len(),
        n + 1,
        "a rejected goal leaves the plan as it was"
    );
    assert_eq!(plan.problem().goals.len(), n + 1);
    // A goal AT_ROBOT = p3 threatens the running move's hold AT_ROBOT = +oo: ordered after its end.
    let m = go(&mut plan, "base", "p1");
    plan.execute_at(plan.action(m).start, 0).unwrap();
    let at = plan.domain().attr_id("AT_ROBOT").unwrap();
    let g = Goal {
        attr: at,
        args: vec![],
        value: Value::Obj(plan.problem().object_id("p3").unwrap()),
        achieve: 0,
        ..picture_goal(&plan, "g8", "p3", (0, 1800))
    };
    request(&mut plan, g, 1_000, &[m]).expect("accepted");
    let st = plan.goals().last().unwrap().st;
    assert!(plan
        .temporal_network()
        .necessarily_before(plan.action(m).end, st));
}

#[test]
fn section_3_3_capacity_alteration_repair_or_abort() {
    let mut plan = fig2();
    let r = storage(&plan);
    let a = picture(&mut plan, "p1");
    picture(&mut plan, "p2");
    // Two future pictures (up to 2 slots) and the storage drops to 1: repair.
    let mut future = plan.clone();
    let mut ledger = ResourceLedger::new(plan.problem());
    assert_eq!(
        alter(&mut future, &mut ledger, r, 1.0, 0, &[]),
        CapacityOutcome::Repair
    );
    // The same drop while one of them runs: the conflict involves a running action, abort.
    plan.execute_at(plan.action(a).start, 0).unwrap();
    assert_eq!(
        alter(&mut plan, &mut ledger, r, 1.0, 1_000, &[a]),
        CapacityOutcome::Abort
    );
}

#[test]
fn section_3_3_causal_link_removal_by_the_abstraction_hierarchy() {
    let mut plan = fig2();
    let h = Hierarchy::new(plan.domain());
    let dom = plan.domain().clone();
    let id = |n: &str| dom.attr_id(n).unwrap();
    let att = h.closure(&[id("PICTURE")]);
    for a in [
        "PICTURE",
        "AT_ROBOT",
        "PTU_POS",
        "ROBOT_STATUS",
        "MVT_INIT",
        "PTU_INIT",
    ] {
        assert!(att.contains(&id(a)), "{a} in {att:?}");
    }
    assert!(!att.contains(&id("COMMUNICATED")));
    // A fixed point: closing again adds nothing.
    assert_eq!(h.closure(&att), att);
    // A goal's link on PICTURE is broken; a link supporting a running action is kept.
    let p = picture(&mut plan, "p1");
    let e = event_on(&plan, p, "PICTURE");
    let g1 = plan.goals()[0].cond;
    let l = plan.add_link(e, g1).unwrap();
    assert_eq!(links_to_break(&plan, &att, &[]), vec![l]);
    assert!(links_to_break(&plan, &[id("COMMUNICATED")], &[]).is_empty());
}

#[test]
fn a_location_added_at_run_time_gets_its_wildcard_initial_facts_in_the_executing_plan() {
    // A goal from the ground on a new target (e3/e4) adds a location object; `PICTURE(*) = false` must hold
    // for it in the executing plan too, or the picture's condition `PICTURE(new) = false` is unsupportable.
    let mut plan = fig2();
    let picture = plan.domain().attr_id("PICTURE").expect("PICTURE");
    let ty = plan.domain().type_id("location").expect("location");
    let mut problem = (**plan.problem()).clone();
    let new = problem.add_object_with_defaults(
        plan.domain(),
        mavtempo_temporal::model::Object {
            name: "g6_loc".into(),
            ty,
            position: None,
        },
    );
    let initial_of_new = |plan: &PartialPlan| {
        plan.events_on(picture)
            .iter()
            .filter(|&&e| plan.event(e).args == [STerm::Obj(new)])
            .count()
    };
    assert_eq!(initial_of_new(&plan), 0);
    plan.set_problem(Arc::new(problem));
    assert_eq!(initial_of_new(&plan), 1);
    let e = plan.events_on(picture)[plan.events_on(picture).len() - 1];
    assert_eq!(
        plan.event(e).to,
        STerm::Obj(mavtempo_temporal::model::Domain::FALSE)
    );
    assert_eq!(plan.event(e).at, plan.temporal_network().origin());
}
