//! The marking kept from the plan's change log (src/executive/src/dispatch/plan_adapter.rs) against Algorithm 2 run on the
//! plan's structure itself (an oracle that never reads the log): after every planning step of the shipped
//! shopping and AUV problems (with their backtracks), and through the executive's edits — past actions
//! leaving, links broken, a backtrack over those, a repaired clone replacing the plan, an unrelated plan.

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::dispatch::{search_for_goal, PlanMarking, PlanView};
use mavtempo_temporal::lang::load_problem_and_domain;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_temporal::planner::{Search, StepOutcome};

fn root(problem: &str) -> PartialPlan {
    let (d, p) = load_problem_and_domain(Path::new(problem)).expect("problem loads");
    PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan")
}

/// Every live action's mark equals Algorithm 2 on the plan; returns how many actions are marked.
fn check(marking: &mut PlanMarking, plan: &PartialPlan, when: &str) -> usize {
    marking.sync(plan).expect("the log fits the plan");
    let view = PlanView(plan);
    let mut marked = 0;
    for a in plan.live_actions() {
        let oracle = search_for_goal(&view, a);
        assert_eq!(
            marking.supports_external_goal(a),
            oracle,
            "{when}: action {a:?}"
        );
        marked += usize::from(oracle);
    }
    let in_graph = marking.marking().graph().num_actions();
    assert_eq!(in_graph, plan.live_actions().count(), "{when}");
    marked
}

fn plan_step_by_step(problem: &str) -> (PartialPlan, PlanMarking) {
    let mut search = Search::new(root(problem));
    let mut marking = PlanMarking::new();
    for step in 0..20_000 {
        match search.step() {
            StepOutcome::Progress => {}
            StepOutcome::Solved => break,
            other => panic!("{problem}: {other:?}"),
        }
        check(
            &mut marking,
            search.plan(),
            &format!("{problem} step {step}"),
        );
    }
    let plan = search.into_plan();
    let marked = check(&mut marking, &plan, problem);
    assert!(
        marked > 0,
        "{problem}: some action serves the external goal"
    );
    assert!(
        marked < plan.live_actions().count(),
        "{problem}: some action serves only the internal goal"
    );
    (plan, marking)
}

#[test]
fn marking_follows_planning_with_backtracks_on_both_shipped_problems() {
    plan_step_by_step(repo!("domains/shopping/problems/day.ixt"));
    plan_step_by_step(repo!("domains/auv/problems/vents.ixt"));
}

#[test]
fn marking_follows_the_executives_edits_clones_and_replacements() {
    let (mut plan, mut marking) = plan_step_by_step(repo!("domains/shopping/problems/day.ixt"));
    let before = marking.rebuilds();
    // Past actions leave the plan (their links stay in the plan, not in the dispatcher's graph).
    let level = plan.save();
    let first: Vec<_> = plan.live_actions().take(3).collect();
    for &a in &first {
        plan.remove_action(a);
        check(&mut marking, &plan, "past action removed");
    }
    // The executive breaks the links into a goal (a contradicted state value).
    let goal_links: Vec<_> = plan
        .goals()
        .iter()
        .filter_map(|g| plan.cond(g.cond).link)
        .collect();
    for l in goal_links {
        plan.remove_link(l);
        check(&mut marking, &plan, "goal link broken");
    }
    assert!(
        plan.live_actions()
            .all(|a| !marking.supports_external_goal(a)),
        "nothing reaches a goal any more"
    );
    // A repair search works on a clone: it continues the log read so far.
    let mut repaired = plan.clone();
    repaired.restore(level);
    check(&mut marking, &repaired, "clone restored over the removals");
    assert!(repaired
        .live_actions()
        .any(|a| marking.supports_external_goal(a)));
    assert_eq!(marking.rebuilds(), before, "a clone continues the log");
    // Going back to the original, which went on differently after the fork: rebuilt from its log.
    let next = plan.live_actions().next().expect("an action is left");
    plan.remove_action(next);
    check(&mut marking, &plan, "back to the diverged original");
    assert_eq!(marking.rebuilds(), before + 1);
    // A plan of another problem altogether.
    let (vents, _) = plan_step_by_step(repo!("domains/auv/problems/vents.ixt"));
    check(&mut marking, &vents, "unrelated plan");
    assert_eq!(marking.rebuilds(), before + 2);
}
