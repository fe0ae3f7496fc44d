//! Seed 2, Algorithms 3–8: the incremental marking `List_goals` — the external goals and every action that
//! supports one through a chain of causal links — maintained from the plan-change notifications while the
//! plan is built and repaired, so that a dispatch decision is a set lookup instead of Algorithm 2's search.
//!
//! POCL reading of the Europa callbacks: a causal link `a → n` is Europa's merge of `n`'s condition token
//! onto `a`'s effect token, and its removal is a split; activation of a token is its action or goal entering
//! the plan, deactivation its leaving.
//!
//! - Alg. 3 NotifyAdded: an external goal is inserted into `List_goals`.
//! - Alg. 4 NotifyRemoved / Alg. 6 NotifyDeactivated: a removed action or goal leaves `List_goals`.
//! - Alg. 5 NotifyActivated / Alg. 7 NotifyMerged: when `n` is in `List_goals` and a link `a → n` appears,
//!   the reverse causal links are searched from `a` and everything reached is inserted. (Alg. 7's two cases —
//!   the goal merged onto an active token, or a token merged onto a marked active token — are both this one
//!   rule once a merge is a link; a new action has no link yet, so Alg. 5 has nothing to do for it.)
//! - Alg. 8 NotifySplit: the paper removes the token "if it is not a goal or not causally linked to a goal",
//!   looking one link ahead. That is wrong in two ways once actions support several goals or chains are
//!   longer than one link: the token may still reach an external goal through another link, and the actions
//!   upstream of it may lose their only path. So a removal (of a link, an action or a goal) first asks
//!   Algorithm 2 whether the establisher still reaches an external goal (then nothing changes); if not, it
//!   recomputes the marks of the marked actions upstream of it (delete and re-derive): those still linked to a marked node
//!   outside that set, and whatever in the set is upstream of them, stay; the others are unmarked. Only
//!   actions upstream of the removed link can have used it, so nothing else needs looking at; this holds
//!   for any graph, cycles included (no reference counting).
//!
//! Retraction on backtrack: either the plan announces the reverse changes (they are ordinary changes here),
//! or [`Marking::save`] / [`Marking::restore`] undo the graph and the marks by trail.

use std::collections::HashSet;

use backtrack::{Level, Trail};

use super::graph::{
    ActionId, CausalGraph, CausalView, Change, Establisher, GoalId, GraphError, Link, Node,
};
use super::search::GoalSearch;
use mavtempo_temporal::model::GoalOrigin;

#[derive(Clone, Debug)]
enum Undo {
    /// Apply this change to the graph (the inverse of what was done).
    Graph(Change),
    /// The node was marked: unmark it.
    Marked(Node),
    /// The node was unmarked: mark it again.
    Unmarked(Node),
}

/// `List_goals` with the causal graph it is computed on.
#[derive(Clone, Debug, Default)]
pub struct Marking {
    graph: CausalGraph,
    marked: HashSet<Node>,
    trail: Trail<Undo>,
    search: GoalSearch,
}

impl Marking {
    pub fn new() -> Self {
        Self::default()
    }

    /// The causal graph as the notifications built it.
    pub fn graph(&self) -> &CausalGraph {
        &self.graph
    }

    /// Whether `a` is in `List_goals`: it supports an external goal (the dispatch-time lookup).
    pub fn supports_external_goal(&self, a: ActionId) -> bool {
        self.marked.contains(&Node::Action(a))
    }

