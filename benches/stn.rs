//! Criterion benches of the STN: one incremental insertion, one execution, one distance query, and one
//! Floyd–Warshall solve of the same plan-like network (the figures of `mavtempo bench stn`, with statistics).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use mavtempo::bench::stn::plan_like;
use mavtempo::stn::{floyd_warshall, Stn, Timepoint};

fn timepoints(stn: &Stn) -> Vec<Timepoint> {
    stn.timepoints().collect()
}

fn stn_benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("stn");
    for n in [100usize, 1_000, 10_000] {
        g.sample_size(20);
        let plan = plan_like(n, 42 + n as u64);
        let Some(full) = plan.build() else {
            eprintln!("plan-like network of {n} timepoints is inconsistent: skipped");
            continue;
        };
        let tps = timepoints(&full);
        // Insert the last constraint into the network holding all the others.
        let (&(f, t, lb, ub), _) = plan
            .constraints
            .split_last()
            .unwrap_or((&(0, 1, 0, 0), &[]));
        let mut base = full.clone();
        if let Some((id, _)) = base.constraints().last() {
            base.remove_constraint(id);
        }
        g.bench_function(format!("insert/{n}"), |b| {
            b.iter(|| {
                let level = base.save();
                black_box(base.add_constraint(tps[f as usize], tps[t as usize], lb, ub)).ok();
                base.restore(level);
            })
        });
        // Execute the first unexecuted timepoint of the schedule at its earliest time, then undo.
        let mut exec = full.clone();
        let first = (0..plan.timepoints)
            .min_by_key(|&i| plan.schedule[i])
            .unwrap_or(0);
        let tp = tps[first + 1];
        g.bench_function(format!("execute/{n}"), |b| {
            b.iter(|| {
                let level = exec.save();
                black_box(exec.execute(tp, exec.lb(tp))).ok();
                exec.restore(level);
            })
        });
        let (a, z) = (tps[1], tps[tps.len() - 1]);
        g.bench_function(format!("distance/{n}"), |b| {
            b.iter(|| black_box(full.distance(a, z)))
        });
        if n <= 1_000 {
            g.sample_size(10);
            g.bench_function(format!("floyd_warshall/{n}"), |b| {
                b.iter(|| black_box(floyd_warshall::solve(&full)))
            });
        }
    }
    g.finish();
}

criterion_group!(benches, stn_benches);
criterion_main!(benches);
