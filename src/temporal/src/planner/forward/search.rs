//! Lazy greedy best-first search over the compressed ground problem, guided by h_FF with helpful actions
//! (Fast Downward's lazy search with preferred operators and its "boosted dual queue"). A state is
//! evaluated only when it is taken from an open list, not when it is generated: its successors enter the
//! open lists with *its* h_FF, those reached by one of its helpful actions in a second list as well. The
//! two lists are taken in turn, the helpful one given a run of extra turns each time the best h_FF
//! improves. On wide problems (hundreds of ground actions, tens applicable in a state) this evaluates one
//! state per expansion instead of one per successor; the order is only guidance, so every successor of
//! every evaluated state still enters the plain list and the search stays complete: duplicate states are
//! detected, dead ends (a goal not even relaxed-reachable) pruned, and [`ForwardOutcome::Exhausted`] is
//! only answered once the lists are empty. The search is resumable: [`Forward::run`] evaluates at most a
//! given number of states, so it can be interleaved with the POCL searches.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use super::dominance::Dominance;
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
    /// The resources its path consumed ([`Dominance::consumed`], summed along it).
    consumed: u32,
    parent: u32,
    action: u32,
}

/// Entries `(h_FF of the parent, insertion number, parent node, action)`: the successor is computed and
/// evaluated when the entry is taken.
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
    /// Entries whose state is dominated by one evaluated before ([`Dominance`]), taken only when both
    /// lists are empty, first filed first.
    deferred: std::collections::VecDeque<(u32, u32)>,
    dominance: Dominance,
    counter: u32,
    best_h: u32,
    boost: u32,
    turn: bool,
    expanded: u64,
    done: Option<ForwardOutcome>,
}

impl Forward {
    pub fn new(task: GroundTask) -> Self {
        let relaxed = Relaxed::new(&task);
        let init = task.initial_state();
        let mut f = Forward {
            relaxed,
            successors: Successors::new(&task),
            nodes: Vec::new(),
            seen: HashMap::new(),
            open: BinaryHeap::new(),
            helpful: BinaryHeap::new(),
            deferred: Default::default(),
            dominance: Dominance::new(&task),
            counter: 0,
            best_h: u32::MAX,
            boost: 0,
            turn: false,
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
                    consumed: 0,
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
        let prefer_helpful = self.boost > 0 || self.turn;
        self.turn = !self.turn;
        let first = if prefer_helpful {
            self.boost = self.boost.saturating_sub(1);
            self.helpful.pop().or_else(|| self.open.pop())
        } else {
            self.open.pop().or_else(|| self.helpful.pop())
        };
        first
            .map(|Reverse((_, _, _, parent, action))| (parent, action, false))
            .or_else(|| self.deferred.pop_front().map(|(p, a)| (p, a, true)))
    }

    /// Files the successors of node `n` (h_FF `h`, helpful actions `helpful`, sorted) in the open lists:
    /// every applicable action not leading to a state already seen, unevaluated.
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
            let consumed = node
                .consumed
                .saturating_add(self.dominance.consumed(&node.state, &next));
            let entry = Reverse((h, consumed, self.counter, n, i as u32));
            if helpful.binary_search(&(i as u32)).is_ok() {
                self.helpful.push(entry);
            }
            self.open.push(entry);
        }
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
            if !was_deferred && std::env::var("NO_DOM").is_err() && self.dominance.dominated(&next) {
                self.deferred.push_back((parent, action));
                continue;
            }
            self.dominance.record(&next);
            let id = self.nodes.len() as u32;
            self.seen.insert(next.clone(), id);
            budget -= 1;
            self.expanded += 1;
            let goal = self.task.goal.holds(&next);
            let consumed = self.nodes.get(parent as usize).map_or(0, |p| {
                p.consumed
                    .saturating_add(self.dominance.consumed(&p.state, &next))
            });
            self.nodes.push(Node {
                state: next,
                consumed,
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
                tracing::trace!(h_ff = e.h_ff, expanded = self.expanded, "forward search progress");
                if std::env::var("FWD_DUMP").is_ok() {
                    let st = &self.nodes[id as usize].state;
                    let atoms: Vec<&str> = (0..self.task.atoms.len()).filter(|&a| st.has(a as u32)).map(|a| self.task.atoms[a].as_str()).collect();
                    let plan: Vec<String> = self.plan_to(id).iter().map(|&a| format!("{} {:?}", self.task.actions[a as usize].name, self.task.actions[a as usize].args)).collect();
                    eprintln!("STATE {:?}\nNUMS {:?} {:?}\nPLAN {:?}\nHELP {:?}", atoms, self.task.nums, st.nums, plan, e.helpful.iter().map(|&a| format!("{} {:?}", self.task.actions[a as usize].name, self.task.actions[a as usize].args)).collect::<Vec<_>>());
                }
                self.best_h = e.h_ff;
                self.boost += BOOST;
            }
            self.expand(id, e.h_ff, &e.helpful);
        }
        ForwardOutcome::Paused
    }
}

/// The actions that may apply in a state, found without testing every action (Fast Downward's
/// successor generator, in its simplest form): each action is filed under one atom its start requires,
/// and only the actions filed under true atoms (and those that require none) are tested.
struct Successors {
    by_atom: Vec<Vec<usize>>,
    always: Vec<usize>,
}

impl Successors {
    fn new(task: &GroundTask) -> Self {
        let mut by_atom = vec![Vec::new(); task.atoms.len()];
        let mut always = Vec::new();
        for (i, a) in task.actions.iter().enumerate() {
            match a.start.pre.pos.first() {
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
