//! The dispatcher's view of a plan's causal structure: actions, goals and the causal links between them
//! (seed 2's tokens and causal links, Definition 4), and the plan-change notifications that keep a mirror of
//! it up to date (the POCL equivalents of Europa's activate / merge / split / deactivate callbacks).
//!
//! The plan implements [`CausalView`] with a thin adapter, or feeds [`Change`]s into a [`CausalGraph`]
//! (the owned mirror the incremental marking keeps, see [`super::marking`]).

use std::collections::HashMap;

use serde::Serialize;
use thiserror::Error;

use mavtempo_temporal::model::GoalOrigin;

// The graph's nodes are the plan's own ids: an action, a goal (Φ_g = Φ_ge ∪ Φ_gi) and a causal link of the
// plan are named as the plan names them, never by a second key of the same number.
pub use mavtempo_temporal::model::GoalId;
pub use mavtempo_temporal::plan::{ActionId, LinkId};

/// What a causal link supports: a condition of an action, or a goal.
#[derive(Copy, Clone, Eq, PartialEq, Ord, PartialOrd, Hash, Debug, Serialize)]
pub enum Node {
    Action(ActionId),
    Goal(GoalId),
}

/// What establishes a causal link: an effect of an action, or the initial state / a predicted timed fact
/// (never dispatched, so never marked).
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug, Serialize)]
pub enum Establisher {
    Initial,
    Action(ActionId),
}

/// A causal link `from → to`: an effect of `from` supports a condition of `to` (or the goal `to`).
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug, Serialize)]
pub struct Link {
    pub from: Establisher,
    pub to: Node,
}

/// One structural change of the plan. Backtracking is either announced by the reverse changes (as the
/// plan's change log does) or done with [`super::Marking::save`] / [`super::Marking::restore`].
#[derive(Copy, Clone, Eq, PartialEq, Debug, Serialize)]
pub enum Change {
    ActionAdded(ActionId),
    /// Also removes the links still attached to the action (Europa's deactivate splits merged tokens).
    ActionRemoved(ActionId),
    GoalAdded(GoalId, GoalOrigin),
    /// Also removes the links still supporting the goal.
    GoalRemoved(GoalId),
    LinkAdded(LinkId, Link),
    LinkRemoved(LinkId),
}

/// A change that does not fit the structure it is applied to (a bug of whoever sends it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum GraphError {
    #[error("action {0:?} is already in the plan")]
    DuplicateAction(ActionId),
    #[error("action {0:?} is not in the plan")]
    UnknownAction(ActionId),
    #[error("goal {0:?} is already in the plan")]
    DuplicateGoal(GoalId),
    #[error("goal {0:?} is not in the plan")]
    UnknownGoal(GoalId),
    #[error("causal link {0:?} is already in the plan")]
    DuplicateLink(LinkId),
    #[error("causal link {0:?} is not in the plan")]
    UnknownLink(LinkId),
    #[error("causal link {0:?} goes from a goal or to the initial state")]
    MalformedLink(LinkId),
}

/// Read access to a plan's causal structure, all that Algorithms 2 and 5–8 need.
pub trait CausalView {
    /// Calls `f` with every node a causal link from an effect of `a` supports (forward causal links).
    fn for_each_supported(&self, a: ActionId, f: &mut dyn FnMut(Node));
    /// Calls `f` with every action whose effect supports a condition of `n` (reverse causal links; the
    /// initial state is left out).
    fn for_each_establisher(&self, n: Node, f: &mut dyn FnMut(ActionId));
    /// The kind of goal `g`, `None` if it is not in the plan.
    fn goal_kind(&self, g: GoalId) -> Option<GoalOrigin>;
}

#[derive(Clone, Debug, Default)]
struct Adjacent {
    /// Links from this node's effects (empty for goals).
    out: Vec<LinkId>,
    /// Links into this node's conditions.
    inc: Vec<LinkId>,
}

/// An owned causal graph, kept up to date from [`Change`]s.
#[derive(Clone, Debug, Default)]
pub struct CausalGraph {
    actions: HashMap<ActionId, Adjacent>,
    goals: HashMap<GoalId, (GoalOrigin, Adjacent)>,
    links: HashMap<LinkId, Link>,
}

impl CausalGraph {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn contains_action(&self, a: ActionId) -> bool {
        self.actions.contains_key(&a)
    }

