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
use super::{sat_add, Time, INF};

impl Stn {
    /// Recomputes the bounds that depended on the (already deactivated) constraints `removed`.
    pub(crate) fn relax_removed(&mut self, removed: &[u32]) {
        self.relax_upper_bounds(removed);
        self.relax_lower_bounds(removed);
    }

    fn relax_upper_bounds(&mut self, removed: &[u32]) {
        let mut sc = std::mem::take(&mut self.scratch);
        sc.begin(self.lb.len());
        // Affected set: tight-reachable from the heads of tight removed edges (origin excluded: ub = 0).
        for &c in removed {
            for forward in [true, false] {
                let (u, v, w) = self.cons[c as usize].edge(forward);
                let ub_u = self.ub[u as usize];
                if w < INF
                    && ub_u < INF
                    && v != 0
                    && self.ub[v as usize] == sat_add(ub_u, w)
                    && !sc.touched(v)
                {
                    sc.touch(v, self.ub[v as usize]);
                    sc.queue.push(v);
                }
            }
        }
        let mut i = 0;
        while i < sc.queue.len() {
            let x = sc.queue[i];
            i += 1;
            let ub_x = self.ub[x as usize];
            for &h in &self.out[x as usize] {
                let (_, y, w) = self.half_edge(h);
                if w < INF && y != 0 && !sc.touched(y) && self.ub[y as usize] == sat_add(ub_x, w) {
                    sc.touch(y, self.ub[y as usize]);
                    sc.queue.push(y);
                }
            }
        }
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
        // Affected set: backwards tight-reachable from the tails of tight removed edges. A timepoint whose
        // lower bound is 0 is held there by `t − origin ≥ 0` and is never affected.
        for &c in removed {
            for forward in [true, false] {
                let (u, v, w) = self.cons[c as usize].edge(forward);
                let lb_u = self.lb[u as usize];
                if w < INF && lb_u > 0 && lb_u == sat_add(self.lb[v as usize], -w) && !sc.touched(u)
                {
                    sc.touch(u, lb_u);
                    sc.queue.push(u);
                }
            }
        }
        let mut i = 0;
        while i < sc.queue.len() {
            let x = sc.queue[i];
            i += 1;
            let lb_x = self.lb[x as usize];
            for &h in &self.inc[x as usize] {
                let (a, _, w) = self.half_edge(h);
                let lb_a = self.lb[a as usize];
                if w < INF && lb_a > 0 && !sc.touched(a) && lb_a == sat_add(lb_x, -w) {
                    sc.touch(a, lb_a);
                    sc.queue.push(a);
                }
            }
        }
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
