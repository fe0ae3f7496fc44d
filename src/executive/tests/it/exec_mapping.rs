//! The executive reads positions and uploaded goals through the config's `[mapping]` only: the AUV
//! (config/sitl-auv.toml), the rover (config/demo-rover.toml) and shopping (an inline mapping) go through the
//! same code; without a mapping positions are ignored and goals rejected with a reason, and a new place is
//! never given object 0.

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::config_check::{check, resolve_mapping};
use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::Executive;
use mavtempo_executive::exec::state_update::integrate_state;
use mavtempo_executive::exec::DomainMapping;
use mavtempo_temporal::lang::load_problem_and_domain;
use mavtempo_temporal::model::{Domain, ObjectId, Value};
use mavtempo_temporal::plan::{PartialPlan, STerm};
use mavtempo_temporal::planner::{Budget, Search, StepOutcome};
use mavtempo_vehicle::config::{Mapping, VehicleConfig};
use mavtempo_vehicle::goals::GoalBatch;
use mavtempo_vehicle::{
    ActionReport, Enu, GoalKind, GoalLocation, GoalRequest, GoalVerdict, ReportStatus, StateValue,
    VehicleEvent,
};

fn solved(problem: &str) -> PartialPlan {
    let (d, p) = load_problem_and_domain(Path::new(problem)).unwrap_or_else(|e| panic!("{e}"));
    let root = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mut search = Search::new(root);
    assert_eq!(search.run(Budget::steps(50_000)), StepOutcome::Solved);
    search.into_plan()
}

/// The mapping of a shipped configuration, checked against the plan's domain and problem.
fn shipped_mapping(config: &str, plan: &PartialPlan) -> DomainMapping {
    let cfg = VehicleConfig::load(Path::new(config)).unwrap_or_else(|e| panic!("{e}"));
    match check(&cfg, plan.domain(), Some(plan.problem())) {
        Ok(c) => c.mapping,
        Err(issues) => panic!("{issues:?}"),
    }
}

fn request(name: &str, kind: GoalKind, place: &str, new: bool, at: Enu) -> GoalRequest {
    GoalRequest {
        name: name.into(),
        kind,
        proposition: format!("{}({place})", kind.predicate()),
        location: (kind != GoalKind::ReturnHome).then(|| GoalLocation {
            name: place.into(),
            new,
            at,
            lat: 0.0,
            lon: 0.0,
        }),
        priority: 1,
        start_window_s: (0.0, 10.0 * 3_600.0),
        duration_s: (0.0, f64::INFINITY),
        d_achiev_s: 60.0,
    }
}

/// Uploads `goals` at time 0 and returns the executive's verdicts, as a cycle gives them: after the
/// repair part, which had the goals' insertion attempts (one per cycle here; each goal gets its own).
fn upload(ex: &mut Executive, goals: Vec<GoalRequest>) -> Vec<GoalVerdict> {
    let n = goals.len();
    let (batch, mut rx) = GoalBatch::new(goals);
    ex.integrate(VehicleEvent::Goals(batch), 0);
    for _ in 0..n.max(1) {
        ex.repair_phase(0, &|| 0);
    }
    ex.answer_goal_batches();
    rx.try_recv().expect("answered")
}

/// Uploads the one goal `goal`; its verdict.
fn upload_one(ex: &mut Executive, goal: GoalRequest) -> GoalVerdict {
    let mut verdicts = upload(ex, vec![goal]);
    assert_eq!(verdicts.len(), 1, "{verdicts:?}");
    verdicts.remove(0)
}

/// The last goal of the plan's problem as `ATTR(args) = value` text.
fn last_goal(ex: &Executive) -> String {
    goal_text(ex, ex.plan().problem().goals.last().expect("a goal"))
}

/// A goal as `ATTR(args) = value` text.
fn goal_text(ex: &Executive, g: &mavtempo_temporal::model::Goal) -> String {
    let p = &ex.plan().problem();
    let args: Vec<&str> = g.args.iter().map(|&o| p.object_name(o)).collect();
    let value = match g.value {
        Value::Obj(o) => p.object_name(o).to_string(),
        Value::Unknown => "+oo".into(),
    };
    format!(
        "{}({}) = {value}",
        ex.plan().domain().attr(g.attr).name,
        args.join(", ")
    )
}

/// A failed report of the plan's first action named `task`, carrying a position.
fn failed_at(ex: &mut Executive, task: &str, at: Enu) {
    let a = ex
        .plan()
        .live_actions()
        .find(|&a| ex.plan().domain().task(ex.plan().action(a).task).name == task)
        .expect("the plan has the task");
    let report = ActionReport {
        id: 1,
        status: ReportStatus::Failed,
        time_ms: 5_000,
        resources: Vec::new(),
        state: vec![("position".into(), StateValue::Position(at))],
        reason: Some("stuck".into()),
    };
    integrate_state(ex, a, &report, 5_000);
}

