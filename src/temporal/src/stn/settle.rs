//! The two Dijkstra searches over reduced costs that both propagation ([`super::propagate`]) and relaxation
//! ([`super::relax`]) end with, once they have queued their starting timepoints. The lower bounds are the
//! potential: they are a feasible potential before and after every change (see `propagate`).

use std::cmp::Reverse;

use super::network::{Half, Stn};
use super::propagate::Scratch;
use super::{sat_add, Time, INF};

impl Stn {
    /// Forward search from the timepoints queued in `sc.heap` (keyed by the reduced distance `ub − lb`)
    /// lowering upper bounds: `ub[y] ≤ ub[x] + w(x→y)`, for the timepoints `y` that `may_lower` accepts.
    pub(crate) fn settle_upper_bounds(
        &mut self,
        sc: &mut Scratch,
        may_lower: impl Fn(&Scratch, u32) -> bool,
    ) {
        while let Some(Reverse((key, x))) = sc.heap.pop() {
            let ub_x = self.ub[x as usize];
            if key != ub_x - self.lb[x as usize] {
                continue; // stale entry
            }
            for i in 0..self.out[x as usize].len() {
                let h = self.out[x as usize][i];
                let (_, y, w) = self.half_edge(h);
                if w >= INF || !may_lower(sc, y) {
                    continue;
                }
                let cand = sat_add(ub_x, w);
                if cand < self.ub[y as usize] {
                    self.set_ub(y, cand);
                    sc.heap.push(Reverse((cand - self.lb[y as usize], y)));
                }
            }
        }
    }

    /// Backward search from the timepoints queued in `sc.heap` (keyed by the change `old − lb`, most
    /// negative first; monotone because the old lower bounds are a feasible potential) raising lower
    /// bounds: `lb[a] ≥ lb[x] − w(a→x)`. Before raising `lb[a]` (currently `lb_a`) through the half `h`,
    /// `admit(sc, h, a, lb_a)` says whether to (`Some(true)`), to leave `a` alone (`Some(false)`), or to stop
    /// (`None`): the raise would close a negative cycle, returned as its closing half and `x`.
    pub(crate) fn settle_lower_bounds(
        &mut self,
        sc: &mut Scratch,
        mut admit: impl FnMut(&mut Scratch, Half, u32, Time) -> Option<bool>,
    ) -> Result<(), (Half, u32)> {
        while let Some(Reverse((key, x))) = sc.heap.pop() {
            let lb_x = self.lb[x as usize];
            if key != sc.old[x as usize] - lb_x {
                continue; // stale entry
            }
            for i in 0..self.inc[x as usize].len() {
                let h = self.inc[x as usize][i];
                let (a, _, w) = self.half_edge(h);
                if w >= INF {
                    continue;
                }
                let cand = sat_add(lb_x, -w);
                let lb_a = self.lb[a as usize];
                if cand <= lb_a {
                    continue;
                }
                match admit(sc, h, a, lb_a) {
                    None => return Err((h, x)),
                    Some(false) => continue,
                    Some(true) => {}
                }
                self.set_lb(a, cand);
                sc.heap.push(Reverse((sc.old[a as usize] - cand, a)));
            }
        }
        Ok(())
    }
}
