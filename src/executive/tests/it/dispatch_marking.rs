//! Seed 2: the incremental marking (Algorithms 3–8) always gives Algorithm 2's answer, on random causal graphs
//! under random edit sequences with backtracking — by the marking's trail or by reverse notifications.

use std::collections::{BTreeMap, BTreeSet};

use mavtempo_executive::dispatch::{
    search_for_goal, ActionId, CausalGraph, Change, Establisher, GoalId, Link, LinkId, MarkLevel,
    Marking, Node,
};
use mavtempo_temporal::model::GoalOrigin;
use proptest::prelude::*;

#[derive(Clone, Debug)]
enum Op {
    AddAction,
    RemoveAction(usize),
    AddGoal(bool),
    RemoveGoal(usize),
    AddLink {
        from: usize,
        initial: bool,
        to: usize,
        to_goal: bool,
    },
    RemoveLink(usize),
    Save,
    /// Backtrack with `Marking::restore`.
    Restore(usize),
    /// Backtrack by announcing the reverse changes, as the plan's change log does.
    Reverse(usize),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        4 => Just(Op::AddAction),
        1 => any::<usize>().prop_map(Op::RemoveAction),
        2 => any::<bool>().prop_map(Op::AddGoal),
        1 => any::<usize>().prop_map(Op::RemoveGoal),
        8 => (any::<usize>(), prop::bool::weighted(0.1), any::<usize>(), prop::bool::weighted(0.3))
            .prop_map(|(from, initial, to, to_goal)| Op::AddLink { from, initial, to, to_goal }),
        2 => any::<usize>().prop_map(Op::RemoveLink),
        1 => Just(Op::Save),
        1 => any::<usize>().prop_map(Op::Restore),
        1 => any::<usize>().prop_map(Op::Reverse),
    ]
}

/// The oracle's own record of the plan structure (no code shared with the marking).
#[derive(Clone, Debug, Default)]
struct Model {
    actions: BTreeSet<u32>,
    goals: BTreeMap<u32, GoalOrigin>,
    links: BTreeMap<u32, Link>,
}

impl Model {
    fn graph(&self) -> CausalGraph {
        let mut g = CausalGraph::new();
        for &a in &self.actions {
            g.apply(&Change::ActionAdded(ActionId(a))).unwrap();
        }
        for (&k, &kind) in &self.goals {
            g.apply(&Change::GoalAdded(GoalId(k), kind)).unwrap();
        }
        for (&l, &link) in &self.links {
            g.apply(&Change::LinkAdded(LinkId(l), link)).unwrap();
        }
        g
    }

    /// The changes removing `n`, as a plan announces them: its links first, then itself.
    fn removal(&self, n: Node) -> Vec<Change> {
        let mut out: Vec<Change> = self
            .links
            .iter()
            .filter(|(_, l)| {
                l.to == n
                    || matches!((l.from, n), (Establisher::Action(a), Node::Action(b)) if a == b)
            })
            .map(|(&l, _)| Change::LinkRemoved(LinkId(l)))
            .collect();
        out.push(match n {
            Node::Action(a) => Change::ActionRemoved(a),
            Node::Goal(g) => Change::GoalRemoved(g),
        });
        out
    }

    /// Applies `c` to the model and returns its inverse.
    fn apply(&mut self, c: Change) -> Change {
        match c {
            Change::ActionAdded(a) => {
                self.actions.insert(a.0);
                Change::ActionRemoved(a)
            }
            Change::ActionRemoved(a) => {
                self.actions.remove(&a.0);
                Change::ActionAdded(a)
            }
            Change::GoalAdded(g, k) => {
                self.goals.insert(g.0, k);
                Change::GoalRemoved(g)
            }
            Change::GoalRemoved(g) => {
                let k = self.goals.remove(&g.0).unwrap();
                Change::GoalAdded(g, k)
            }
            Change::LinkAdded(l, link) => {
                self.links.insert(l.0, link);
                Change::LinkRemoved(l)
            }
            Change::LinkRemoved(l) => {
                let link = self.links.remove(&l.0).unwrap();
                Change::LinkAdded(l, link)
            }
        }
    }
}

fn nth<T: Copy>(set: impl ExactSizeIterator<Item = T>, i: usize) -> Option<T> {
    let len = set.len();
    if len == 0 {
        None
    } else {
        let mut set = set;
        set.nth(i % len)
    }
}

struct Saved {
    level: MarkLevel,
    model: Model,
    log_len: usize,
}