#[test]
fn auv_goals_and_positions_follow_the_auv_mapping() {
    let plan = solved(repo!("domains/auv/problems/vents.ixt"));
    let mapping = shipped_mapping(repo!("config/sitl-auv.toml"), &plan);
    let mut ex = Executive::new(plan, ExecConfig::default()).with_mapping(mapping);
    let vent1 = Enu::new(1_000.0, 0.0, -1_500.0);
    let spot = Enu::new(600.0, 200.0, -1_500.0);
    assert_eq!(
        upload_one(
            &mut ex,
            request("g3", GoalKind::SampleAt, "vent1", false, vent1),
        ),
        GoalVerdict::Accepted
    );
    assert_eq!(last_goal(&ex), "SAMPLED(vent1) = true");
    // A place no object is at becomes a new location object, named after the goal.
    let g4 = request("g4", GoalKind::SurveyOf, "g4_loc", true, spot);
    let mapped = ex.goal_from_request(&g4).expect("mapped");
    assert_eq!(goal_text(&ex, &mapped), "SURVEYED(g4_loc) = true");
    // No route leads to the new place (CONNECTED is static): its insertion fails and it is rejected
    // (the station told in its words, the planner's reason in the goal's fate), the plan kept as it was.
    let goals_before = ex.plan().problem().goals.len();
    match upload(&mut ex, vec![g4]).as_slice() {
        [GoalVerdict::Rejected(r)] => assert_eq!(r, "no way to fit it in with the goals held"),
        other => panic!("{other:?}"),
    }
    let fate = ex
        .goal_fates()
        .into_iter()
        .find(|f| f.name == "g4")
        .expect("g4's fate");
    assert!(
        fate.reason_text().contains("plan repair found no plan"),
        "{fate:?}"
    );
    assert_eq!(ex.plan().problem().goals.len(), goals_before);
    let o = ex.plan().problem().object_id("g4_loc").expect("new object");
    let location = ex.plan().domain().type_id("location");
    assert_eq!(ex.plan().problem().object(o).map(|o| o.ty), location);
    upload_one(
        &mut ex,
        request("g5", GoalKind::ReturnHome, "", false, Enu::default()),
    );
    assert_eq!(last_goal(&ex), "AUV_AT() = surface");
    // The AUV's position attribute is AUV_AT: a stopped `go` sets it to a new place there.
    let before = ex.plan().problem().objects.len();
    let go_from = {
        let a = ex
            .plan()
            .live_actions()
            .find(|&a| ex.plan().domain().task(ex.plan().action(a).task).name == "go")
            .expect("a go");
        ex.plan().term_name(STerm::Var(ex.plan().action(a).vars[0]))
    };
    let stop = Enu::new(300.0, 0.0, -450.0);
    failed_at(&mut ex, "go", stop);
    assert_eq!(ex.plan().problem().objects.len(), before + 1);
    let last = ex.plan().problem().objects.last().expect("object");
    assert_eq!(Some(last.ty), location);
    assert_eq!(last.local(None).map(|(e, n, _)| (e, n)), Some((300.0, 0.0)));
    // Met on the way from where the `go` started, the new place keeps that place's routes (CONNECTED is
    // static): the AUV can go on from there wherever it could from the start, and back to the start.
    let p = &ex.plan().problem();
    let new = p.object_id(&last.name).expect("named");
    let from = p.object_id(&go_from).expect("from");
    let connected = ex.plan().domain().attr_id("CONNECTED").expect("CONNECTED");
    let route = |a: ObjectId, b: ObjectId| {
        p.initial
            .iter()
            .rev()
            .find(|f| f.attr == connected && f.args == vec![a, b])
            .map(|f| f.value)
    };
    let mut routes = 0;
    for to in ["surface", "vent1", "vent2"] {
        let to = p.object_id(to).expect("object");
        let expected = if to == from {
            Some(Value::Obj(Domain::TRUE))
        } else {
            route(from, to)
        };
        assert_eq!(
            route(new, to),
            expected,
            "{go_from} -> {}",
            p.object_name(to)
        );
        routes += usize::from(route(new, to) == Some(Value::Obj(Domain::TRUE)));
    }
    assert!(routes >= 1, "the new place has a route on");
}

