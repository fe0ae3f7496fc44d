//! Shipped problems are solved and the independent checker accepts the plan. (The rover problems fig2 and
//! dala are not solved yet within a practical step budget: see the planner's issue note.)

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use mavtempo::lang::load_problem_and_domain;
use mavtempo::plan::validate::validate;
use mavtempo::planner::{solve, Budget};

fn solve_and_check(path: &str) -> usize {
    let (d, p) = load_problem_and_domain(Path::new(path)).unwrap_or_else(|e| panic!("{path}: {e}"));
    let (d, p) = (Arc::new(d), Arc::new(p));
    let planned = solve(d.clone(), p.clone(), Budget::steps(3_000))
        .unwrap_or_else(|e| panic!("{path}: no plan: {e}"));
    let sol = planned.plan.to_solution(&HashMap::new());
    assert!(
        sol.unachieved().next().is_none(),
        "{path}: unachieved goals"
    );
    if let Err(r) = validate(&d, &p, &sol) {
        panic!("{path}: checker rejects the plan: {r}");
    }
    sol.actions.len()
}

#[test]
fn auv_vents_is_solved_and_checked() {
    let n = solve_and_check("domains/auv/problems/vents.ixt");
    assert!(n >= 4, "go, survey, sample, go back: {n} actions");
}

#[test]
fn shopping_day_is_solved_and_checked() {
    solve_and_check("domains/shopping/problems/day.ixt");
}
