//! The trail: every change is recorded so that `restore(level)` can undo everything after `level`.

use super::network::Stn;
use super::{ConstraintId, Level, Time};

#[derive(Clone, Debug)]
pub(crate) enum Entry {
    /// Old lower bound of a timepoint.
    Lb(u32, Time),
    /// Old upper bound of a timepoint.
    Ub(u32, Time),
    AddTimepoint,
    AddConstraint,
    Remove(u32),
    /// Old bounds of a tightened constraint.
    Weights(u32, Time, Time),
    /// Old execution marker of a timepoint.
    Executed(u32, Option<ConstraintId>),
}

impl Stn {
    /// Undoes everything done after `level` (bounds, constraints, timepoints, executions, removals).
    pub fn restore(&mut self, level: Level) {
        let _ = level;
        todo!()
    }
}
