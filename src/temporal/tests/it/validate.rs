//! The independent plan checker (`mavtempo_temporal::plan::validate`): correct plans are accepted, hand-broken ones
//! are rejected with the right violation; random sequential plans are accepted and a random mutation of
//! one is detected.

mod builder;
mod tiny;

use std::path::Path;

use mavtempo_temporal::lang::{load_domain, load_problem};
use mavtempo_temporal::model::Domain;
use mavtempo_temporal::plan::solution::{Consumer, Establisher, PlanTerm, PlanTp, Solution};
use mavtempo_temporal::plan::validate::{validate, LinkFault, NumericFault, Violation};
use proptest::prelude::*;

use builder::Builder;
use tiny::Step;

fn violations(d: &Domain, p: &mavtempo_temporal::model::Problem, s: &Solution) -> Vec<Violation> {
    match validate(d, p, s) {
        Ok(_) => Vec::new(),
        Err(r) => r.violations,
    }
}

/// go(a, b), snap(b): achieves g1.
fn correct() -> (Domain, mavtempo_temporal::model::Problem, Solution) {
    let d = tiny::domain();
    let p = tiny::problem(&d, 60_000);
    let s = tiny::sequential(&d, &p, &[Step::Go(1), Step::Snap], 2);
    (d, p, s)
}

#[test]
fn a_correct_plan_is_accepted_at_its_earliest_schedule() {
    let (d, p, s) = correct();
    let checked = validate(&d, &p, &s).unwrap_or_else(|e| panic!("{e}"));
    let time = |name: &str| {
        let i = s
            .timepoints
            .iter()
            .position(|t| t.name == name)
            .expect(name);
        checked.schedule[i]
    };
    // go at top speed: 10 m / 2 m/s = 5 s; precedences are ]0, +oo[ (one millisecond).
    assert_eq!(time("a1.st"), 1);
    assert_eq!(time("a1.et"), 5_001);
    assert_eq!(time("a2.st"), 5_002);
    assert_eq!(time("a2.et"), 6_002);
    assert_eq!(time("g1.st"), 6_003);
    // The goal is flexible: its window reaches the deadline.
    let g = s
        .timepoints
        .iter()
        .find(|t| t.name == "g1.st")
        .expect("g1.st");
    assert_eq!((g.lb, g.ub), (Some(6_003), Some(60_000)));
}

#[test]
fn the_plan_survives_a_json_round_trip() {
    let (d, p, s) = correct();
    let text = serde_json::to_string(&s).expect("serialise");
    let back: Solution = serde_json::from_str(&text).expect("deserialise");
    assert_eq!(back, s);
    assert!(validate(&d, &p, &back).is_ok());
}

#[test]
fn a_broken_hold_is_rejected() {
    let (d, p, mut s) = correct();
    // snap(c) while the robot is at b.
    let c = p.object_id("c").expect("c");
    s.actions[1].args[0] = PlanTerm::Obj(c);
    let v = violations(&d, &p, &s);
    assert!(
        v.iter().any(
            |v| matches!(v, Violation::HoldBroken { action, lapse }
            if action == "a2 (snap)" && lapse.instance == "AT()" && lapse.value == "c" && lapse.actual == "b")
        ),
        "{v:#?}"
    );
    // Its causal link no longer matches the hold it claims to support, and g1 is no longer achieved.
    assert!(
        v.iter()
            .any(|v| matches!(v, Violation::LinkMismatch { .. })),
        "{v:#?}"
    );
    assert!(
        v.iter()
            .any(|v| matches!(v, Violation::GoalBroken { goal, .. } if goal == "g1")),
        "{v:#?}"
    );
}

#[test]
fn an_over_full_storage_is_rejected() {
    let d = tiny::domain();
    let p = tiny::problem(&d, 60_000);
    // Three pictures with two free slots.
    let steps = [Step::Snap, Step::Go(1), Step::Snap, Step::Go(2), Step::Snap];
    let s = tiny::sequential(&d, &p, &steps, 3);
    let v = violations(&d, &p, &s);
    assert_eq!(v.len(), 1, "{v:#?}");
    assert!(
        matches!(&v[0], Violation::ResourceBelowZero { resource, culprit, level, .. }
            if resource == "STORE" && culprit == "a5 (snap)" && *level == -1.0),
        "{v:#?}"
    );
    // Two are fine.
    assert!(validate(&d, &p, &tiny::sequential(&d, &p, &steps, 2)).is_ok());
}

