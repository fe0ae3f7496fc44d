//! The benchmarks' generators (`mavtempo bench`, the soak) give what they promise to the layers they feed:
//! plan-like networks the incremental STN keeps as Floyd–Warshall does, rover missions the planner solves.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use mavtempo::bench::stn::plan_like;
use mavtempo::bench::suite::generate::{problem, SuiteDomain};
use mavtempo::plan::validate::validate;
use mavtempo::planner::{solve, Budget};
use mavtempo::stn::{floyd_warshall, Stn, Timepoint};

/// The network's bounds and distances are the oracle's (a full Floyd–Warshall over its constraints).
fn agrees_with_floyd_warshall(stn: &Stn) {
    let apsp = floyd_warshall::solve(stn).expect("the oracle finds the network consistent");
    for a in stn.timepoints() {
        assert_eq!(
            (stn.lb(a), stn.ub(a)),
            (apsp.lb(a), apsp.ub(a)),
            "bounds of {a:?}"
        );
        for b in stn.timepoints() {
            assert_eq!(
                stn.distance(a, b),
                apsp.distance(a, b),
                "distance {a:?}->{b:?}"
            );
        }
    }
}

/// Builds a plan-like network and checks it against the oracle after every few insertions and executions.
#[test]
fn generated_plan_like_network_equals_floyd_warshall() {
    let plan = plan_like(60, 7);
    let mut stn = Stn::new();
    for _ in 0..plan.timepoints {
        stn.add_timepoint();
    }
    let tps: Vec<Timepoint> = stn.timepoints().collect();
    for (i, &(f, t, lb, ub)) in plan.constraints.iter().enumerate() {
        stn.add_constraint(tps[f as usize], tps[t as usize], lb, ub)
            .expect("the generated network is consistent by construction");
        if i % 25 == 0 {
            agrees_with_floyd_warshall(&stn);
        }
    }
    agrees_with_floyd_warshall(&stn);
    for i in 0..plan.timepoints {
        let t = tps[i + 1];
        stn.execute(t, stn.lb(t))
            .expect("executing at the earliest time is consistent");
        if i % 10 == 0 {
            agrees_with_floyd_warshall(&stn);
        }
    }
    agrees_with_floyd_warshall(&stn);
}

/// Random rover missions of 8 pictures (the suite's generator, seeds the planner was not tuned on) need
/// three downloads in the visibility windows: the download sends what is stored, a saturating
/// production, so the storage envelope no longer drifts with the pictures' uncertain sizes.
#[test]
fn random_rover_missions_of_eight_pictures_are_solved_and_checked() {
    let d = Arc::new(
        mavtempo::lang::load_domain(Path::new("domains/rover/rover.ixt")).expect("domain"),
    );
    for seed in [1000, 1001, 1003, 1006] {
        let text = problem(SuiteDomain::Rover, 8, seed);
        let p = mavtempo::lang::parse_problem("rover8", &text, &d).expect("generated problem");
        let planned = solve(d.clone(), Arc::new(p.clone()), Budget::steps(20_000))
            .unwrap_or_else(|e| panic!("seed {seed}: no plan: {e}"));
        let sol = planned.plan.to_solution(&HashMap::new());
        assert!(sol.unachieved().next().is_none(), "seed {seed}");
        if let Err(r) = validate(&d, &p, &sol) {
            panic!("seed {seed}: checker rejects the plan: {r}");
        }
        let downloads = sol
            .actions
            .iter()
            .filter(|a| a.task_name == "download_images")
            .count();
        assert!(
            downloads >= 2,
            "seed {seed}: {downloads} downloads for 8 pictures in 3 slots"
        );
    }
}