    /// `List_goals`: the external goals and the actions that support them.
    pub fn list_goals(&self) -> impl Iterator<Item = Node> + '_ {
        self.marked.iter().copied()
    }

    /// Drops the undo trail: nothing before this point will be restored (a reader of a change log that
    /// announces backtracks itself, so the trail would only grow).
    pub fn forget_trail(&mut self) {
        self.trail.clear();
    }

    /// The current trail level.
    pub fn save(&mut self) -> Level {
        self.trail.level()
    }

    /// Undoes every change applied after `level` (graph and marks).
    pub fn restore(&mut self, level: Level) {
        let (graph, marked) = (&mut self.graph, &mut self.marked);
        self.trail.restore(level, |undo| match undo {
            Undo::Graph(c) => {
                // The inverse of a change that succeeded cannot fail.
                let undone = graph.apply(&c);
                debug_assert!(undone.is_ok(), "{undone:?}");
            }
            Undo::Marked(n) => {
                marked.remove(&n);
            }
            Undo::Unmarked(n) => {
                marked.insert(n);
            }
        });
    }

    /// Applies one plan change and updates `List_goals`. On `Err` nothing changed.
    pub fn apply(&mut self, c: &Change) -> Result<(), GraphError> {
        match *c {
            Change::ActionAdded(a) => {
                self.graph.apply(c)?;
                self.trail.push(Undo::Graph(Change::ActionRemoved(a)));
            }
            Change::GoalAdded(g, kind) => {
                self.graph.apply(c)?;
                self.trail.push(Undo::Graph(Change::GoalRemoved(g)));
                self.notify_added(g, kind);
            }
            Change::LinkAdded(l, link) => {
                self.graph.apply(c)?;
                self.trail.push(Undo::Graph(Change::LinkRemoved(l)));
                self.notify_merged(link);
            }
            Change::LinkRemoved(l) => {
                let link = self.graph.remove_link(l)?;
                self.trail.push(Undo::Graph(Change::LinkAdded(l, link)));
                self.notify_split(&[link.from]);
            }
            Change::ActionRemoved(a) => {
                if !self.graph.contains_action(a) {
                    return Err(GraphError::UnknownAction(a));
                }
                let upstream = self.detach(Node::Action(a))?;
                self.graph.apply(c)?;
                self.trail.push(Undo::Graph(Change::ActionAdded(a)));
                self.notify_removed(Node::Action(a));
                self.notify_split(&upstream);
            }
            Change::GoalRemoved(g) => {
                let kind = self.graph.goal_kind(g).ok_or(GraphError::UnknownGoal(g))?;
                let upstream = self.detach(Node::Goal(g))?;
                self.graph.apply(c)?;
                self.trail.push(Undo::Graph(Change::GoalAdded(g, kind)));
                self.notify_removed(Node::Goal(g));
                self.notify_split(&upstream);
            }
        }
        Ok(())
    }

    /// Removes the links of `n` one by one (trailed) and returns the establishers of those into it.
    fn detach(&mut self, n: Node) -> Result<Vec<Establisher>, GraphError> {
        let mut upstream = Vec::new();
        for l in self.graph.links_of(n) {
            let link = self.graph.remove_link(l)?;
            self.trail.push(Undo::Graph(Change::LinkAdded(l, link)));
            if link.to == n {
                upstream.push(link.from);
            }
        }
        Ok(upstream)
    }

    /// Algorithm 3.
    fn notify_added(&mut self, g: GoalId, kind: GoalOrigin) {
        if kind == GoalOrigin::External {
            self.mark(Node::Goal(g));
        }
    }

    /// Algorithms 4 and 6: the removed token leaves `List_goals`.
    fn notify_removed(&mut self, n: Node) {
        self.unmark(n);
    }

    /// Algorithms 5 and 7: a link into a marked node marks its establisher and, by the reverse causal
    /// links, everything upstream.
    fn notify_merged(&mut self, link: Link) {
        if let Establisher::Action(a) = link.from {
            if self.marked.contains(&link.to) {
                self.mark_upstream(a);
            }
        }
    }

    /// Algorithm 8 (corrected, see the module doc): delete and re-derive upstream of `from`.
    fn notify_split(&mut self, from: &[Establisher]) {
        // The marked actions upstream of the removal (every action upstream of a marked one is marked).
        // An establisher that still reaches an external goal (Algorithm 2 on the graph as it is now, which
        // usually stops after a few links) keeps its mark, and so does everything upstream of it.
        let mut affected = Vec::new();
        let mut seen = HashSet::new();
        for e in from {
            if let Establisher::Action(a) = *e {
                if self.marked.contains(&Node::Action(a))
                    && !seen.contains(&a)
                    && !self.search.supports_external_goal(&self.graph, a)
                {
                    seen.insert(a);
                    affected.push(a);
                }
            }
        }
        let mut i = 0;
        while i < affected.len() {
            let x = affected[i];
            i += 1;
            let marked = &self.marked;
            self.graph.for_each_establisher(Node::Action(x), &mut |b| {
                if marked.contains(&Node::Action(b)) && seen.insert(b) {
                    affected.push(b);
                }
            });
        }
        // Re-derive within the affected set: those with a link to a node outside it that is still marked
        // (an external goal, or an action whose marking never depended on the removed link) keep their
        // mark, and so does everything in the set upstream of them; the rest lose it.
        let mut keep = HashSet::new();
        let mut stack = Vec::new();
        for &x in &affected {
            let mut still = false;
            let marked = &self.marked;
            self.graph.for_each_supported(x, &mut |n| {
                still |= marked.contains(&n) && !matches!(n, Node::Action(b) if seen.contains(&b));
            });
            if still && keep.insert(x) {
                stack.push(x);
            }
        }
        while let Some(x) = stack.pop() {
            self.graph.for_each_establisher(Node::Action(x), &mut |b| {
                if seen.contains(&b) && keep.insert(b) {
                    stack.push(b);
                }
            });
        }
        for &x in &affected {
            if !keep.contains(&x) {
                self.unmark(Node::Action(x));
            }
        }
    }

    /// Marks `a` and every action upstream of it by reverse causal links.
    fn mark_upstream(&mut self, a: ActionId) {
        if !self.mark(Node::Action(a)) {
            return;
        }
        let mut stack = vec![a];
        while let Some(x) = stack.pop() {
            let mut found = Vec::new();
            let marked = &self.marked;
            self.graph.for_each_establisher(Node::Action(x), &mut |b| {
                if !marked.contains(&Node::Action(b)) {
                    found.push(b);
                }
            });
            for b in found {
                if self.mark(Node::Action(b)) {
                    stack.push(b);
                }
            }
        }
    }

    /// Marks `n`; false if it already was.
    fn mark(&mut self, n: Node) -> bool {
        let new = self.marked.insert(n);
        if new {
            self.trail.push(Undo::Marked(n));
        }
        new
    }

    fn unmark(&mut self, n: Node) {
        if self.marked.remove(&n) {
            self.trail.push(Undo::Unmarked(n));
        }
    }
}