#[test]
fn a_violated_deadline_is_rejected() {
    let (d, _, s) = correct();
    // The same plan against a problem whose g1 must start within 4 s: it starts at 6.003 s.
    let strict = tiny::problem(&d, 4_000);
    let v = violations(&d, &strict, &s);
    assert_eq!(
        v,
        vec![Violation::GoalWindow {
            goal: "g1".into(),
            start: 6_003,
            window: "[0, 4000]".into()
        }]
    );
    assert!(v[0].to_string().contains("outside its window I^g"));
}

#[test]
fn an_event_with_a_wrong_from_value_is_rejected() {
    let (d, p, mut s) = correct();
    // go(c, b) while the robot is at a.
    s.actions[0].args[0] = PlanTerm::Obj(p.object_id("c").expect("c"));
    let v = violations(&d, &p, &s);
    assert!(
        v.iter().any(
            |v| matches!(v, Violation::EventFrom { action, time, expected, actual, .. }
            if action == "a1 (go)" && *time == 1 && expected == "c" && actual == "a")
        ),
        "{v:#?}"
    );
}

#[test]
fn overlapping_uses_of_a_unary_resource_are_rejected() {
    let d = tiny::domain();
    let p = tiny::problem(&d, 60_000);
    let with_calibration = |after_snap: bool| {
        let mut b = Builder::new(&d, &p);
        let go = b.action("go", &["a", "b"]);
        tiny::move_window(&mut b, go, "a", "b", 0.5, 2.0);
        let snap = b.action("snap", &["b"]);
        let cal = b.action("calibrate", &[]);
        let (go_st, go_et, snap_st, snap_et, cal_st) =
            (b.st(go), b.et(go), b.st(snap), b.et(snap), b.st(cal));
        b.before(PlanTp::ORIGIN, go_st);
        b.before(go_et, snap_st);
        // Unordered with the snap, calibrate starts with it at the earliest schedule.
        b.before(if after_snap { snap_et } else { go_et }, cal_st);
        b.event_to_hold(go, 1, snap, 0);
        b.achieve("g1", snap_et, snap, 0);
        b.finish()
    };
    let v = violations(&d, &p, &with_calibration(false));
    assert_eq!(
        v,
        vec![Violation::UnaryOverlap {
            resource: "CAM".into(),
            first: "a2 (snap)".into(),
            second: "a3 (calibrate)".into(),
            time: 5_002
        }]
    );
    assert!(validate(&d, &p, &with_calibration(true)).is_ok());
}

#[test]
fn a_schedule_inconsistent_network_is_rejected() {
    let (d, p, mut s) = correct();
    // go must start after the snap ends, which itself follows go.
    let (go_st, snap_et) = (s.actions[0].timepoints[0], s.actions[1].timepoints[1]);
    s.constraints
        .push(mavtempo_temporal::plan::solution::PlanConstraint {
            from: snap_et,
            to: go_st,
            lb: Some(0),
            ub: None,
        });
    let v = violations(&d, &p, &s);
    assert_eq!(v.len(), 1, "{v:#?}");
    let Violation::InconsistentNetwork { cycle } = &v[0] else {
        panic!("{v:#?}")
    };
    assert!(
        cycle.contains("a1.st") && cycle.contains("a2.et"),
        "{cycle}"
    );
}

#[test]
fn a_window_the_network_forbids_is_rejected() {
    let (d, p, mut s) = correct();
    let i = s
        .timepoints
        .iter()
        .position(|t| t.name == "a2.st")
        .expect("a2.st");
    s.timepoints[i].lb = Some(0);
    let v = violations(&d, &p, &s);
    assert!(
        matches!(v.as_slice(), [Violation::WindowOutsideNetwork { tp, computed, .. }]
            if tp == "a2.st" && computed.starts_with("[5002, ")),
        "{v:#?}"
    );
}

#[test]
fn numeric_bounds_that_the_schedule_cannot_meet_are_rejected() {
    let (d, p, mut s) = correct();
    // ?speed at most 1 m/s: 10 m cannot be covered in the scheduled 5 s.
    s.actions[0].num_vars[0].hi = Some(1.0);
    let v = violations(&d, &p, &s);
    assert!(
        matches!(v.as_slice(), [Violation::Numeric { action, reason: NumericFault::NoSolution { constraint, .. } }]
            if action == "a1 (go)" && constraint == "?dist = ?speed * ?duration"),
        "{v:#?}"
    );
}