    pub fn actions(&self) -> impl Iterator<Item = ActionId> + '_ {
        self.actions.keys().copied()
    }

    pub fn goals(&self) -> impl Iterator<Item = (GoalId, GoalOrigin)> + '_ {
        self.goals.iter().map(|(g, (k, _))| (*g, *k))
    }

    pub fn links(&self) -> impl Iterator<Item = (LinkId, Link)> + '_ {
        self.links.iter().map(|(l, k)| (*l, *k))
    }

    pub fn link(&self, l: LinkId) -> Option<Link> {
        self.links.get(&l).copied()
    }

    pub fn num_actions(&self) -> usize {
        self.actions.len()
    }

    /// The links attached to `n` (into it, and out of it for an action), each once.
    pub fn links_of(&self, n: Node) -> Vec<LinkId> {
        let adj = match n {
            Node::Action(a) => self.actions.get(&a),
            Node::Goal(g) => self.goals.get(&g).map(|(_, adj)| adj),
        };
        let mut links: Vec<LinkId> = adj
            .map(|adj| adj.inc.iter().chain(&adj.out).copied().collect())
            .unwrap_or_default();
        // A link from an action's effect to its own condition is both in and out.
        links.sort_unstable();
        links.dedup();
        links
    }

    /// Applies one change; on `Err` nothing changed. Removing an action or a goal removes its links first.
    pub fn apply(&mut self, c: &Change) -> Result<(), GraphError> {
        match *c {
            Change::ActionAdded(a) => {
                if self.actions.contains_key(&a) {
                    return Err(GraphError::DuplicateAction(a));
                }
                self.actions.insert(a, Adjacent::default());
            }
            Change::ActionRemoved(a) => self.remove_node(Node::Action(a))?,
            Change::GoalAdded(g, kind) => {
                if self.goals.contains_key(&g) {
                    return Err(GraphError::DuplicateGoal(g));
                }
                self.goals.insert(g, (kind, Adjacent::default()));
            }
            Change::GoalRemoved(g) => self.remove_node(Node::Goal(g))?,
            Change::LinkAdded(l, link) => self.add_link(l, link)?,
            Change::LinkRemoved(l) => {
                self.remove_link(l)?;
            }
        }
        Ok(())
    }

    /// Removes an action or a goal, its links first; an unknown node is refused before anything changes.
    fn remove_node(&mut self, n: Node) -> Result<(), GraphError> {
        self.adjacent_mut(n)?;
        for l in self.links_of(n) {
            self.remove_link(l)?;
        }
        match n {
            Node::Action(a) => drop(self.actions.remove(&a)),
            Node::Goal(g) => drop(self.goals.remove(&g)),
        }
        Ok(())
    }

    fn add_link(&mut self, l: LinkId, link: Link) -> Result<(), GraphError> {
        if self.links.contains_key(&l) {
            return Err(GraphError::DuplicateLink(l));
        }
        if let Establisher::Action(a) = link.from {
            if !self.actions.contains_key(&a) {
                return Err(GraphError::UnknownAction(a));
            }
        }
        self.adjacent_mut(link.to)?.inc.push(l);
        if let Establisher::Action(a) = link.from {
            if let Some(adj) = self.actions.get_mut(&a) {
                adj.out.push(l);
            }
        }
        self.links.insert(l, link);
        Ok(())
    }

    /// Removes link `l` and returns it.
    pub(crate) fn remove_link(&mut self, l: LinkId) -> Result<Link, GraphError> {
        let link = self.links.remove(&l).ok_or(GraphError::UnknownLink(l))?;
        if let Ok(adj) = self.adjacent_mut(link.to) {
            adj.inc.retain(|x| *x != l);
        }
        if let Establisher::Action(a) = link.from {
            if let Some(adj) = self.actions.get_mut(&a) {
                adj.out.retain(|x| *x != l);
            }
        }
        Ok(link)
    }

    fn adjacent_mut(&mut self, n: Node) -> Result<&mut Adjacent, GraphError> {
        match n {
            Node::Action(a) => self.actions.get_mut(&a).ok_or(GraphError::UnknownAction(a)),
            Node::Goal(g) => self
                .goals
                .get_mut(&g)
                .map(|(_, adj)| adj)
                .ok_or(GraphError::UnknownGoal(g)),
        }
    }
}

impl CausalView for CausalGraph {
    fn for_each_supported(&self, a: ActionId, f: &mut dyn FnMut(Node)) {
        if let Some(adj) = self.actions.get(&a) {
            for l in &adj.out {
                if let Some(link) = self.links.get(l) {
                    f(link.to);
                }
            }
        }
    }