backtrack::impl_backtrack!(Marking, Level);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dispatch::graph::{test_plan, LinkId};

    fn chain() -> Marking {
        // a0 → a1 → a2 → g0 (external), a1 → g1 (external)
        let mut m = Marking::new();
        let links = [
            (0, Node::Action(ActionId(1))),
            (1, Node::Action(ActionId(2))),
            (2, Node::Goal(GoalId(0))),
            (1, Node::Goal(GoalId(1))),
        ];
        for c in test_plan(3, &[GoalOrigin::External, GoalOrigin::External], &links) {
            m.apply(&c).unwrap();
        }
        m
    }

    #[test]
    fn a_link_into_a_marked_node_marks_the_whole_chain_upstream() {
        let m = chain();
        for a in 0..3 {
            assert!(m.supports_external_goal(ActionId(a)), "a{a}");
        }
    }

    /// An action supporting two goals keeps its mark when one goes, and a2, whose only goal went, loses its
    /// mark (the paper's Algorithms 4/6 remove only the goal itself and would leave a2 marked).
    #[test]
    fn removing_one_of_two_goals_keeps_what_still_supports_the_other() {
        let mut m = chain();
        m.apply(&Change::GoalRemoved(GoalId(0))).unwrap();
        assert!(m.supports_external_goal(ActionId(0)));
        assert!(m.supports_external_goal(ActionId(1)));
        assert!(!m.supports_external_goal(ActionId(2)));
        m.apply(&Change::LinkRemoved(LinkId(3))).unwrap();
        assert!(!m.supports_external_goal(ActionId(0)));
        assert!(!m.supports_external_goal(ActionId(1)));
    }

    #[test]
    fn restore_undoes_marks_and_structure() {
        let mut m = chain();
        let level = m.save();
        m.apply(&Change::ActionRemoved(ActionId(1))).unwrap();
        assert!(!m.supports_external_goal(ActionId(0)));
        assert!(m.supports_external_goal(ActionId(2)));
        m.restore(level);
        for a in 0..3 {
            assert!(m.supports_external_goal(ActionId(a)), "a{a}");
        }
        assert_eq!(m.graph().links().count(), 4);
    }
}
