//! The all-pairs method of IxTeT: Floyd–Warshall over the whole network. Test oracle and bench baseline.

use super::network::Stn;
use super::{Time, Timepoint};

/// All-pairs shortest paths of a network (`n × n`, row-major).
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
    pub fn lb(&self, t: Timepoint) -> Time {
        -self.distance(t, Timepoint(0))
    }
    pub fn ub(&self, t: Timepoint) -> Time {
        self.distance(Timepoint(0), t)
    }
}

/// Solves the network's active constraints (and the implicit `t − origin ≥ 0`); `None` if inconsistent.
pub fn solve(stn: &Stn) -> Option<Apsp> {
    let _ = stn;
    todo!()
}
