//! Every shipped problem is solved and the independent checker accepts the plan.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use mavtempo::lang::load_problem_and_domain;
use mavtempo::plan::validate::validate;
use mavtempo::planner::{solve, Budget};

fn solve_and_check(path: &str) -> usize {
    let (d, p) = load_problem_and_domain(Path::new(path)).unwrap_or_else(|e| panic!("{path}: {e}"));
    let (d, p) = (Arc::new(d), Arc::new(p));
    let planned = solve(d.clone(), p.clone(), Budget::steps(20_000))
        .unwrap_or_else(|e| panic!("{path}: no plan: {e}"));
    let sol = planned.plan.to_solution(&HashMap::new());
    assert!(sol.unachieved().next().is_none(), "{path}: unachieved goals");
    if let Err(r) = validate(&d, &p, &sol) {
        panic!("{path}: checker rejects the plan: {r}");
    }
    sol.actions.len()
}

#[test]
fn rover_fig2_is_solved_and_checked() {
    let n = solve_and_check("domains/rover/problems/fig2.ixt");
    assert!(n >= 5 * 2 + 1, "five pictures, their moves and a download: {n} actions");
}

#[test]
fn rover_dala_is_solved_and_checked() {
    solve_and_check("domains/rover/problems/dala.ixt");
}

#[test]
fn auv_vents_is_solved_and_checked() {
    solve_and_check("domains/auv/problems/vents.ixt");
}

#[test]
fn shopping_day_is_solved_and_checked() {
    solve_and_check("domains/shopping/problems/day.ixt");
}
