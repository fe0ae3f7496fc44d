//! Bounded recomputation of the bounds after constraints are removed (relaxation).
//!
//! Removing edges can only loosen bounds, and only those of timepoints whose shortest paths all used a
//! removed edge. For the upper bounds these are among the timepoints reachable from the head of a removed
//! edge that was tight (`ub[v] = ub[u] + w`) through tight edges; a timepoint outside that set keeps a
//! shortest path avoiding the removed edges, hence its bound. The affected set is recomputed from its
//! unaffected neighbours by a Dijkstra restricted to it (the old lower bounds stay a feasible potential,
//! having fewer edges). The lower bounds are handled symmetrically, backwards from the tails.

use std::cmp::Reverse;

use super::network::Stn;
use super::propagate::Scratch;
use super::{sat_add, Time, INF};

impl Stn {
    /// Recomputes the bounds that depended on the (already deactivated) constraints `removed`.
    pub(crate) fn relax_removed(&mut self, removed: &[u32]) {
        self.relax_upper_bounds(removed);
        self.relax_lower_bounds(removed);
    }

    /// Puts into `sc.queue` (touched, with their old bound) the timepoints whose upper bound (`UPPER`) or
    /// lower bound may have depended on the removed constraints: for the upper bounds, those reachable
    /// by tight edges (`ub[y] = ub[x] + w(x→y)`) from the heads of the removed edges that were tight; for
    /// the lower bounds, backwards likewise from their tails. The origin (`ub = 0`) and the timepoints whose
    /// lower bound is 0 (held there by `t − origin ≥ 0`) are never affected.
    fn affected<const UPPER: bool>(&self, sc: &mut Scratch, removed: &[u32]) {
        // The edge between x and y (x→y for the upper bounds, y→x for the lower ones) of weight w is
        // tight for y's bound, given x's.
        let tight = |x: u32, y: u32, w: Time| {
            if UPPER {
                let ub_x = self.ub[x as usize];
                w < INF && ub_x < INF && y != 0 && self.ub[y as usize] == sat_add(ub_x, w)
            } else {
                let lb_y = self.lb[y as usize];
                w < INF && lb_y > 0 && lb_y == sat_add(self.lb[x as usize], -w)
            }
        };
        let mark = |sc: &mut Scratch, y: u32| {
            if !sc.touched(y) {
                sc.touch(
                    y,
                    if UPPER {
                        self.ub[y as usize]
                    } else {
                        self.lb[y as usize]
                    },
                );
                sc.queue.push(y);
            }
        };
        for &c in removed {
            for forward in [true, false] {
                let (u, v, w) = self.cons[c as usize].edge(forward);
                let (x, y) = if UPPER { (u, v) } else { (v, u) };
                if tight(x, y, w) {
                    mark(sc, y);
                }
            }
        }
        let mut i = 0;
        while i < sc.queue.len() {
            let x = sc.queue[i];
            i += 1;
            let edges = if UPPER { &self.out } else { &self.inc };
            for &h in &edges[x as usize] {
                let (a, b, w) = self.half_edge(h);
                let y = if UPPER { b } else { a };
                if tight(x, y, w) {
                    mark(sc, y);
                }
            }
        }
    }

    fn relax_upper_bounds(&mut self, removed: &[u32]) {
        let mut sc = std::mem::take(&mut self.scratch);
        sc.begin(self.lb.len());
        self.affected::<true>(&mut sc, removed);
        // Restart each affected timepoint from its unaffected predecessors.
        for i in 0..sc.queue.len() {
            let x = sc.queue[i];
            let mut best = INF;
            for &h in &self.inc[x as usize] {
                let (a, _, w) = self.half_edge(h);
                if w < INF && !sc.touched(a) {
                    best = best.min(sat_add(self.ub[a as usize], w));
                }
            }
            self.set_ub(x, best);
            if best < INF {
                sc.heap.push(Reverse((best - self.lb[x as usize], x)));
            }
        }
        self.settle_upper_bounds(&mut sc, |sc, y| sc.touched(y));
        self.scratch = sc;
    }

    fn relax_lower_bounds(&mut self, removed: &[u32]) {
        let mut sc = std::mem::take(&mut self.scratch);
        sc.begin(self.lb.len());
        self.affected::<false>(&mut sc, removed);
        // Restart each affected timepoint from its unaffected successors (and the origin).
        for i in 0..sc.queue.len() {
            let x = sc.queue[i];
            let mut best: Time = 0;
            for &h in &self.out[x as usize] {
                let (_, b, w) = self.half_edge(h);
                if w < INF && !sc.touched(b) {
                    best = best.max(sat_add(self.lb[b as usize], -w));
                }
            }
            self.set_lb(x, best);
            sc.heap.push(Reverse((sc.old[x as usize] - best, x)));
        }
        // Only the affected set is recomputed; no cycle can appear by removing edges.
        let _ = self.settle_lower_bounds(&mut sc, |sc, _, a, _| Some(sc.touched(a)));
        self.scratch = sc;
    }
}
