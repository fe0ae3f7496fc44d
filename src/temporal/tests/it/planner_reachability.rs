//! Fast, explained failure: a goal that cannot be achieved even alone is refused before the search, named,
//! with the dead end its single-goal search met — instead of a full search running into its budget.

use mavtempo_testkit::problems as common;

use std::sync::Arc;

use mavtempo_temporal::plan::PartialPlan;
use mavtempo_temporal::planner::reachability::{unreachable_goals, STEPS_PER_GOAL};
use mavtempo_temporal::planner::{solve, solve_portfolio_with, Budget, PlanFailure};

#[test]
fn a_target_beyond_the_battery_is_refused_at_once_and_named() {
    let d = Arc::new(common::rover());
    // 500 m at 0.5 % per metre: 250 % of a 100 % battery for the last leg alone.
    let p = Arc::new(common::fig2_with_far_target(&d, 500.0, 1));
    match solve(d, p, Budget::steps(200_000)) {
        Err(PlanFailure::Unreachable(u)) => {
            assert_eq!(u.name, "gfar");
            assert!(u.reason.contains("BATTERY"), "{}", u.reason);
            assert!(u.reason.contains("capacity"), "{}", u.reason);
        }
        other => panic!("expected gfar refused before the search, got {other:?}"),
    }
}

/// The portfolio's other search (the forward search of a PDDL problem) has its first slice before the
/// root's reachability analysis — a plan it finds there needs none — and the analysis still refuses what
/// it refuses when it does not.
#[test]
fn the_other_search_has_its_first_slice_before_the_reachability_analysis() {
    let d = Arc::new(common::rover());
    let p = Arc::new(common::fig2_with_far_target(&d, 500.0, 1));
    let mut slices = Vec::new();
    let out = solve_portfolio_with(d, p, Budget::steps(200_000), &mut |steps, share| {
        slices.push((steps, share));
        Err(7)
    });
    match out {
        Err(PlanFailure::Unreachable(u)) => assert_eq!(u.name, "gfar"),
        other => panic!("expected gfar refused, got {other:?}"),
    }
    assert_eq!(slices.len(), 1, "one slice, before gfar was refused");
    assert_eq!(slices[0].0, 200_000, "the whole step budget is left to it");
}

#[test]
fn a_window_closing_before_the_target_can_be_reached_is_refused_and_named() {
    let d = Arc::new(common::rover());
    // p2 is 27 m away and the rover drives at most 0.6 m/s: its picture cannot start within 40 s.
    let text = std::fs::read_to_string(repo!("domains/rover/problems/fig2.ixt")).expect("fig2");
    let window = "    st in [0, 4min];\n    achieve 55s;";
    assert!(
        text.contains(window),
        "g2's window is in the shipped problem"
    );
    let changed = text.replace(window, "    st in [0, 40s];\n    achieve 5s;");
    let p = Arc::new(
        mavtempo_temporal::lang::parse_problem("fig2-g2-40s", &changed, &d).expect("parses"),
    );
    match solve(d, p, Budget::steps(200_000)) {
        Err(PlanFailure::Unreachable(u)) => {
            assert_eq!(u.name, "g2");
            assert!(u.reason.contains("move"), "{}", u.reason);
        }
        other => panic!("expected g2 refused before the search, got {other:?}"),
    }
}

#[test]
fn reachable_goals_are_not_refused() {
    let d = Arc::new(common::rover());
    // A target 60 m away (30 % of the battery) is reachable alone: nothing is refused.
    let p = Arc::new(common::fig2_with_far_target(&d, 60.0, 1));
    let root = PartialPlan::new(d.clone(), p).expect("root plan");
    assert_eq!(unreachable_goals(&root, STEPS_PER_GOAL), Vec::new());
    let p = Arc::new(common::fig2_with_g2_window(&d, "90s"));
    let root = PartialPlan::new(d, p).expect("root plan");
    assert_eq!(unreachable_goals(&root, STEPS_PER_GOAL), Vec::new());
}
