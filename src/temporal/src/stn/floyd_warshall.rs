//! The all-pairs method of IxTeT: Floyd–Warshall over the whole network. Test oracle and bench baseline.

use super::network::Stn;
use super::{norm_lb, norm_ub, Constraint, Time, Timepoint, INF};

/// All-pairs shortest paths of a consistent network (`n × n`, row-major; `INF` = no path).
#[derive(Clone, Debug)]
pub struct Apsp {
    pub n: usize,
    pub d: Vec<Time>,
}

impl Apsp {
    /// Shortest path a→b (maximum possible `b − a`).
    pub fn distance(&self, a: Timepoint, b: Timepoint) -> Time {
        self.d[a.index() * self.n + b.index()]
    }
    /// Earliest time of `t`.
    pub fn lb(&self, t: Timepoint) -> Time {
        -self.distance(t, Timepoint(0))
    }
    /// Latest time of `t`.
    pub fn ub(&self, t: Timepoint) -> Time {
        self.distance(Timepoint(0), t)
    }
}

/// Solves the network's active constraints (and the implicit `t − origin ≥ 0`); `None` if inconsistent
/// (a negative cycle).
pub fn solve(stn: &Stn) -> Option<Apsp> {
    solve_constraints(stn.num_timepoints(), stn.constraints().map(|(_, k)| k))
}

/// Solves `n` timepoints (0 the origin, every other one after it) under `constraints` (bounds normalised
/// as by [`Stn::add_constraint`]); `None` if inconsistent.
pub fn solve_constraints(
    n: usize,
    constraints: impl IntoIterator<Item = Constraint>,
) -> Option<Apsp> {
    let mut d = vec![INF; n * n];
    for i in 0..n {
        d[i * n + i] = 0;
        d[i * n] = d[i * n].min(0);
    }
    for k in constraints {
        let (f, t) = (k.from.index(), k.to.index());
        let (lb, ub) = (norm_lb(k.lb), norm_ub(k.ub));
        if ub < INF {
            d[f * n + t] = d[f * n + t].min(ub);
        }
        if lb > -INF {
            d[t * n + f] = d[t * n + f].min(-lb);
        }
    }
    for k in 0..n {
        let row_k = d[k * n..(k + 1) * n].to_vec();
        for i in 0..n {
            let dik = d[i * n + k];
            if dik >= INF {
                continue;
            }
            for (dij, &dkj) in d[i * n..(i + 1) * n].iter_mut().zip(&row_k) {
                // A missing k→j path stays missing whatever dik is.
                let s = if dkj >= INF { INF } else { dik + dkj };
                *dij = (*dij).min(s);
            }
        }
        if (0..n).any(|i| d[i * n + i] < 0) {
            return None;
        }
    }
    Some(Apsp { n, d })
}