    fn for_each_establisher(&self, n: Node, f: &mut dyn FnMut(ActionId)) {
        let adj = match n {
            Node::Action(a) => self.actions.get(&a),
            Node::Goal(g) => self.goals.get(&g).map(|(_, adj)| adj),
        };
        for l in adj.into_iter().flat_map(|adj| &adj.inc) {
            if let Some(Link {
                from: Establisher::Action(a),
                ..
            }) = self.links.get(l)
            {
                f(*a);
            }
        }
    }

    fn goal_kind(&self, g: GoalId) -> Option<GoalOrigin> {
        self.goals.get(&g).map(|(k, _)| *k)
    }
}

/// The changes that build a test plan: actions `0..actions`, goal `i` of kind `goals[i]`, then link `k`
/// from action `links[k].0` to `links[k].1`.
#[cfg(test)]
pub(crate) fn test_plan(actions: u32, goals: &[GoalOrigin], links: &[(u32, Node)]) -> Vec<Change> {
    let actions = (0..actions).map(|a| Change::ActionAdded(ActionId(a)));
    let goals = (0..)
        .zip(goals)
        .map(|(g, &kind)| Change::GoalAdded(GoalId(g), kind));
    let links = (0..).zip(links).map(|(k, &(from, to))| {
        let from = Establisher::Action(ActionId(from));
        Change::LinkAdded(LinkId(k), Link { from, to })
    });
    actions.chain(goals).chain(links).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_changes_are_errors_and_change_nothing() {
        let mut g = CausalGraph::new();
        let a = ActionId(1);
        g.apply(&Change::ActionAdded(a)).unwrap();
        assert_eq!(
            g.apply(&Change::ActionAdded(a)),
            Err(GraphError::DuplicateAction(a))
        );
        let to_missing_goal = Link {
            from: Establisher::Action(a),
            to: Node::Goal(GoalId(9)),
        };
        assert_eq!(
            g.apply(&Change::LinkAdded(LinkId(0), to_missing_goal)),
            Err(GraphError::UnknownGoal(GoalId(9)))
        );
        assert_eq!(g.links().count(), 0);
        assert!(g.links_of(Node::Action(a)).is_empty());
        assert_eq!(
            g.apply(&Change::LinkRemoved(LinkId(0))),
            Err(GraphError::UnknownLink(LinkId(0)))
        );
        assert_eq!(
            g.apply(&Change::GoalRemoved(GoalId(0))),
            Err(GraphError::UnknownGoal(GoalId(0)))
        );
    }

    #[test]
    fn removing_an_action_removes_its_links() {
        let mut g = CausalGraph::new();
        let (a, b) = (ActionId(0), ActionId(1));
        g.apply(&Change::ActionAdded(a)).unwrap();
        g.apply(&Change::ActionAdded(b)).unwrap();
        let ab = Link {
            from: Establisher::Action(a),
            to: Node::Action(b),
        };
        g.apply(&Change::LinkAdded(LinkId(0), ab)).unwrap();
        let init = Link {
            from: Establisher::Initial,
            to: Node::Action(a),
        };
        g.apply(&Change::LinkAdded(LinkId(1), init)).unwrap();
        g.apply(&Change::ActionRemoved(a)).unwrap();
        assert_eq!(g.links().count(), 0);
        let mut est = Vec::new();
        g.for_each_establisher(Node::Action(b), &mut |x| est.push(x));
        assert!(est.is_empty());
    }

    /// An action's effect supporting its own condition (go's `AT = +oo` hold): removed once.
    #[test]
    fn removing_an_action_with_a_link_to_itself() {
        let mut g = CausalGraph::new();
        let a = ActionId(0);
        g.apply(&Change::ActionAdded(a)).unwrap();
        let own = Link {
            from: Establisher::Action(a),
            to: Node::Action(a),
        };
        g.apply(&Change::LinkAdded(LinkId(0), own)).unwrap();
        assert_eq!(g.links_of(Node::Action(a)), vec![LinkId(0)]);
        assert_eq!(g.apply(&Change::ActionRemoved(a)), Ok(()));
        let mut m = crate::dispatch::Marking::new();
        m.apply(&Change::ActionAdded(a)).unwrap();
        m.apply(&Change::LinkAdded(LinkId(0), own)).unwrap();
        assert_eq!(m.apply(&Change::ActionRemoved(a)), Ok(()));
    }
}
