//! Incremental propagation of the bounds when a constraint is added or tightened.
//!
//! `ub[x]` is the shortest path origin→x and `lb[x]` is minus the shortest path x→origin. Both bound vectors
//! are feasible potentials (`lb[y] ≤ lb[x] + w` and `ub[y] ≤ ub[x] + w` for every edge x→y of weight w), and
//! `lb` is always finite (every timepoint is after the origin), so it serves as the potential of the
//! reduced-cost Dijkstra searches.
//!
//! A new edge u→v of weight w can only raise lower bounds backwards from u and lower upper bounds forwards
//! from v. The lower bounds are propagated first: any negative cycle goes through the new edge, so it shows
//! up as the propagation coming back to v (or reaching the origin, whose bounds are fixed at 0) — the cycle
//! detection of Cesta & Oddi. Once the lower bounds are consistent they are exact for the new network and
//! serve as potentials for the forward propagation of the upper bounds.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::error::{CycleEdge, EdgeSource, Inconsistent};
use super::network::{Half, Stn};
use super::{sat_add, ConstraintId, Time, Timepoint, INF};

/// Reusable buffers of the searches (kept to avoid allocating on the hot path).
#[derive(Clone, Debug, Default)]
pub(crate) struct Scratch {
    pub heap: BinaryHeap<Reverse<(Time, u32)>>,
    /// `stamp[x] == gen` iff x was touched by the current search.
    pub stamp: Vec<u32>,
    pub gen: u32,
    /// Value of x's bound before the current search.
    pub old: Vec<Time>,
    /// Half that last improved x in the current search.
    pub parent: Vec<Half>,
    pub queue: Vec<u32>,
}

impl Scratch {
    /// Starts a new search over `n` timepoints.
    pub fn begin(&mut self, n: usize) {
        if self.stamp.len() < n {
            self.stamp.resize(n, 0);
            self.old.resize(n, 0);
            self.parent.resize(
                n,
                Half {
                    c: 0,
                    forward: true,
                },
            );
        }
        self.gen = self.gen.wrapping_add(1);
        if self.gen == 0 {
            self.stamp.iter_mut().for_each(|s| *s = 0);
            self.gen = 1;
        }
        self.heap.clear();
        self.queue.clear();
    }

    /// Marks x as touched, remembering `old` the first time; returns whether it was already touched.
    pub fn touch(&mut self, x: u32, old: Time) -> bool {
        let seen = self.stamp[x as usize] == self.gen;
        if !seen {
            self.stamp[x as usize] = self.gen;
            self.old[x as usize] = old;
        }
        seen
    }

    pub fn touched(&self, x: u32) -> bool {
        self.stamp[x as usize] == self.gen
    }
}

impl Stn {
    /// (tail, head, weight) of a half; weight `INF` when the half is no edge or its constraint is removed.
    pub(crate) fn half_edge(&self, h: Half) -> (u32, u32, Time) {
        let d = &self.cons[h.c as usize];
        let (a, b, w) = d.edge(h.forward);
        (a, b, if d.active { w } else { INF })
    }

    pub(crate) fn cycle_edge(&self, h: Half, modified: u32) -> CycleEdge {
        let (a, b, w) = self.cons[h.c as usize].edge(h.forward);
        CycleEdge {
            from: Timepoint(a),
            to: Timepoint(b),
            weight: w,
            source: if h.c == modified {
                EdgeSource::New
            } else {
                EdgeSource::Constraint(ConstraintId(h.c))
            },
        }
    }

    /// Sets constraint `c` (active, bounds satisfied by the current network or wider) to `[lb, ub]` and
    /// propagates, one direction at a time so that each search starts from bounds exact for its network.
    /// On `Err` the caller restores its level.
    pub(crate) fn impose(&mut self, c: u32, lb: Time, ub: Time) -> Result<(), Inconsistent> {
        if ub < self.cons[c as usize].ub {
            self.cons[c as usize].ub = ub;
            self.sync_edges(c);
            self.log_edge(Half { c, forward: true });
            self.propagate_half(Half { c, forward: true })?;
        }
        if lb > self.cons[c as usize].lb {
            self.cons[c as usize].lb = lb;
            self.sync_edges(c);
            self.log_edge(Half { c, forward: false });
            self.propagate_half(Half { c, forward: false })?;
        }
        // Only now that nothing can be rolled back (see `Paths::recorded`).
        self.paths_add_half(Half { c, forward: true });
        self.paths_add_half(Half { c, forward: false });
        Ok(())
    }

    /// The matrix of paths after a new or lowered edge was propagated ([`super::paths`]).
    fn paths_add_half(&mut self, h: Half) {
        let (u, v, w) = self.half_edge(h);
        self.paths_add_edge(u, v, w);
    }

    /// Logs a new or lowered edge for the query memory ([`super::memo`]).
    fn log_edge(&mut self, h: Half) {
        let (u, v, w) = self.half_edge(h);
        if w >= INF {
            return;
        }
        self.log_stamp += 1;
        self.log.push(super::memo::LoggedEdge {
            stamp: self.log_stamp,
            at: self.trail.level(),
            u,
            v,
            w,
        });
    }

