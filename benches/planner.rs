//! Criterion: planning time on the shipped problems and a generated 10-target rover grid (see
//! `mavtempo bench plan` for the 20- and 40-target grids).

use std::path::Path;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, Criterion};
use mavtempo::lang::load_problem_and_domain;
use mavtempo::planner::{solve, Budget};

/// The repository root: cargo runs a bench in its package's directory, `benches/`.
fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn bench(c: &mut Criterion) {
    for path in [
        "domains/rover/problems/fig2.ixt",
        "domains/rover/problems/dala.ixt",
        "domains/auv/problems/vents.ixt",
        "domains/shopping/problems/day.ixt",
    ] {
        let Ok((d, p)) = load_problem_and_domain(&root().join(path)) else {
            continue;
        };
        let (d, p) = (Arc::new(d), Arc::new(p));
        c.bench_function(&format!("plan {path}"), |b| {
            b.iter(|| solve(d.clone(), p.clone(), Budget::steps(20_000)).is_ok())
        });
    }
}

fn grid(c: &mut Criterion) {
    let Ok(d) = mavtempo::lang::load_domain(&root().join("domains/rover/rover.ixt")) else {
        return;
    };
    let text = mavtempo::lang::generate::rover_grid_problem(10);
    let Ok(p) = mavtempo::lang::parse_problem("grid10", &text, &d) else {
        return;
    };
    let (d, p) = (Arc::new(d), Arc::new(p));
    c.bench_function("plan rover/grid10", |b| {
        b.iter(|| solve(d.clone(), p.clone(), Budget::steps(20_000)).is_ok())
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(10);
    targets = bench, grid
}
criterion_main!(benches);
