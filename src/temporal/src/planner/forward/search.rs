//! Lazy greedy best-first search over the compressed ground problem, guided by h_FF with helpful actions
//! (Fast Downward's lazy search with preferred operators and its "boosted dual queue"), with a third open
//! list ordered by novelty (Lipovetzky & Geffner's best-first width search, [`super::novelty`]). A state is
//! evaluated only when it is taken from an open list, not when it is generated: its successors enter the
//! open lists with *its* h_FF, those reached by one of its helpful actions in a second list as well, and
//! every one in the third list keyed by its novelty among the successors of states of the same h_FF,
//! then by that h_FF. The lists are taken in turn, the helpful one given a run of extra turns each time
//! the best h_FF improves. On wide problems (hundreds of ground actions, tens applicable in a state) this
//! evaluates one state per expansion instead of one per successor.
//!
//! The novelty list is what crosses plateaus: in stacking domains (Depots) h_FF ignores that a hoist
//! holds one crate at a time, the relaxed plan's actions lead back to states already seen, and the h_FF
//! lists dig deep into one corner of the plateau (tens of thousands of states on Depots p5, p6, p9); the
//! successors that make a new atom or pair of atoms true spread the search over the plateau instead
//! (a few thousand states).
//!
//! The order is only guidance, so every successor of every evaluated state still enters the plain list
//! and the search stays complete: duplicate states are detected, dead ends (a goal not even
//! relaxed-reachable) pruned, and [`ForwardOutcome::Exhausted`] is only answered once all the lists are
//! empty. The search is resumable: [`Forward::run`] evaluates at most a given number of states, so it can
//! be interleaved with the POCL searches.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use super::dominance::Dominance;
use super::novelty::Novelty;
use super::relaxed::Relaxed;
use super::{GroundTask, State};

/// Turns given to the helpful open list each time the best h_FF improves.
const BOOST: u32 = 1000;

/// What [`Forward::run`] ended with.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ForwardOutcome {
    /// A sequence of actions (indices into the ground task's actions) reaching the goal.
    Plan(Vec<u32>),
    /// Every reachable state was expanded without reaching the goal: no *sequential* plan exists (a plan
    /// with required concurrency may still exist).
    Exhausted,
    /// The expansion budget of this call ran out; call again to go on.
    Paused,
}

/// An evaluated state and how it was reached.
struct Node {
    state: State,
    parent: u32,
    action: u32,
}

/// Entries `(first key, second key, insertion number, parent node, action)`: the successor is computed
/// and evaluated when the entry is taken. The keys are (h_FF of the parent, 0) in the h_FF lists and
/// (novelty, h_FF of the parent) in the novelty list.
type Open = BinaryHeap<Reverse<(u32, u32, u32, u32, u32)>>;

/// A resumable lazy greedy best-first search.
pub struct Forward {
    task: GroundTask,
    successors: Successors,
    relaxed: Relaxed,
    nodes: Vec<Node>,
    seen: HashMap<State, u32>,
    open: Open,
    helpful: Open,
    novel: Open,
    novelty: Novelty,
    /// Entries whose state is dominated by one evaluated before ([`Dominance`]), taken only when the
    /// other lists are empty, first filed first.
    deferred: std::collections::VecDeque<(u32, u32)>,
    dominance: Dominance,
    counter: u32,
    /// Ties between equal keys broken by a seeded shuffle of the insertion order, not first in first
    /// out ([`super::restarts`]).
    seed: Option<u64>,
    best_h: u32,
    boost: u32,
    /// Which list's turn it is: 0 helpful, 1 plain (helpful while boosted), 2 novelty.
    turn: u8,
    expanded: u64,
    done: Option<ForwardOutcome>,
}

impl Forward {
    pub fn new(task: GroundTask) -> Self {
        Self::seeded(task, None)
    }

    /// A search whose ties are broken by a shuffle seeded by `seed` (`None`: first in, first out).
    pub fn seeded(task: GroundTask, seed: Option<u64>) -> Self {
        let relaxed = Relaxed::new(&task);
        let init = task.initial_state();
        let mut f = Forward {
            relaxed,
            successors: Successors::new(&task),
            nodes: Vec::new(),
            seen: HashMap::new(),
            open: BinaryHeap::new(),
            helpful: BinaryHeap::new(),
            novel: BinaryHeap::new(),
            novelty: Novelty::new(task.atoms.len()),
            deferred: Default::default(),
            dominance: Dominance::new(&task),
            counter: 0,
            seed,
            best_h: u32::MAX,
            boost: 0,
            turn: 0,
            expanded: 0,
            done: None,
            task,
        };
        if f.task.goal.holds(&init) {
            f.done = Some(ForwardOutcome::Plan(Vec::new()));
            return f;
        }
        match f.relaxed.estimate(&init) {
            None => f.done = Some(ForwardOutcome::Exhausted),
            Some(e) => {
                f.best_h = e.h_ff;
                f.seen.insert(init.clone(), 0);
                f.dominance.record(&init);
                f.nodes.push(Node {
                    state: init,
                    parent: u32::MAX,
                    action: u32::MAX,
                });
                f.expand(0, e.h_ff, &e.helpful);
            }
        }
        f
    }

