//! The planner on small problems of a camera domain: flexible plans, resource conflicts solved by ordering
//! and by inserting a producer, typed failure reasons, step-wise search with plan-change notifications.

use mavtempo_testkit::problems as common;

use std::collections::HashMap;
use std::sync::Arc;

use mavtempo_temporal::lang::{parse_domain, parse_problem};
use mavtempo_temporal::model::{Domain, Problem};
use mavtempo_temporal::plan::validate::validate;
use mavtempo_temporal::plan::{PartialPlan, PlanChange, UsageKind};
use mavtempo_temporal::planner::{solve, Budget, FailReason, PlanFailure, Search, StepOutcome};

/// Pictures of targets; a unary camera (optional) and a storage reservoir freed by downloads.
fn domain(with_camera: bool) -> Arc<Domain> {
    let camera = if with_camera {
        "use(CAMERA: 1, (st, et));"
    } else {
        ""
    };
    let text = format!(
        "domain snap;
         type target;
         attribute PICTURE(?t: target): bool;
         resource CAMERA: unary;
         resource STORAGE: reservoir capacity 3;
         task take(?t: target) (st, et) {{
             event(PICTURE(?t): (false, true), et);
             {camera}
             consume(STORAGE: 1, st);
             (et - st) in [5, 10];
         }} nonPreemptive
         task download() (st, et) {{
             produce(STORAGE: ?freed, et);
             variable ?freed;
             ?freed in [1, 3];
             (et - st) in [10, 20];
         }} nonPreemptive"
    );
    Arc::new(parse_domain("snap.ixt", &text).unwrap_or_else(|e| panic!("{e}")))
}

fn problem(d: &Domain, targets: usize, deadline_s: Option<u32>) -> Arc<Problem> {
    let mut text = String::from("problem p; domain snap; horizon 30min;\n");
    for i in 1..=targets {
        text += &format!("object t{i}: target;\n");
    }
    text += "initial { PICTURE(*) = false; }\nresource STORAGE: level 3, capacity 3;\n";
    for i in 1..=targets {
        let window = deadline_s.map_or(String::new(), |s| format!("st in [0, {s}s];"));
        text += &format!("goal g{i} {{ hold(PICTURE(t{i}): true, (st, et)); {window} }}\n");
    }
    Arc::new(parse_problem("p.ixt", &text, d).unwrap_or_else(|e| panic!("{e}")))
}

fn checked(d: &Arc<Domain>, p: &Arc<Problem>) -> PartialPlan {
    let planned =
        solve(d.clone(), p.clone(), Budget::steps(5_000)).unwrap_or_else(|e| panic!("{e}"));
    let sol = planned.plan.to_solution(&HashMap::new());
    assert_eq!(sol.unachieved().count(), 0);
    if let Err(r) = validate(d, p, &sol) {
        panic!("checker rejects: {r}");
    }
    planned.plan
}

fn takes(plan: &PartialPlan) -> Vec<mavtempo_temporal::plan::ActionId> {
    plan.live_actions()
        .filter(|&a| plan.domain().task(plan.action(a).task).name == "take")
        .collect()
}

/// The checked plan for two pictures, the camera a unary resource or not, and its two `take` actions.
fn two_takes(camera_unary: bool) -> (PartialPlan, [mavtempo_temporal::plan::ActionId; 2]) {
    let d = domain(camera_unary);
    let plan = checked(&d, &problem(&d, 2, None));
    let t = takes(&plan);
    assert_eq!(t.len(), 2);
    (plan, [t[0], t[1]])
}

#[test]
fn independent_actions_stay_unordered() {
    let (plan, [a, b]) = two_takes(false);
    let (a, b) = (plan.action(a), plan.action(b));
    // Least commitment: either order (and overlap) remains possible.
    assert!(plan.temporal_network().possibly_before(a.end, b.start));
    assert!(plan.temporal_network().possibly_before(b.end, a.start));
    assert!(
        plan.temporal_network().possibly_before(a.start, b.end)
            && plan.temporal_network().possibly_before(b.start, a.end)
    );
}

#[test]
fn unary_resource_conflict_is_solved_by_ordering() {
    let (plan, [a, b]) = two_takes(true);
    let (a, b) = (plan.action(a), plan.action(b));
    let ordered = |x: &mavtempo_temporal::plan::Action, y: &mavtempo_temporal::plan::Action| {
        !plan.temporal_network().possibly_before(y.start, x.end)
    };
    assert!(
        ordered(a, b) || ordered(b, a),
        "the camera uses must not overlap"
    );
}

#[test]
fn fourth_picture_with_capacity_three_needs_a_download_before_it() {
    let d = domain(true);
    let plan = checked(&d, &problem(&d, 4, None));
    let downloads: Vec<_> = plan
        .live_actions()
        .filter(|&a| plan.domain().task(plan.action(a).task).name == "download")
        .collect();
    assert_eq!(
        downloads.len(),
        1,
        "one download frees room for the fourth picture"
    );
    let dl = plan.action(downloads[0]);
    let produced_at = plan
        .action(downloads[0])
        .usages
        .iter()
        .find_map(|&u| match plan.usage(u).kind {
            UsageKind::Produce { at } => Some(at),
            _ => None,
        })
        .unwrap_or(dl.end);
    // At least one picture is necessarily after the download's production.
    let after = takes(&plan)
        .into_iter()
        .filter(|&a| {
            plan.temporal_network()
                .necessarily_before(produced_at, plan.action(a).start)
                || {
                    let s = plan.action(a).start;
                    plan.temporal_network().distance(s, produced_at) <= 0
                }
        })
        .count();
    assert!(after >= 1);
    // Three pictures without a download: no producer needed.
    let plan3 = checked(&d, &problem(&d, 3, None));
    assert_eq!(plan3.num_actions(), 3);
}

