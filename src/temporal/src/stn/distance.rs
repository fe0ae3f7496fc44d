//! On-demand shortest-path queries, without an all-pairs matrix.
//!
//! A path a→b through the origin weighs at least `d(a, origin) + d(origin, b) = ub[b] − lb[a]`, a value the
//! bounds give for free. The search starts from that bound, never expands the origin, and is an A* whose
//! heuristic comes from the bounds: both the earliest and (where finite) the latest times are solutions of
//! the network, so `d(x, b) ≥ max(lb[b] − lb[x], ub[b] − ub[x])`, a consistent lower bound (the same
//! potentials as the reduced-cost Dijkstra of the propagation). Nodes whose estimate reaches the bound found
//! so far are never expanded: when b's bounds are tight the search stays tiny.
//!
//! Ordering questions ("can b − a ≥ k?") only need to know whether the distance is below a threshold:
//! [`distance_below`] starts with the threshold as the bound, so a search that cannot beat it expands
//! almost nothing; it also stops at the first fixed timepoint it reaches (whose distance to b is exact).
//! The per-node labels live in a thread-local dense array reset by an epoch counter, not
//! in a hash map: the planner asks thousands of these per second.

use std::cell::RefCell;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::network::Stn;
use super::{sat_add, Time, INF};

#[derive(Default)]
struct Scratch {
    epoch: u32,
    stamp: Vec<u32>,
    dist: Vec<Time>,
    heap: BinaryHeap<Reverse<(Time, u32)>>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Shortest path a→b (maximum possible `b − a`), `INF` if unbounded.
pub(crate) fn distance(stn: &Stn, a: u32, b: u32) -> Time {
    bounded(stn, a, b, INF)
}

/// Whether the shortest path a→b is shorter than `limit`. A "no" the search proved is remembered
/// ([`super::memo`]): asked again, it is re-checked against the edges added since instead of searched.
pub(crate) fn distance_below(stn: &Stn, a: u32, b: u32, limit: Time) -> bool {
    if let Some(d) = kept(stn, a, b) {
        return d < limit;
    }
    if a != b && a != 0 && b != 0 {
        let via_origin = sat_add(stn.ub[b as usize], -stn.lb[a as usize]);
        if via_origin >= limit && stn.memo.proves(stn, a, b, limit) {
            return false;
        }
        let below = bounded(stn, a, b, limit) < limit;
        if !below {
            stn.memo.record(stn, a, b, limit);
        }
        return below;
    }
    bounded(stn, a, b, limit) < limit
}

/// The shortest path a→b from the matrix of paths avoiding the origin ([`super::paths`]) and the bounds,
/// when the matrix is kept.
#[inline]
fn kept(stn: &Stn, a: u32, b: u32) -> Option<Time> {
    if a == b {
        return Some(0);
    }
    let via_origin = sat_add(stn.ub[b as usize], -stn.lb[a as usize]);
    if a == 0 || b == 0 {
        return Some(via_origin);
    }
    stn.path_avoiding_origin(a, b).map(|d| d.min(via_origin))
}

/// The shortest path a→b if it is shorter than `limit`; otherwise some value `≥ limit`.
fn bounded(stn: &Stn, a: u32, b: u32, limit: Time) -> Time {
    if let Some(d) = kept(stn, a, b) {
        return d;
    }
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
    let mut best = via_origin.min(limit);
    if estimate(a) >= best {
        return best;
    }
    SCRATCH.with(|cell| {
        let mut s = cell.borrow_mut();
        let s = &mut *s;
        let n = stn.lb.len();
        if s.stamp.len() < n {
            s.stamp.resize(n, 0);
            s.dist.resize(n, INF);
        }
        s.epoch = s.epoch.wrapping_add(1);
        if s.epoch == 0 {
            s.stamp.iter_mut().for_each(|x| *x = 0);
            s.epoch = 1;
        }
        let epoch = s.epoch;
        s.heap.clear();
        s.stamp[a as usize] = epoch;
        s.dist[a as usize] = 0;
        s.heap.push(Reverse((estimate(a), a)));
        while let Some(Reverse((key, x))) = s.heap.pop() {
            let dx = s.dist[x as usize];
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
            // A fixed timepoint (executed, or pinned by its bounds) reaches b through the origin at exactly
            // its estimate, so no path beats `key` any more: the executive's networks are full of them.
            if lb[x as usize] == ub[x as usize] && ub_b < INF {
                best = key;
                break;
            }
            for &(y, w) in &stn.wout[x as usize] {
                if w >= INF || y == 0 {
                    continue;
                }
                let cand = sat_add(dx, w);
                let yi = y as usize;
                if s.stamp[yi] != epoch || cand < s.dist[yi] {
                    s.stamp[yi] = epoch;
                    s.dist[yi] = cand;
                    let k = sat_add(cand, estimate(y));
                    if k < best {
                        s.heap.push(Reverse((k, y)));
                    }
                }
            }
        }
    });
    best
}

/// Exact shortest paths from `a` to every timepoint (`forward`), or from every timepoint to `a`, `INF` where
/// unbounded: one Dijkstra for many ordering questions about the same timepoint (a flaw pass over ~n
/// candidates sharing an event). Reduced costs `w + lb[tail] − lb[head]` are ≥ 0 because the earliest times
/// are a solution; as in [`bounded`], the origin is never expanded and paths through it are priced by the
/// bounds (`ub[head] − lb[tail]`), which are exact distances to and from the origin.
pub(crate) fn all_distances(stn: &Stn, a: u32, forward: bool) -> Vec<Time> {
    let (lb, ub) = (&stn.lb, &stn.ub);
    let n = lb.len();
    let ai = a as usize;
    let mut out: Vec<Time> = (0..n)
        .map(|y| {
            if forward {
                sat_add(ub[y], -lb[ai])
            } else {
                sat_add(ub[ai], -lb[y])
            }
        })
        .collect();
    out[ai] = 0;
    if a == 0 {
        return out;
    }
    if stn.has_paths() {
        for (y, o) in out.iter_mut().enumerate().skip(1) {
            let (from, to) = if forward {
                (a, y as u32)
            } else {
                (y as u32, a)
            };
            if let Some(d) = stn.path_avoiding_origin(from, to) {
                *o = (*o).min(d);
            }
        }
        return out;
    }
    // Reduced distances from a (in the reversed graph when !forward).
    let mut reduced = vec![INF; n];
    let mut heap = BinaryHeap::new();
    reduced[ai] = 0;
    heap.push(Reverse((0, a)));
    while let Some(Reverse((dx, x))) = heap.pop() {
        if dx != reduced[x as usize] {
            continue; // stale
        }
        let halves = if forward {
            &stn.out[x as usize]
        } else {
            &stn.inc[x as usize]
        };
        for &h in halves {
            let (tail, head, w) = stn.half_edge(h);
            let y = if forward { head } else { tail };
            if w >= INF || y == 0 {
                continue;
            }
            let cand = dx + w + lb[tail as usize] - lb[head as usize];
            if cand < reduced[y as usize] {
                reduced[y as usize] = cand;
                heap.push(Reverse((cand, y)));
            }
        }
    }
    for (y, &r) in reduced.iter().enumerate() {
        if r < INF {
            // Undo the potentials: forward a→y adds lb[y] − lb[a], backward y→a adds lb[a] − lb[y].
            let d = if forward {
                r + lb[y] - lb[ai]
            } else {
                r + lb[ai] - lb[y]
            };
            out[y] = out[y].min(d);
        }
    }
    out
}