#[test]
fn an_unbound_variable_is_instantiated_respecting_inequality() {
    let (d, p, mut s) = correct();
    // Leave go's ?from open over {a, b}: ?from ≠ ?to = b forces a.
    s.variables
        .push(mavtempo_temporal::plan::solution::PlanVar {
            id: mavtempo_temporal::plan::solution::PlanVarId(0),
            name: "a1.?from".into(),
            domain: vec![p.object_id("b").expect("b"), p.object_id("a").expect("a")],
        });
    s.actions[0].args[0] = PlanTerm::Var(mavtempo_temporal::plan::solution::PlanVarId(0));
    let checked = validate(&d, &p, &s).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(checked.bindings, vec![p.object_id("a").expect("a")]);
    // With only b left, the binding constraint of go is reported.
    s.variables[0].domain.pop();
    let v = violations(&d, &p, &s);
    assert!(
        v.iter()
            .any(|v| matches!(v, Violation::Binding { action, .. } if action == "a1 (go)")),
        "{v:#?}"
    );
}

/// The rover of the papers, loaded from `domains/`: move to p1, turn the PTU down, take the picture (g1).
fn rover_g1(ptu_before_picture: bool) -> (Domain, mavtempo_temporal::model::Problem, Solution) {
    let root = Path::new(repo!("domains/rover"));
    let d = load_domain(&root.join("rover.ixt")).expect("rover domain");
    let p = load_problem(&root.join("problems/fig2.ixt"), &d).expect("fig2");
    let mut b = Builder::new(&d, &p);
    let mv = b.action("move", &["base", "p1"]);
    tiny::move_window(&mut b, mv, "base", "p1", 0.3, 0.6);
    let ptu = b.action("move_ptu", &["FORWARD", "DOWN"]);
    let pic = b.action("take_picture", &["p1"]);
    let (mv_st, mv_et, ptu_st, ptu_et, pic_st, pic_et) = (
        b.st(mv),
        b.et(mv),
        b.st(ptu),
        b.et(ptu),
        b.st(pic),
        b.et(pic),
    );
    b.before(PlanTp::ORIGIN, mv_st);
    b.before(mv_et, ptu_st);
    b.before(if ptu_before_picture { ptu_et } else { mv_et }, pic_st);
    // take_picture: AT_ROBOT = p1 from move's end event, PTU_POS = DOWN from move_ptu's end event.
    b.event_to_hold(mv, 1, pic, 0);
    b.event_to_hold(ptu, 1, pic, 1);
    b.link(
        Establisher::Initial,
        Consumer::EventFrom {
            action: mv,
            event: 0,
        },
    );
    b.achieve("g1", pic_et, pic, 0);
    let s = b.finish();
    (d, p, s)
}

#[test]
fn a_rover_plan_from_the_shipped_domain_is_accepted() {
    let (d, p, s) = rover_g1(true);
    let checked = validate(&d, &p, &s).unwrap_or_else(|e| panic!("{e}"));
    // move at 0.6 m/s over sqrt(116) m: ceil(17 950.3) ms.
    let et = s
        .timepoints
        .iter()
        .position(|t| t.name == "a1.et")
        .expect("a1.et");
    assert_eq!(checked.schedule[et], 1 + 17_951);
    assert_eq!(s.unachieved().count(), 4);
}

#[test]
fn a_rover_picture_before_the_ptu_is_down_is_rejected() {
    let (d, p, s) = rover_g1(false);
    let v = violations(&d, &p, &s);
    assert!(
        v.iter().any(
            |v| matches!(v, Violation::HoldBroken { action, lapse }
            if action == "a3 (take_picture)" && lapse.instance == "PTU_POS()" && lapse.value == "DOWN")
        ),
        "{v:#?}"
    );
    // The causal link from move_ptu's end now starts after the hold it supports.
    assert!(
        v.iter().any(|v| matches!(v, Violation::LinkMismatch { link, reason: LinkFault::EstablisherAfter { what: "hold", .. } }
            if link.contains("a2 event #1"))),
        "{v:#?}"
    );
}

