//! The dispatched set (seed 1 §3.1): the actions started on the vehicle with `START a p_a i_a`, their
//! identifiers `i_a`, the preemptive ones an `END i_a` was sent to, and those to be told END by the next act
//! part (an interruption asked by message integration or a cancellation). They move together, so they are
//! kept here and edited only through these methods.

use std::collections::BTreeMap;

use mavtempo_temporal::plan::ActionId;

#[derive(Debug, Clone)]
pub(crate) struct Dispatched {
    started: BTreeMap<ActionId, u64>,
    by_id: BTreeMap<u64, ActionId>,
    stop_sent: Vec<ActionId>,
    /// Interruptions requested, sent in the act part.
    stop_requested: Vec<ActionId>,
    next_id: u64,
}

impl Default for Dispatched {
    fn default() -> Self {
        Dispatched {
            started: BTreeMap::new(),
            by_id: BTreeMap::new(),
            stop_sent: Vec::new(),
            stop_requested: Vec::new(),
            next_id: 1,
        }
    }
}

impl Dispatched {
    /// A fresh `i_a` for the next START: never given twice in a mission, even to a START the vehicle
    /// refused, so that no late report of one action can be taken for another's.
    pub(crate) fn new_id(&mut self) -> u64 {
        let id = self.next_id;
        self.next_id += 1;
        id
    }

    /// `a` was started as `id`.
    pub(crate) fn started(&mut self, a: ActionId, id: u64) {
        self.started.insert(a, id);
        self.by_id.insert(id, a);
    }

    pub(crate) fn id_of(&self, a: ActionId) -> Option<u64> {
        self.started.get(&a).copied()
    }

    /// The action a report's `i_a` names, if it is one of this plan's.
    pub(crate) fn action_of(&self, id: u64) -> Option<ActionId> {
        self.by_id.get(&id).copied()
    }

    pub(crate) fn is_started(&self, a: ActionId) -> bool {
        self.started.contains_key(&a)
    }

    /// Every action started in this plan (finished ones too), in id order of the plan's actions.
    pub(crate) fn started_actions(&self) -> Vec<ActionId> {
        self.started.keys().copied().collect()
    }

    /// An `END i_a` was sent to `a`.
    pub(crate) fn stop_sent(&mut self, a: ActionId) {
        if !self.stop_sent.contains(&a) {
            self.stop_sent.push(a);
        }
    }

    /// `a` was told END and has not reported yet.
    pub(crate) fn is_stopping(&self, a: ActionId) -> bool {
        self.stop_sent.contains(&a)
    }

    /// The started actions told END that have not reported yet.
    pub(crate) fn stopping(&self) -> impl Iterator<Item = ActionId> + '_ {
        self.stop_sent
            .iter()
            .copied()
            .filter(|a| self.started.contains_key(a))
    }

    /// `a` is to be told END by the next act part (once).
    pub(crate) fn request_stop(&mut self, a: ActionId) {
        if !self.stop_requested.contains(&a) {
            self.stop_requested.push(a);
        }
    }

    /// The interruptions requested since the last act part, in the order asked.
    pub(crate) fn take_stop_requests(&mut self) -> Vec<ActionId> {
        std::mem::take(&mut self.stop_requested)
    }

    /// `a` reported: an END sent to it is answered.
    pub(crate) fn reported(&mut self, a: ActionId) {
        self.stop_sent.retain(|&x| x != a);
    }

    /// A new plan from complete replanning: the old plan's actions and their ids mean nothing in it, so
    /// their reports are ignored from now on; ids are not reused.
    pub(crate) fn forget_plan(&mut self) {
        self.started.clear();
        self.by_id.clear();
        self.stop_sent.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_are_never_reused_and_a_new_plan_forgets_the_old_ones() {
        let mut d = Dispatched::default();
        let a = ActionId(3);
        let refused = d.new_id();
        let id = d.new_id();
        assert_ne!(refused, id);
        d.started(a, id);
        assert_eq!(d.action_of(id), Some(a));
        assert_eq!(d.action_of(refused), None);
        d.stop_sent(a);
        d.stop_sent(a);
        assert_eq!(d.stopping().collect::<Vec<_>>(), vec![a]);
        d.reported(a);
        assert!(!d.is_stopping(a) && d.is_started(a));
        d.stop_sent(a);
        d.forget_plan();
        assert!(!d.is_started(a) && d.action_of(id).is_none() && d.stopping().next().is_none());
        assert!(d.new_id() > id);
    }
}
