//! The repair search tree between cycles (seed 1 §3.2, §3.4) and what one cycle's repair part comes to.
//! Data only: [`super::repair`] develops the tree.

use super::outcome::AbortReason;
use mavtempo_temporal::model::Time;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_temporal::planner::Search;

/// A repair search in progress.
pub struct Repair {
    pub search: Search,
    /// The last labelled (executable) node's plan.
    pub labelled: Option<PartialPlan>,
}

/// The result of one cycle's repair part.
#[derive(Clone, Debug, PartialEq)]
pub enum RepairOutcome {
    /// Nothing to repair.
    Idle,
    /// A flawless plan was found and became *ExecutingPlan*.
    Solved,
    /// The budget ran out; the last labelled node is *ExecutingPlan*.
    InProgress,
    /// Dead end: execution is aborted.
    Failed(AbortReason),
}

/// The repair tree cannot be rooted: timepoints not executed yet cannot all be after now.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("plan not executable at {now_ms} ms: {source}")]
pub struct NotExecutable {
    pub now_ms: Time,
    pub source: mavtempo_temporal::stn::Inconsistent,
}

impl From<NotExecutable> for AbortReason {
    fn from(e: NotExecutable) -> Self {
        AbortReason::NotExecutable {
            now_ms: e.now_ms,
            error: e.source.to_string(),
        }
    }
}