#[test]
fn impossible_deadline_reports_the_root_flaw() {
    let d = domain(false);
    // A picture takes at least 5 s; the goal must hold from at most 2 s on.
    let p = problem(&d, 1, Some(2));
    match solve(d, p, Budget::steps(1_000)) {
        Err(PlanFailure::Search(FailReason::NoResolver { flaw })) => {
            assert!(flaw.contains("PICTURE(t1) = true"), "{flaw}");
        }
        other => panic!("expected no resolver at the root, got {other:?}"),
    }
}

#[test]
fn step_budget_is_a_resumable_deadline_and_changes_are_logged() {
    let d = domain(true);
    let root = PartialPlan::new(d.clone(), problem(&d, 4, None)).unwrap_or_else(|e| panic!("{e}"));
    let cursor = root.change_cursor();
    let mut search = Search::new(root);
    assert_eq!(
        search.run(Budget::steps(1)),
        StepOutcome::Failed(FailReason::Deadline { steps: 1 })
    );
    let mut outcome = StepOutcome::Progress;
    for _ in 0..5_000 {
        outcome = search.step();
        if outcome != StepOutcome::Progress {
            break;
        }
    }
    assert_eq!(outcome, StepOutcome::Solved);
    // Replaying the change log gives exactly the plan's live actions and links.
    let mut actions = std::collections::BTreeSet::new();
    let mut links = std::collections::BTreeSet::new();
    for c in search.plan().changes_since(cursor) {
        match *c {
            PlanChange::ActionAdded(a) => assert!(actions.insert(a)),
            PlanChange::ActionRemoved(a) => assert!(actions.remove(&a)),
            PlanChange::LinkAdded(e) => assert!(links.insert(e.link)),
            PlanChange::LinkRemoved(e) => assert!(links.remove(&e.link)),
            _ => {}
        }
    }
    let live: std::collections::BTreeSet<_> = search.plan().live_actions().collect();
    assert_eq!(actions, live);
    assert_eq!(
        links.len(),
        search.plan().links().iter().filter(|l| l.active).count()
    );
    assert!(search.executable(&[]));
}

/// `next_is_backtrack` (seed 1 §3.6's exception to the time limit) is true exactly when the next step
/// backtracks, and asking does not change the search.
#[test]
fn next_is_backtrack_predicts_the_next_step() {
    let d = common::rover();
    // g2's picture within the first minute: the tour must begin at p2, which the search finds only after
    // backtracking.
    let p = common::fig2_with_g2_window(&d, "60s");
    let root =
        mavtempo_temporal::plan::PartialPlan::new(std::sync::Arc::new(d), std::sync::Arc::new(p))
            .expect("root plan");
    let mut peeking = mavtempo_temporal::planner::Search::new(root.clone());
    let mut plain = mavtempo_temporal::planner::Search::new(root);
    let mut predictions = 0;
    for _ in 0..2_000 {
        let predicted = peeking.next_is_backtrack();
        predictions += usize::from(predicted);
        let before = peeking.backtracks();
        let a = peeking.step();
        let b = plain.step();
        assert_eq!(a, b, "peeking changed the search");
        assert_eq!(
            predicted,
            peeking.backtracks() > before,
            "prediction {predicted} at step {}",
            peeking.steps()
        );
        if a != mavtempo_temporal::planner::StepOutcome::Progress {
            break;
        }
    }
    assert_eq!(peeking.steps(), plain.steps());
    assert_eq!(peeking.backtracks(), plain.backtracks());
    assert!(
        plain.backtracks() > 0,
        "the problem should need backtracking"
    );
    assert!(predictions > 0, "no backtrack was predicted");
}

/// A `from` condition nothing can support (the rover's position is unknown) must not be "supported" by an
/// endless chain of moves, each needing the previous one: the regression bound makes the search fail for
/// good, quickly, instead of running into the step budget.
#[test]
fn unsupportable_from_condition_fails_instead_of_regressing_forever() {
    let d = mavtempo_temporal::lang::load_domain(std::path::Path::new(repo!(
        "domains/rover/rover.ixt"
    )))
    .expect("shipped domain");
    // Fig. 2 up to its first goal, without the rover's position.
    let full =
        std::fs::read_to_string(repo!("domains/rover/problems/fig2.ixt")).expect("shipped problem");
    let text =
        full[..full.find("goal g2").expect("g2 in fig2")].replace("    AT_ROBOT() = base;\n", "");
    let p = mavtempo_temporal::lang::parse_problem("fig2-lost", &text, &d).expect("problem parses");
    let root =
        mavtempo_temporal::plan::PartialPlan::new(std::sync::Arc::new(d), std::sync::Arc::new(p))
            .expect("root plan");
    let mut search = mavtempo_temporal::planner::Search::new(root);
    let outcome = search.run(mavtempo_temporal::planner::Budget::steps(5_000));
    match outcome {
        mavtempo_temporal::planner::StepOutcome::Failed(
            mavtempo_temporal::planner::FailReason::Exhausted { .. }
            | mavtempo_temporal::planner::FailReason::NoResolver { .. },
        ) => {}
        other => panic!("expected a definitive failure, got {other:?}"),
    }
    assert!(
        search.plan().num_actions() < 50,
        "the plan grew without bound"
    );
}