fn steps() -> impl Strategy<Value = Vec<Step>> {
    prop::collection::vec(
        prop_oneof![(0usize..3).prop_map(Step::Go), Just(Step::Snap)],
        1..9,
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn random_sequential_plans_are_accepted_and_a_mutation_is_detected(
        steps in steps(),
        pick in any::<prop::sample::Index>(),
        shift in 1i64..5_000,
        drop in any::<bool>(),
    ) {
        let d = tiny::domain();
        let p = tiny::problem(&d, 60_000);
        let s = tiny::sequential(&d, &p, &steps, 2);
        prop_assert!(validate(&d, &p, &s).is_ok(), "{:?}", validate(&d, &p, &s).err());
        // Actions something else depends on (a link to another action or to a goal).
        let depended: Vec<_> = s.actions.iter().map(|a| a.id).filter(|&id| {
            s.causal_links.iter().any(|l| matches!(l.establisher, Establisher::Event { action, .. } if action == id)
                && !matches!(l.consumer, Consumer::Hold { action, .. } | Consumer::EventFrom { action, .. } if action == id))
        }).collect();
        if drop && !depended.is_empty() {
            let id = depended[pick.index(depended.len())];
            let mut m = s.clone();
            let tps = m.action(id).map(|a| a.timepoints.clone()).unwrap_or_default();
            m.actions.retain(|a| a.id != id);
            m.constraints.retain(|c| !tps.contains(&c.from) && !tps.contains(&c.to));
            m.causal_links.retain(|l| {
                !matches!(l.establisher, Establisher::Event { action, .. } if action == id)
                    && !matches!(l.consumer, Consumer::Hold { action, .. } | Consumer::EventFrom { action, .. } if action == id)
            });
            let v = violations(&d, &p, &m);
            prop_assert!(v.iter().any(|v| matches!(v,
                Violation::EventFrom { .. } | Violation::HoldBroken { .. } | Violation::LinkBroken { .. }
                | Violation::GoalBroken { .. } | Violation::GoalUnsupported { .. })), "dropped {:?}: {:#?}", id, v);
        } else if s.timepoints.len() > 1 {
            let i = 1 + pick.index(s.timepoints.len() - 1);
            let mut m = s.clone();
            let ub = m.timepoints[i].ub.unwrap_or(tiny::HORIZON);
            m.timepoints[i].lb = Some(ub + shift);
            m.timepoints[i].ub = Some(ub + shift + 1_000);
            let v = violations(&d, &p, &m);
            prop_assert!(v.iter().any(|v| matches!(v, Violation::WindowOutsideNetwork { tp, .. } if *tp == m.timepoints[i].name)), "{:#?}", v);
        }
    }
}

#[test]
fn simultaneous_changes_of_one_attribute_are_rejected() {
    let d = tiny::domain();
    let p = tiny::problem(&d, 60_000);
    let mut b = Builder::new(&d, &p);
    let go1 = b.action("go", &["a", "b"]);
    tiny::move_window(&mut b, go1, "a", "b", 0.5, 2.0);
    let go2 = b.action("go", &["b", "c"]);
    tiny::move_window(&mut b, go2, "b", "c", 0.5, 2.0);
    let (st1, et1, st2) = (b.st(go1), b.et(go1), b.st(go2));
    b.before(PlanTp::ORIGIN, st1);
    // [0, +oo[ instead of ]0, +oo[: at the earliest schedule go2 leaves b when go1 arrives there.
    b.constrain(et1, st2, Some(0), None);
    let v = violations(&d, &p, &b.finish());
    assert!(
        v.iter().any(
            |v| matches!(v, Violation::SimultaneousEvents { instance, time, first, second }
            if instance == "AT()" && *time == 5_001 && first == "a1 (go)" && second == "a2 (go)")
        ),
        "{v:#?}"
    );
}

#[test]
fn a_plan_for_another_problem_is_malformed() {
    let (d, p, mut s) = correct();
    s.problem = "other".into();
    assert!(
        matches!(violations(&d, &p, &s).as_slice(), [Violation::Malformed(m)] if m.contains("tiny/other"))
    );
    // A dangling action index is reported, not a panic.
    let (_, _, mut s) = correct();
    s.actions[0].timepoints[1] = PlanTp(999);
    assert!(matches!(
        violations(&d, &p, &s).as_slice(),
        [Violation::Malformed(_)]
    ));
}

#[test]
fn timepoints_after_the_horizon_are_rejected() {
    let (d, _, s) = correct();
    let mut short = tiny::problem(&d, 60_000);
    short.horizon = 6_000;
    let v = violations(&d, &short, &s);
    assert_eq!(
        v,
        vec![Violation::AfterHorizon {
            tp: "a2.et".into(),
            time: 6_002,
            horizon: 6_000
        }]
    );
}
