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

/// Plan repair between cycles: the tree in progress, whether a repair was asked for, and the steps of the
/// episode (bounded by `repair_episode_max_steps`; an episode ends when a tree finishes or is dropped by a
/// new plan).
#[derive(Default)]
pub struct RepairState {
    pub(super) tree: Option<Repair>,
    pub(super) requested: bool,
    pub(super) episode_steps: u64,
}

impl RepairState {
    /// Message integration asks for plan repair in the next cycle.
    pub fn request(&mut self) {
        self.requested = true;
    }

    /// The tree was rooted in a plan that is no more (a goal withdrawn): repair starts again from the plan.
    pub fn restart(&mut self) {
        self.tree = None;
        self.requested = true;
    }

    /// No repair while the operator has the vehicle: the tree and the request are dropped.
    pub fn hold(&mut self) {
        self.tree = None;
        self.requested = false;
    }

    /// A new plan from complete replanning: no tree, no request, a new episode.
    pub fn reset(&mut self) {
        *self = RepairState::default();
    }
}
