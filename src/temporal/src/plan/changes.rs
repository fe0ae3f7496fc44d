//! Plan-change notifications (seed 2 §"Dynamic solution during planning": the POCL equivalents of Europa's
//! add / remove / activate / merge / split callbacks). The plan appends one [`PlanChange`] per structural
//! change, *including* the undoing of changes on backtrack, so a reader that replays the log from any cursor
//! sees the plan's current structure (Algorithms 3–8 maintain their marking from it). A link change carries
//! its establisher and consumer: link ids are reused after a backtrack, so a reader replaying the log later
//! cannot look them up in the plan.

use std::sync::atomic::{AtomicU64, Ordering};

use serde::Serialize;

use super::{ActionId, LinkId, Owner, PartialPlan};
use crate::model::GoalId;

/// A causal link with what it connects: the owner of the establishing event (an action, the initial state
/// or a predicted timed fact) and the owner of the supported condition (an action or a goal).
#[derive(Copy, Clone, Eq, PartialEq, Debug, Serialize)]
pub struct LinkEnds {
    pub link: LinkId,
    pub establisher: Owner,
    pub consumer: Owner,
}

/// One structural change of the plan.
#[derive(Copy, Clone, Eq, PartialEq, Debug, Serialize)]
pub enum PlanChange {
    ActionAdded(ActionId),
    ActionRemoved(ActionId),
    GoalAdded(GoalId),
    GoalRemoved(GoalId),
    LinkAdded(LinkEnds),
    LinkRemoved(LinkEnds),
}

/// A position in the change log.
#[derive(Copy, Clone, Eq, PartialEq, Ord, PartialOrd, Debug, Default)]
pub struct ChangeCursor(pub usize);

/// The append-only log. Each log has an identity; a cloned plan's log gets a new one and remembers the
/// logs it descends from and their lengths at the fork (their common prefix), so a reader holding a cursor
/// into an ancestor (the executive's plan before a repair replaced it) knows whether it can go on from there.
#[derive(Debug)]
pub(crate) struct ChangeLog {
    log: Vec<PlanChange>,
    id: u64,
    /// `(ancestor log id, its length when forked)`, oldest first, at most [`MAX_ANCESTRY`].
    ancestry: Vec<(u64, usize)>,
}

const MAX_ANCESTRY: usize = 32;

fn fresh_log_id() -> u64 {
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

impl Default for ChangeLog {
    fn default() -> Self {
        ChangeLog {
            log: Vec::new(),
            id: fresh_log_id(),
            ancestry: Vec::new(),
        }
    }
}

impl Clone for ChangeLog {
    fn clone(&self) -> Self {
        let skip = (self.ancestry.len() + 1).saturating_sub(MAX_ANCESTRY);
        let mut ancestry: Vec<(u64, usize)> = self.ancestry[skip..].to_vec();
        ancestry.push((self.id, self.log.len()));
        ChangeLog {
            log: self.log.clone(),
            id: fresh_log_id(),
            ancestry,
        }
    }
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

    pub fn id(&self) -> u64 {
        self.id
    }

    /// The changes after `cursor` of log `log`, if this log is `log` or shares its first `cursor` changes.
    pub fn continuing(&self, log: u64, cursor: ChangeCursor) -> Option<&[PlanChange]> {
        let shared = log == self.id
            || self
                .ancestry
                .iter()
                .any(|&(id, len)| id == log && cursor.0 <= len);
        shared.then(|| self.since(cursor))
    }
}

impl PartialPlan {
    /// Link `l` with its ends, as the change log records it.
    pub(crate) fn link_ends(&self, l: LinkId) -> LinkEnds {
        let link = &self.links[l.index()];
        LinkEnds {
            link: l,
            establisher: self.events[link.event.index()].owner,
            consumer: self.conds[link.cond.index()].owner,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_clone_continues_its_ancestors_cursors_up_to_the_fork_only() {
        let mut a = ChangeLog::default();
        a.push(PlanChange::ActionAdded(ActionId(0)));
        let early = a.cursor();
        a.push(PlanChange::ActionAdded(ActionId(1)));
        let mut b = a.clone();
        let mut c = b.clone();
        assert_ne!(a.id(), b.id());
        a.push(PlanChange::ActionRemoved(ActionId(1)));
        let late = a.cursor();
        b.push(PlanChange::ActionAdded(ActionId(2)));
        c.push(PlanChange::ActionAdded(ActionId(3)));
        assert_eq!(
            c.continuing(a.id(), early),
            Some(
                &[
                    PlanChange::ActionAdded(ActionId(1)),
                    PlanChange::ActionAdded(ActionId(3))
                ][..]
            )
        );
        // `a` went on after the fork: its reader's state is not a prefix of `b` or `c`.
        assert_eq!(b.continuing(a.id(), late), None);
        assert_eq!(c.continuing(a.id(), late), None);
        assert_eq!(a.continuing(b.id(), early), None);
        assert_eq!(a.continuing(a.id(), late), Some(&[][..]));
    }
}
