//! Incremental propagation of the bounds when a constraint is added or tightened.

use super::error::Inconsistent;
use super::network::Stn;

/// Reusable buffers of the propagations (kept to avoid allocating on the hot path).
#[derive(Clone, Debug, Default)]
pub(crate) struct Scratch {}

impl Stn {
    /// Propagates both directions of constraint `c` (just added or tightened).
    pub(crate) fn propagate_constraint(&mut self, c: u32) -> Result<(), Inconsistent> {
        let _ = c;
        todo!()
    }
}
