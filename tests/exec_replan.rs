//! Complete replanning (seed 1 §3.6): P_ti extraction, T_end, goal rejection order.

#[path = "common/mapping.rs"]
mod mapping;

use std::path::Path;
use std::sync::Arc;

use mavtempo::exec::config::ExecConfig;
use mavtempo::exec::executive::Executive;
use mavtempo::exec::replan::{extract, goal_to_reject};
use mavtempo::lang::load_problem_and_domain;
use mavtempo::model::{GoalId, Value};
use mavtempo::plan::PartialPlan;

fn fig2() -> Executive {
    let (d, p) =
        load_problem_and_domain(Path::new("domains/rover/problems/fig2.ixt")).expect("fig2 loads");
    let plan = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mapping = mapping::rover(&plan);
    Executive::new(plan, ExecConfig::default()).with_mapping(mapping)
}

#[test]
fn rejection_order_lowest_priority_then_least_flexibility() {
    let ex = fig2();
    let mut plan = ex.plan.clone();
    // g3 has priority 3; among the others (priority 1) the least st_ub − d_achiev is g2's (window 4 min,
    // d_achiev 55 s), then, with the same 30 min window, g5 (d_achiev 80 s), g4 (65 s), g1 (25 s).
    let mut order = Vec::new();
    while let Some(g) = goal_to_reject(&plan) {
        order.push(plan.problem.goals[g.index()].name.clone());
        plan.remove_goal(g);
    }
    assert_eq!(order, ["g2", "g5", "g4", "g1", "g3"]);
}

#[test]
fn p_ti_keeps_the_state_drops_incoherent_goals_and_puts_goals_after_t_end() {
    let mut ex = fig2();
    let at = ex.plan.domain.attr_id("AT_ROBOT").unwrap();
    let p1 = ex.plan.problem.object_id("p1").unwrap();
    let now = 9 * 60_000;
    ex.state.set((at, vec![]), now - 1_000, Value::Obj(p1));
    let storage = ex.resource("STORAGE").unwrap();
    ex.past[storage.index()] = (1.2, 1.4);
    // g1 achieved already: not in G_ti.
    ex.set_fate(GoalId(0), mavtempo::exec::executive::Fate::Achieved, "");
    let ext = extract(&ex, now, &[]).expect("P_ti");
    // S_ti = S_ts: the robot is at p1, the storage level its pessimistic bound.
    let init = ext
        .plan
        .problem
        .initial
        .iter()
        .find(|f| f.attr == at)
        .expect("AT_ROBOT in the initial state");
    assert_eq!(init.value, Value::Obj(p1));
    assert!((ext.plan.problem.resources[storage.index()].level - 1.2).abs() < 1e-9);
    // g2 (st ≤ 4 min) and g3 (st ≤ 8 min) are no longer coherent with 9 min; g1 is done; g4, g5 remain.
    assert_eq!(ext.incoherent, vec![GoalId(1), GoalId(2)]);
    let active: Vec<u32> = ext
        .plan
        .goals
        .iter()
        .filter(|g| g.active)
        .map(|g| g.goal.0)
        .collect();
    assert_eq!(active, vec![3, 4]);
    // T_end after now; each goal after T_end; new timepoints after T_end.
    assert!(ext.plan.stn.lb(ext.t_end) >= now);
    for g in ext.plan.goals.iter().filter(|g| g.active) {
        assert!(ext.plan.stn.necessarily_before(ext.t_end, g.st));
    }
    let mut plan = ext.plan;
    let tp = plan.new_timepoint().unwrap();
    assert!(plan.stn.necessarily_before(ext.t_end, tp));
    // Inserting actions lowers T_end's upper bound ("planning to plan").
    let before = plan.stn.ub(ext.t_end);
    let g4 = plan.goals.iter().find(|g| g.active).expect("g4 active").st;
    plan.stn
        .add_constraint(tp, g4, 600_000, mavtempo::stn::INF)
        .unwrap();
    assert!(plan.stn.ub(ext.t_end) < before);
}
