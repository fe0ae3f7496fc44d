//! A goal withdrawn while the plan runs (the operator cancels it): the goal leaves the plan with the actions
//! not started yet that served only it, and their causal links. Not in the papers, whose goals leave a plan
//! only by complete replanning (seed 1 §3.6); the plan is then repaired as after any other edit (§3.4).

use std::collections::BTreeSet;

use super::{ActionId, EventId, Owner, PartialPlan};
use crate::model::GoalId;

impl PartialPlan {
    /// The live actions that serve goal `g` only: each of their active causal links supports `g` or another
    /// such action (a fixpoint backwards from the goal's condition), and they have at least one.
    pub fn actions_serving_only(&self, g: GoalId) -> Vec<ActionId> {
        let mut only: BTreeSet<ActionId> = BTreeSet::new();
        loop {
            let before = only.len();
            for a in self.live_actions().collect::<Vec<_>>() {
                if only.contains(&a) {
                    continue;
                }
                let mut served = self
                    .links
                    .iter()
                    .filter(|l| l.active && self.event(l.event).owner == Owner::Action(a))
                    .map(|l| self.cond(l.cond).owner)
                    .peekable();
                if served.peek().is_none() {
                    continue;
                }
                let all_ours = served.all(|o| match o {
                    Owner::Goal(h) => h == g,
                    Owner::Action(b) => only.contains(&b),
                    _ => false,
                });
                if all_ours {
                    only.insert(a);
                }
            }
            if only.len() == before {
                return only.into_iter().collect();
            }
        }
    }

    /// Withdraws goal `g` and the actions `actions` (not started: their events never happen), with every
    /// causal link from or to them; the flaw caches are recomputed.
    pub fn withdraw_goal(&mut self, g: GoalId, actions: &[ActionId]) {
        let owned = |o: Owner| match o {
            Owner::Action(a) => actions.contains(&a),
            Owner::Goal(h) => h == g,
            _ => false,
        };
        let links: Vec<_> = (0..self.links.len())
            .map(|i| super::LinkId(i as u32))
            .filter(|&l| {
                let link = self.link(l);
                link.active
                    && (owned(self.event(link.event).owner) || owned(self.cond(link.cond).owner))
            })
            .collect();
        for l in links {
            self.remove_link(l);
        }
        for &a in actions {
            self.remove_action(a);
        }
        self.remove_goal(g);
        self.recompute_candidates();
    }

    /// Whether event `e` happens or may still happen: not an event of a removed action that was never
    /// executed (a withdrawn action's effects neither support nor threaten anything).
    pub fn event_in_effect(&self, e: EventId) -> bool {
        let ev = self.event(e);
        match ev.owner {
            Owner::Action(a) => !self.action(a).removed || self.is_executed(ev.at),
            _ => true,
        }
    }
}
