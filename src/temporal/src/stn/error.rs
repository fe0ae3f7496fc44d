//! Inconsistency of the network: the negative cycle that proves it.

use super::{ConstraintId, Time, Timepoint};

/// Where an edge of a negative cycle comes from.
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug)]
pub enum EdgeSource {
    /// A constraint already in the network (with its bounds as stored).
    Constraint(ConstraintId),
    /// The constraint being added, executed or tightened by the failing call (with its new bounds).
    New,
    /// The implicit `t − origin ≥ 0` every timepoint carries.
    AfterOrigin,
}

/// One edge `to − from ≤ weight` of a negative cycle.
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug)]
pub struct CycleEdge {
    pub from: Timepoint,
    pub to: Timepoint,
    pub weight: Time,
    pub source: EdgeSource,
}

/// The constraints cannot all hold: `cycle` is a closed chain of edges (each edge's `to` is the next one's
/// `from`, the last one's `to` is the first one's `from`) whose weights sum to a negative number.
#[derive(Clone, Eq, PartialEq, Debug, thiserror::Error)]
#[error("inconsistent temporal constraints: negative cycle of {} edges, total {}", .cycle.len(), self.total())]
pub struct Inconsistent {
    pub cycle: Vec<CycleEdge>,
}

impl Inconsistent {
    /// Sum of the cycle's weights (negative).
    pub fn total(&self) -> Time {
        self.cycle.iter().map(|e| e.weight).sum()
    }

    /// The existing constraints involved (without the new one and the implicit ones), deduplicated.
    pub fn constraints(&self) -> Vec<ConstraintId> {
        let mut out: Vec<ConstraintId> = self
            .cycle
            .iter()
            .filter_map(|e| match e.source {
                EdgeSource::Constraint(c) => Some(c),
                _ => None,
            })
            .collect();
        out.sort();
        out.dedup();
        out
    }
}