fn check(marking: &Marking, model: &Model) -> Result<(), TestCaseError> {
    let oracle = model.graph();
    for &a in &model.actions {
        let a = ActionId(a);
        prop_assert_eq!(
            marking.supports_external_goal(a),
            search_for_goal(&oracle, a),
            "action {:?}",
            a
        );
    }
    let marked_goals: BTreeSet<u32> = marking
        .list_goals()
        .filter_map(|n| match n {
            Node::Goal(g) => Some(g.0),
            Node::Action(_) => None,
        })
        .collect();
    let external: BTreeSet<u32> = model
        .goals
        .iter()
        .filter(|(_, k)| **k == GoalOrigin::External)
        .map(|(g, _)| *g)
        .collect();
    prop_assert_eq!(marked_goals, external);
    let marked_actions = marking
        .list_goals()
        .filter(|n| matches!(n, Node::Action(a) if model.actions.contains(&a.0)))
        .count();
    prop_assert_eq!(
        marked_actions,
        marking
            .list_goals()
            .filter(|n| matches!(n, Node::Action(_)))
            .count(),
        "a removed action is still marked"
    );
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(192))]

    #[test]
    fn incremental_marking_equals_algorithm_2(ops in prop::collection::vec(op(), 1..80)) {
        let mut marking = Marking::new();
        let mut model = Model::default();
        // Inverses of the changes applied so far, for backtracking by reverse notifications.
        let mut log: Vec<Change> = Vec::new();
        let mut saved: Vec<Saved> = Vec::new();
        let (mut next_action, mut next_goal, mut next_link) = (0u32, 0u32, 0u32);
        for op in ops {
            let changes: Vec<Change> = match op {
                Op::AddAction => {
                    next_action += 1;
                    vec![Change::ActionAdded(ActionId(next_action))]
                }
                Op::RemoveAction(i) => nth(model.actions.iter().copied(), i)
                    .map(|a| model.removal(Node::Action(ActionId(a))))
                    .unwrap_or_default(),
                Op::AddGoal(external) => {
                    next_goal += 1;
                    let kind = if external { GoalOrigin::External } else { GoalOrigin::Internal };
                    vec![Change::GoalAdded(GoalId(next_goal), kind)]
                }
                Op::RemoveGoal(i) => nth(model.goals.keys().copied(), i)
                    .map(|g| model.removal(Node::Goal(GoalId(g))))
                    .unwrap_or_default(),
                Op::AddLink { from, initial, to, to_goal } => {
                    let from = if initial {
                        Some(Establisher::Initial)
                    } else {
                        nth(model.actions.iter().copied(), from).map(|a| Establisher::Action(ActionId(a)))
                    };
                    let to = if to_goal {
                        nth(model.goals.keys().copied(), to).map(|g| Node::Goal(GoalId(g)))
                    } else {
                        nth(model.actions.iter().copied(), to).map(|a| Node::Action(ActionId(a)))
                    };
                    match (from, to) {
                        (Some(from), Some(to)) => {
                            next_link += 1;
                            vec![Change::LinkAdded(LinkId(next_link), Link { from, to })]
                        }
                        _ => vec![],
                    }
                }
                Op::RemoveLink(i) => nth(model.links.keys().copied(), i)
                    .map(|l| vec![Change::LinkRemoved(LinkId(l))])
                    .unwrap_or_default(),
                Op::Save => {
                    saved.push(Saved { level: marking.save(), model: model.clone(), log_len: log.len() });
                    vec![]
                }
                Op::Restore(i) => {
                    if !saved.is_empty() {
                        let i = i % saved.len();
                        saved.truncate(i + 1);
                        let s = &saved[i];
                        marking.restore(s.level);
                        model = s.model.clone();
                        log.truncate(s.log_len);
                    }
                    vec![]
                }
                Op::Reverse(i) => {
                    if saved.is_empty() {
                        vec![]
                    } else {
                        let i = i % saved.len();
                        saved.truncate(i + 1);
                        let undo: Vec<Change> = log.drain(saved[i].log_len..).rev().collect();
                        for c in &undo {
                            model.apply(*c);
                            prop_assert!(marking.apply(c).is_ok(), "{:?}", c);
                        }
                        // The reverse changes bring the structure back to the saved one; later restores to
                        // this save level undo them by trail.
                        prop_assert_eq!(&model.links, &saved[i].model.links);
                        vec![]
                    }
                }
            };
            for c in changes {
                prop_assert!(marking.apply(&c).is_ok(), "{:?}", c);
                log.push(model.apply(c));
            }
            check(&marking, &model)?;
        }
    }
}