    /// Propagates the (new or lowered) edge `new` = u→v.
    fn propagate_half(&mut self, new: Half) -> Result<(), Inconsistent> {
        let (u, v, w) = self.half_edge(new);
        if w >= INF {
            return Ok(());
        }
        self.raise_lower_bounds(new, u, v, w)?;
        self.lower_upper_bounds(u, v, w);
        Ok(())
    }

    /// Backward search from u raising lower bounds ([`Stn::settle_lower_bounds`]).
    fn raise_lower_bounds(
        &mut self,
        new: Half,
        u: u32,
        v: u32,
        w: Time,
    ) -> Result<(), Inconsistent> {
        let cand = sat_add(self.lb[v as usize], -w);
        if cand <= self.lb[u as usize] {
            return Ok(());
        }
        let level = self.trail.level();
        if u == v || u == 0 {
            return Err(self.report_cycle(level, new, None, v));
        }
        let mut sc = std::mem::take(&mut self.scratch);
        sc.begin(self.lb.len());
        sc.touch(u, self.lb[u as usize]);
        sc.parent[u as usize] = new;
        self.set_lb(u, cand);
        sc.heap.push(Reverse((sc.old[u as usize] - cand, u)));
        // Coming back to v, or reaching the origin, closes a negative cycle through the new edge.
        let settled = self.settle_lower_bounds(&mut sc, |sc, h, a, lb_a| {
            if a == v || a == 0 {
                return None;
            }
            sc.touch(a, lb_a);
            sc.parent[a as usize] = h;
            Some(true)
        });
        self.scratch = sc;
        settled.map_err(|closing| self.report_cycle(level, new, Some(closing), v))
    }

    /// Forward search from v lowering upper bounds ([`Stn::settle_upper_bounds`]; the new, exact lower
    /// bounds are the potential). Only called on a consistent network.
    fn lower_upper_bounds(&mut self, u: u32, v: u32, w: Time) {
        let ub_u = self.ub[u as usize];
        if ub_u >= INF || v == 0 {
            return;
        }
        let cand = sat_add(ub_u, w);
        if cand >= self.ub[v as usize] {
            return;
        }
        let mut sc = std::mem::take(&mut self.scratch);
        sc.begin(self.lb.len());
        self.set_ub(v, cand);
        sc.heap.push(Reverse((cand - self.lb[v as usize], v)));
        // The origin's upper bound is fixed at 0.
        self.settle_upper_bounds(&mut sc, |_, y| y != 0);
        self.scratch = sc;
    }

    /// Builds the negative cycle found while propagating `new` = u→v, then undoes the search (to `level`).
    /// `closing` is the half a→x whose relaxation would have raised `lb[a]` for a = v or a = origin; `None`
    /// when the new edge alone closes the cycle (u = v or u = origin).
    fn report_cycle(
        &mut self,
        level: super::Level,
        new: Half,
        closing: Option<(Half, u32)>,
        v: u32,
    ) -> Inconsistent {
        let (u, _, _) = self.half_edge(new);
        let mut cycle = Vec::new();
        let mut tail = u;
        if let Some((h, x)) = closing {
            cycle.push(self.cycle_edge(h, new.c));
            tail = self.cons[h.c as usize].edge(h.forward).0;
            let mut y = x;
            while y != u {
                let p = self.scratch.parent[y as usize];
                cycle.push(self.cycle_edge(p, new.c));
                y = self.cons[p.c as usize].edge(p.forward).1;
            }
        }
        cycle.push(self.cycle_edge(new, new.c));
        self.restore(level);
        if tail == 0 && v != 0 {
            // The cycle goes through the origin: close it with a shortest path v→origin.
            self.path_to_origin(v, new.c, &mut cycle);
        }
        Inconsistent { cycle }
    }

    /// Appends a shortest path x→origin (weight `−lb[x]`) made of edges tight for the lower bounds, ended by
    /// the implicit `t − origin ≥ 0` when it stops at a timepoint whose lower bound is 0.
    fn path_to_origin(&mut self, x: u32, modified: u32, cycle: &mut Vec<CycleEdge>) {
        let mut sc = std::mem::take(&mut self.scratch);
        sc.begin(self.lb.len());
        sc.touch(x, 0);
        sc.queue.push(x);
        let mut end = None;
        let mut i = 0;
        while i < sc.queue.len() {
            let a = sc.queue[i];
            i += 1;
            if a == 0 || self.lb[a as usize] == 0 {
                end = Some(a);
                break;
            }
            for &h in &self.out[a as usize] {
                let (_, b, w) = self.half_edge(h);
                if w < INF
                    && !sc.touched(b)
                    && self.lb[a as usize] == sat_add(self.lb[b as usize], -w)
                {
                    sc.touch(b, 0);
                    sc.parent[b as usize] = h;
                    sc.queue.push(b);
                }
            }
        }
        if let Some(end) = end {
            let mut path = Vec::new();
            let mut b = end;
            while b != x {
                let h = sc.parent[b as usize];
                path.push(self.cycle_edge(h, modified));
                b = self.cons[h.c as usize].edge(h.forward).0;
            }
            cycle.extend(path.into_iter().rev());
            if end != 0 {
                cycle.push(CycleEdge {
                    from: Timepoint(end),
                    to: Timepoint(0),
                    weight: 0,
                    source: EdgeSource::AfterOrigin,
                });
            }
        }
        self.scratch = sc;
    }
}
