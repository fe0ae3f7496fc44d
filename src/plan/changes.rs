//! Plan-change notifications (seed 2 §"Dynamic solution during planning": the POCL equivalents of Europa's
//! add / remove / activate / merge / split callbacks). The plan appends one [`PlanChange`] per structural
//! change, *including* the undoing of changes on backtrack, so a reader that replays the log from any cursor
//! sees the plan's current structure (Algorithms 3–8 maintain their marking from it).

use serde::Serialize;

use super::{ActionId, LinkId};
use crate::model::GoalId;

/// One structural change of the plan.
#[derive(Copy, Clone, Eq, PartialEq, Debug, Serialize)]
pub enum PlanChange {
    ActionAdded(ActionId),
    ActionRemoved(ActionId),
    GoalAdded(GoalId),
    GoalRemoved(GoalId),
    LinkAdded(LinkId),
    LinkRemoved(LinkId),
}

/// A position in the change log.
#[derive(Copy, Clone, Eq, PartialEq, Ord, PartialOrd, Debug, Default)]
pub struct ChangeCursor(pub usize);

/// The append-only log.
#[derive(Clone, Debug, Default)]
pub(crate) struct ChangeLog {
    log: Vec<PlanChange>,
}

impl ChangeLog {
    pub fn push(&mut self, c: PlanChange) {
        self.log.push(c);
    }

    pub fn since(&self, cursor: ChangeCursor) -> &[PlanChange] {
        self.log.get(cursor.0..).unwrap_or(&[])
    }

    pub fn cursor(&self) -> ChangeCursor {
        ChangeCursor(self.log.len())
    }
}
