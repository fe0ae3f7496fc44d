//! On-demand shortest-path queries, without an all-pairs matrix.
//!
//! A path a→b through the origin weighs at least `d(a, origin) + d(origin, b) = ub[b] − lb[a]`, a value the
//! bounds give for free. The search therefore starts from that bound, never expands the origin, and runs a
//! Dijkstra over reduced costs (the lower bounds are a feasible potential) pruned at the bound: when b's
//! bounds are tight the search stays tiny.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use super::network::Stn;
use super::{sat_add, Time, INF};

/// Shortest path a→b (maximum possible `b − a`), `INF` if unbounded.
pub(crate) fn distance(stn: &Stn, a: u32, b: u32) -> Time {
    if a == b {
        return 0;
    }
    let lb = &stn.lb;
    let via_origin = sat_add(stn.ub[b as usize], -lb[a as usize]);
    if a == 0 || b == 0 {
        return via_origin;
    }
    // Reduced distance r(x) = d(a, x) + lb[a] − lb[x] ≥ 0.
    let reduced = |x: u32, d: Time| d + lb[a as usize] - lb[x as usize];
    let mut best = via_origin;
    let mut dist: HashMap<u32, Time> = HashMap::new();
    let mut heap = BinaryHeap::new();
    dist.insert(a, 0);
    heap.push(Reverse((reduced(a, 0), a)));
    while let Some(Reverse((key, x))) = heap.pop() {
        let dx = dist[&x];
        if key != reduced(x, dx) {
            continue;
        }
        if best < INF && key >= reduced(b, best) {
            break;
        }
        if x == b {
            best = best.min(dx);
            break;
        }
        for &h in &stn.out[x as usize] {
            let (_, y, w) = stn.half_edge(h);
            if w >= INF || y == 0 {
                continue;
            }
            let cand = sat_add(dx, w);
            if dist.get(&y).is_none_or(|&dy| cand < dy) {
                dist.insert(y, cand);
                heap.push(Reverse((reduced(y, cand), y)));
            }
        }
    }
    best
}