#[test]
fn the_rover_goes_through_the_same_code() {
    let plan = solved(repo!("domains/rover/problems/fig2.ixt"));
    let mapping = shipped_mapping(repo!("config/demo-rover.toml"), &plan);
    let mut ex = Executive::new(plan, ExecConfig::default()).with_mapping(mapping);
    assert_eq!(
        upload_one(
            &mut ex,
            request(
                "g6",
                GoalKind::PictureOf,
                "g6_loc",
                true,
                Enu::new(30.0, -8.0, 0.0),
            ),
        ),
        GoalVerdict::Accepted
    );
    assert_eq!(last_goal(&ex), "PICTURE(g6_loc) = true");
    // demo-rover.toml has no sample goals (the rover domain has no such attribute).
    let verdict = upload_one(
        &mut ex,
        request("g7", GoalKind::SampleAt, "base", false, Enu::default()),
    );
    assert_eq!(
        verdict,
        GoalVerdict::Rejected("no goal mapping for sample items in the config".into())
    );
    // No home object in demo-rover.toml: a return home is a "be at" the problem's home position, where
    // fig2's `base` is (issue 30: RTL items were always rejected with the shipped rover configs).
    let verdict = upload_one(
        &mut ex,
        request("g8", GoalKind::ReturnHome, "", false, Enu::default()),
    );
    assert_eq!(verdict, GoalVerdict::Accepted);
    assert_eq!(last_goal(&ex), "AT_ROBOT() = base");
}

#[test]
fn shopping_goals_follow_an_inline_mapping() {
    let plan = solved(repo!("domains/shopping/problems/day.ixt"));
    let m: Mapping = toml::from_str(
        r#"
        position = "AT"
        location_type = "place"
        goals.waypoint = { attribute = "AT" }
        "#,
    )
    .expect("mapping parses");
    let mapping = resolve_mapping(&m, plan.domain(), Some(plan.problem()), None).expect("resolves");
    let mut ex = Executive::new(plan, ExecConfig::default()).with_mapping(mapping);
    // The places have no coordinates: a place the intake named is taken by its name.
    assert_eq!(
        upload_one(
            &mut ex,
            request("g3", GoalKind::BeAt, "grocery", false, Enu::default()),
        ),
        GoalVerdict::Accepted
    );
    assert_eq!(last_goal(&ex), "AT() = grocery");
}

#[test]
fn without_a_mapping_positions_are_ignored_and_goals_rejected() {
    let plan = solved(repo!("domains/auv/problems/vents.ixt"));
    let mut ex = Executive::new(plan, ExecConfig::default());
    let goals_before = ex.plan().problem().goals.len();
    let verdicts = upload(
        &mut ex,
        vec![
            request(
                "g3",
                GoalKind::PictureOf,
                "g3_loc",
                true,
                Enu::new(5.0, 5.0, 0.0),
            ),
            request("g4", GoalKind::ReturnHome, "", false, Enu::default()),
        ],
    );
    assert_eq!(
        verdicts,
        vec![
            GoalVerdict::Rejected("no goal mapping for picture items in the config".into()),
            GoalVerdict::Rejected("no goal mapping for return_home items in the config".into()),
        ]
    );
    assert_eq!(ex.plan().problem().goals.len(), goals_before);
    let objects = ex.plan().problem().objects.len();
    // The same report that makes a place with the mapping (auv_goals_and_positions_...) makes none here.
    failed_at(&mut ex, "go", Enu::new(300.0, 0.0, -450.0));
    assert_eq!(
        ex.plan().problem().objects.len(),
        objects,
        "no place was made"
    );
}

#[test]
fn a_new_place_without_a_location_type_is_a_rejection_not_object_zero() {
    let plan = solved(repo!("domains/auv/problems/vents.ixt"));
    let d: &Domain = plan.domain();
    let mut mapping = shipped_mapping(repo!("config/sitl-auv.toml"), &plan);
    assert!(d.type_id("location").is_some());
    mapping.location_type = None;
    let mut ex = Executive::new(plan, ExecConfig::default()).with_mapping(mapping);
    let objects = ex.plan().problem().objects.len();
    let verdict = upload_one(
        &mut ex,
        request(
            "g3",
            GoalKind::SampleAt,
            "g3_loc",
            true,
            Enu::new(5.0, 5.0, 0.0),
        ),
    );
    match verdict {
        GoalVerdict::Rejected(r) => assert!(r.contains("no location type"), "{r}"),
        other => panic!("{other:?}"),
    }
    assert_eq!(ex.plan().problem().objects.len(), objects);
    assert!(ex
        .plan()
        .problem()
        .goals
        .iter()
        .all(|g| g.args.iter().all(|o| o.index() != 0)));
}
