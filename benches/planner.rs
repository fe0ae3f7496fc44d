//! Criterion: planning time on the shipped problems the planner solves (see `mavtempo bench plan` for all).

use std::path::Path;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use mavtempo::lang::load_problem_and_domain;
use mavtempo::planner::{solve, Budget};

fn bench(c: &mut Criterion) {
    for path in [
        "domains/auv/problems/vents.ixt",
        "domains/shopping/problems/day.ixt",
    ] {
        let Ok((d, p)) = load_problem_and_domain(Path::new(path)) else {
            continue;
        };
        let (d, p) = (Arc::new(d), Arc::new(p));
        c.bench_function(&format!("plan {path}"), |b| {
            b.iter(|| solve(d.clone(), p.clone(), Budget::steps(20_000)).is_ok())
        });
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench
}
criterion_main!(benches);