    /// The ground task searched.
    pub fn task(&self) -> &GroundTask {
        &self.task
    }

    /// States evaluated so far.
    pub fn expanded(&self) -> u64 {
        self.expanded
    }

    fn plan_to(&self, mut node: u32) -> Vec<u32> {
        let mut out = Vec::new();
        while let Some(n) = self.nodes.get(node as usize) {
            if n.parent == u32::MAX {
                break;
            }
            out.push(n.action);
            node = n.parent;
        }
        out.reverse();
        out
    }

    /// The next entry, and whether it comes from the deferred list.
    fn pop(&mut self) -> Option<(u32, u32, bool)> {
        let turn = self.turn;
        self.turn = (self.turn + 1) % 3;
        let boosted = self.boost > 0;
        let first = match turn {
            2 => self.novel.pop(),
            0 => self.helpful.pop(),
            _ if boosted => self.helpful.pop(),
            _ => self.open.pop(),
        };
        if turn != 2 && (turn == 0 || boosted) {
            self.boost = self.boost.saturating_sub(1);
        }
        first
            .or_else(|| self.open.pop())
            .or_else(|| self.helpful.pop())
            .or_else(|| self.novel.pop())
            .map(|Reverse((_, _, _, parent, action))| (parent, action, false))
            .or_else(|| self.deferred.pop_front().map(|(p, a)| (p, a, true)))
    }

    /// Files the successors of node `n` (h_FF `h`, helpful actions `helpful`, sorted) in the open lists:
    /// every applicable action not leading to a state already seen, unevaluated (its novelty measured).
    fn expand(&mut self, n: u32, h: u32, helpful: &[u32]) {
        let Some(node) = self.nodes.get(n as usize) else {
            return;
        };
        for i in self.successors.candidates(&node.state) {
            let Some(next) = self.task.actions[i].successor(&node.state) else {
                continue;
            };
            if self.seen.contains_key(&next) {
                continue;
            }
            self.counter += 1;
            let entry = Reverse((h, self.tie(), self.counter, n, i as u32));
            if helpful.binary_search(&(i as u32)).is_ok() {
                self.helpful.push(entry);
            }
            self.open.push(entry);
            let act = &self.task.actions[i];
            let added: Vec<u32> = act.start.add.iter().chain(&act.end.add).copied().collect();
            let w = self.novelty.measure(h, &next, &added);
            self.novel.push(Reverse((w, h, self.counter, n, i as u32)));
        }
    }

    /// The second key of the h_FF lists: 0 (first in, first out), or the insertion number shuffled by
    /// the seed (splitmix64).
    fn tie(&self) -> u32 {
        let Some(seed) = self.seed else {
            return 0;
        };
        let mut z = u64::from(self.counter) ^ seed.wrapping_mul(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z >> 32) as u32
    }

    /// Evaluates at most `max_expansions` states.
    pub fn run(&mut self, max_expansions: u64) -> ForwardOutcome {
        if let Some(d) = &self.done {
            return d.clone();
        }
        let mut budget = max_expansions;
        while budget > 0 {
            let Some((parent, action, was_deferred)) = self.pop() else {
                self.done = Some(ForwardOutcome::Exhausted);
                return ForwardOutcome::Exhausted;
            };
            let Some(next) = self
                .nodes
                .get(parent as usize)
                .and_then(|p| self.task.actions[action as usize].successor(&p.state))
            else {
                continue;
            };
            if self.seen.contains_key(&next) {
                continue; // reached since the entry was filed, or filed in both lists
            }
            if !was_deferred && self.dominance.dominated(&next) {
                self.deferred.push_back((parent, action));
                continue;
            }
            self.dominance.record(&next);
            let id = self.nodes.len() as u32;
            self.seen.insert(next.clone(), id);
            budget -= 1;
            self.expanded += 1;
            let goal = self.task.goal.holds(&next);
            self.nodes.push(Node {
                state: next,
                parent,
                action,
            });
            if goal {
                let out = ForwardOutcome::Plan(self.plan_to(id));
                self.done = Some(out.clone());
                return out;
            }
            let Some(e) = self.relaxed.estimate(&self.nodes[id as usize].state) else {
                continue; // a dead end: its successors are not filed
            };
            if e.h_ff < self.best_h {
                tracing::trace!(
                    h_ff = e.h_ff,
                    expanded = self.expanded,
                    "forward search progress"
                );
                self.best_h = e.h_ff;
                self.boost += BOOST;
            }
            self.expand(id, e.h_ff, &e.helpful);
        }
        ForwardOutcome::Paused
    }
}

/// The actions that may apply in a state, found without testing every action (Fast Downward's
/// successor generator, in its simplest form): each action is filed under one atom that must be true
/// before it, and only the actions filed under true atoms (and those that require none) are tested. That
/// atom is one its start requires or else one its `over all` or `at end` conditions require and its start
/// does not add (checked after the start, which does not add it, it must already hold before): actions
/// with all their conditions `over all`, as Depots' drop and load, are not tested in every state.
struct Successors {
    by_atom: Vec<Vec<usize>>,
    always: Vec<usize>,
}

