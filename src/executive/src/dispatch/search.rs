//! Seed 2, Algorithm 2 (SearchForGoal): a forward search over causal links from an action's effects to an
//! external goal (Φ_ge).
//!
//! The paper's pseudo-code `return`s inside its loops: it answers from the first effect of the first
//! consuming action only (`return False` on an effect that is neither a goal nor a condition, `return
//! SearchForGoal(E)` on the first condition), so an action whose first effect feeds an internal goal and whose
//! second feeds an external one would be deferred. Its text says what is meant — "equivalent to a breadth
//! first search along the planning structure … O(N + E)" — and that is what this is: a breadth-first search
//! over all causal links with a visited set (plans are acyclic, but a visited set keeps shared sub-chains
//! from being explored twice).

use std::collections::{HashSet, VecDeque};

use super::graph::{ActionId, CausalView, Node};
use mavtempo_temporal::model::GoalOrigin;

/// Algorithm 2 with reusable scratch space (one per dispatcher, so a decision allocates nothing once warm).
#[derive(Clone, Debug, Default)]
pub struct GoalSearch {
    visited: HashSet<ActionId>,
    queue: VecDeque<ActionId>,
}

impl GoalSearch {
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether an external goal is reachable from `a` along causal links (`a` supports it).
    pub fn supports_external_goal(&mut self, view: &dyn CausalView, a: ActionId) -> bool {
        self.visited.clear();
        self.queue.clear();
        self.visited.insert(a);
        self.queue.push_back(a);
        while let Some(x) = self.queue.pop_front() {
            let mut found = false;
            let (visited, queue) = (&mut self.visited, &mut self.queue);
            view.for_each_supported(x, &mut |n| match n {
                Node::Goal(g) => found |= view.goal_kind(g) == Some(GoalOrigin::External),
                Node::Action(b) => {
                    if visited.insert(b) {
                        queue.push_back(b);
                    }
                }
            });
            if found {
                return true;
            }
        }
        false
    }
}

/// One-shot Algorithm 2.
pub fn search_for_goal(view: &dyn CausalView, a: ActionId) -> bool {
    GoalSearch::new().supports_external_goal(view, a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dispatch::graph::{test_plan, CausalGraph, GoalId};
    use mavtempo_temporal::model::GoalOrigin;

    fn graph(actions: u32, goals: &[GoalOrigin], links: &[(u32, Node)]) -> CausalGraph {
        let mut g = CausalGraph::new();
        for c in test_plan(actions, goals, links) {
            g.apply(&c).unwrap();
        }
        g
    }

    /// The case the paper's early `return` gets wrong: the first consumer leads to an internal goal only.
    #[test]
    fn every_effect_is_followed_not_only_the_first() {
        let g = graph(
            3,
            &[GoalOrigin::Internal, GoalOrigin::External],
            &[
                (0, Node::Action(ActionId(1))),
                (1, Node::Goal(GoalId(0))),
                (0, Node::Action(ActionId(2))),
                (2, Node::Goal(GoalId(1))),
            ],
        );
        assert!(search_for_goal(&g, ActionId(0)));
        assert!(!search_for_goal(&g, ActionId(1)));
        assert!(search_for_goal(&g, ActionId(2)));
    }

    #[test]
    fn cycles_terminate() {
        let links = [
            (0, Node::Action(ActionId(1))),
            (1, Node::Action(ActionId(0))),
        ];
        let g = graph(2, &[], &links);
        assert!(!search_for_goal(&g, ActionId(0)));
    }
}
