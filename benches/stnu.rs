//! Criterion bench of the STNU dynamic-controllability check: Morris 2014's O(n³) algorithm against the
//! tightening fixpoint of Morris & Muscettola 2005, on dynamically controllable plan-like STNUs.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use mavtempo::bench::stnu::dc_plan_like;
use mavtempo::stn::dc_reference;

fn dc_benches(c: &mut Criterion) {
    let mut g = c.benchmark_group("stnu_dc");
    g.sample_size(10);
    for n in [20usize, 50, 100] {
        let s = dc_plan_like(n, 7 + n as u64);
        g.bench_function(format!("morris2014/{n}"), |b| {
            b.iter(|| black_box(s.check_dc().is_ok()))
        });
        g.bench_function(format!("fixpoint/{n}"), |b| {
            b.iter(|| black_box(dc_reference::is_dc(&s)))
        });
    }
    g.finish();
}

criterion_group!(benches, dc_benches);
criterion_main!(benches);