impl Successors {
    fn new(task: &GroundTask) -> Self {
        let mut by_atom = vec![Vec::new(); task.atoms.len()];
        let mut always = Vec::new();
        for (i, a) in task.actions.iter().enumerate() {
            let later = a.over_all.pos.iter().chain(&a.end.pre.pos);
            let before = a
                .start
                .pre
                .pos
                .first()
                .or_else(|| later.into_iter().find(|x| !a.start.add.contains(x)));
            match before {
                Some(&x) if (x as usize) < by_atom.len() => by_atom[x as usize].push(i),
                _ => always.push(i),
            }
        }
        Successors { by_atom, always }
    }

    /// The candidates in `state`, in action order (the search's tie-breaking does not depend on the
    /// filing).
    fn candidates(&self, state: &State) -> Vec<usize> {
        let mut out = self.always.clone();
        for (x, acts) in self.by_atom.iter().enumerate() {
            if !acts.is_empty() && state.has(x as u32) {
                out.extend(acts);
            }
        }
        out.sort_unstable();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Cond, GroundAction};
    use super::*;

    /// Blocksworld with one arm, `n` blocks, as a ground task (each action one instantaneous start):
    /// atoms on(a, b) = a·n + b, ontable(a), clear(a), holding(a), handempty.
    struct Blocks {
        n: u32,
    }

    impl Blocks {
        fn on(&self, a: u32, b: u32) -> u32 {
            a * self.n + b
        }
        fn ontable(&self, a: u32) -> u32 {
            self.n * self.n + a
        }
        fn clear(&self, a: u32) -> u32 {
            self.n * self.n + self.n + a
        }
        fn holding(&self, a: u32) -> u32 {
            self.n * self.n + 2 * self.n + a
        }
        fn handempty(&self) -> u32 {
            self.n * self.n + 3 * self.n
        }

        fn action(name: &str, pre: Vec<u32>, add: Vec<u32>, del: Vec<u32>) -> GroundAction {
            super::super::test_tasks::action(name, pre, Vec::new(), add, del)
        }

        /// Towers as lists of blocks, bottom first.
        fn atoms_of(&self, towers: &[Vec<u32>]) -> Vec<u32> {
            let mut out = vec![self.handempty()];
            for t in towers {
                out.push(self.ontable(t[0]));
                out.extend(t.windows(2).map(|w| self.on(w[1], w[0])));
                out.push(self.clear(t[t.len() - 1]));
            }
            out
        }

        fn task(&self, init: &[Vec<u32>], goal: &[Vec<u32>]) -> GroundTask {
            let n = self.n;
            let mut actions = Vec::new();
            for a in 0..n {
                let (h, c, t, e) = (
                    self.holding(a),
                    self.clear(a),
                    self.ontable(a),
                    self.handempty(),
                );
                actions.push(Self::action(
                    "pickup",
                    vec![c, t, e],
                    vec![h],
                    vec![c, t, e],
                ));
                actions.push(Self::action("putdown", vec![h], vec![c, t, e], vec![h]));
                for b in (0..n).filter(|&b| b != a) {
                    let (on, cb) = (self.on(a, b), self.clear(b));
                    actions.push(Self::action(
                        "stack",
                        vec![h, cb],
                        vec![on, c, e],
                        vec![h, cb],
                    ));
                    actions.push(Self::action(
                        "unstack",
                        vec![on, c, e],
                        vec![h, cb],
                        vec![on, c, e],
                    ));
                }
            }
            // The goal: every `on` and `ontable` of the goal towers (clear and handempty left free).
            let goal = self
                .atoms_of(goal)
                .into_iter()
                .filter(|&x| x < n * n + n)
                .collect();
            GroundTask {
                atoms: (0..=self.handempty()).map(|i| i.to_string()).collect(),
                init: self.atoms_of(init),
                goal: Cond {
                    pos: goal,
                    ..Cond::default()
                },
                actions,
                ..GroundTask::default()
            }
        }
    }

    /// The novelty list only reorders: with a goal no sequence reaches (a block on itself is never an
    /// atom any action adds), every reachable state is expanded and the answer is Exhausted.
    #[test]
    fn an_unreachable_goal_is_exhausted_not_paused() {
        let b = Blocks { n: 3 };
        let mut task = b.task(&[vec![0, 1, 2]], &[vec![2, 1, 0]]);
        // Reachable in the relaxation (so not pruned as a dead end at once) but not really: holding two
        // blocks at once.
        task.goal.pos = vec![b.holding(0), b.holding(1)];
        let mut f = Forward::new(task);
        assert_eq!(f.run(100_000), ForwardOutcome::Exhausted);
        // The 3-block state space: 22 states (13 arrangements with the arm empty, 9 with a block in
        // hand), each evaluated once but the initial one, which no expansion counts.
        assert_eq!(f.expanded(), 21);
    }
}
