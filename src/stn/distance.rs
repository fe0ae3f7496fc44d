//! On-demand shortest-path queries, without an all-pairs matrix.
//!
//! A path a→b through the origin weighs at least `d(a, origin) + d(origin, b) = ub[b] − lb[a]`, a value the
//! bounds give for free. The search starts from that bound, never expands the origin, and is an A* whose
//! heuristic comes from the bounds: both the earliest and (where finite) the latest times are solutions of
//! the network, so `d(x, b) ≥ max(lb[b] − lb[x], ub[b] − ub[x])`, a consistent lower bound (the same
//! potentials as the reduced-cost Dijkstra of the propagation). Nodes whose estimate reaches the bound found
//! so far are never expanded: when b's bounds are tight the search stays tiny.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use super::network::Stn;
use super::{sat_add, Time, INF};

/// Shortest path a→b (maximum possible `b − a`), `INF` if unbounded.
pub(crate) fn distance(stn: &Stn, a: u32, b: u32) -> Time {
    if a == b {
        return 0;
    }
    let (lb, ub) = (&stn.lb, &stn.ub);
    let via_origin = sat_add(ub[b as usize], -lb[a as usize]);
    if a == 0 || b == 0 {
        return via_origin;
    }
    let (lb_b, ub_b) = (lb[b as usize], ub[b as usize]);
    let estimate = |x: u32| {
        let by_lb = lb_b - lb[x as usize];
        let ub_x = ub[x as usize];
        if ub_b < INF && ub_x < INF {
            by_lb.max(ub_b - ub_x)
        } else {
            by_lb
        }
    };
    let mut best = via_origin;
    let mut dist: HashMap<u32, Time> = HashMap::new();
    let mut heap = BinaryHeap::new();
    dist.insert(a, 0);
    heap.push(Reverse((estimate(a), a)));
    while let Some(Reverse((key, x))) = heap.pop() {
        let dx = dist.get(&x).copied().unwrap_or(INF);
        if key != sat_add(dx, estimate(x)) {
            continue; // stale
        }
        if key >= best {
            break;
        }
        if x == b {
            best = dx;
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
                heap.push(Reverse((sat_add(cand, estimate(y)), y)));
            }
        }
    }
    best
}
