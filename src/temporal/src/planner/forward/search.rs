//! Greedy best-first search over the compressed ground problem, guided by h_FF with helpful actions
//! (Fast Downward's "boosted dual queue": one open list of every successor, one of those reached by a
//! helpful action, taken in turn, the helpful one given a run of extra turns each time the best h_FF
//! improves). Duplicate states are detected; dead ends (a goal not even relaxed-reachable) are pruned. The
//! search is resumable: [`Forward::run`] expands at most a given number of states, so it can be
//! interleaved with the POCL searches.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

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

struct Node {
    state: State,
    parent: u32,
    action: u32,
    /// The state's helpful actions, kept from its evaluation until it is expanded.
    helpful: Box<[u32]>,
    expanded: bool,
}

type Open = BinaryHeap<Reverse<(u32, u32, u32)>>;

/// A resumable greedy best-first search.
pub struct Forward {
    task: GroundTask,
    successors: Successors,
    relaxed: Relaxed,
    nodes: Vec<Node>,
    seen: HashMap<State, u32>,
    /// Entries `(h_FF, insertion number, node)`.
    open: Open,
    helpful: Open,
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
            counter: 0,
            best_h: u32::MAX,
            boost: 0,
            turn: false,
            expanded: 0,
            done: None,
            task,
        };
        match f.relaxed.estimate(&init) {
            None => f.done = Some(ForwardOutcome::Exhausted),
            Some(e) => {
                f.best_h = e.h_ff;
                f.seen.insert(init.clone(), 0);
                f.nodes.push(Node {
                    state: init,
                    parent: u32::MAX,
                    action: u32::MAX,
                    helpful: e.helpful.into(),
                    expanded: false,
                });
                f.open.push(Reverse((e.h_ff, 0, 0)));
            }
        }
        f
    }

    /// The ground task searched.
    pub fn task(&self) -> &GroundTask {
        &self.task
    }

    /// States expanded so far.
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

    fn pop(&mut self) -> Option<u32> {
        let prefer_helpful = self.boost > 0 || self.turn;
        self.turn = !self.turn;
        let first = if prefer_helpful {
            self.boost = self.boost.saturating_sub(1);
            self.helpful.pop().or_else(|| self.open.pop())
        } else {
            self.open.pop().or_else(|| self.helpful.pop())
        };
        first.map(|Reverse((_, _, n))| n)
    }

    /// Expands at most `max_expansions` states.
    pub fn run(&mut self, max_expansions: u64) -> ForwardOutcome {
        if let Some(d) = &self.done {
            return d.clone();
        }
        if self.task.goal.holds(&self.nodes[0].state) {
            let out = ForwardOutcome::Plan(Vec::new());
            self.done = Some(out.clone());
            return out;
        }
        let mut budget = max_expansions;
        while budget > 0 {
            let Some(n) = self.pop() else {
                self.done = Some(ForwardOutcome::Exhausted);
                return ForwardOutcome::Exhausted;
            };
            let node = &mut self.nodes[n as usize];
            if std::mem::replace(&mut node.expanded, true) {
                continue; // in both open lists: expanded once
            }
            budget -= 1;
            self.expanded += 1;
            let helpful = std::mem::take(&mut node.helpful);
            let state = node.state.clone();
            for i in self.successors.candidates(&state) {
                let Some(next) = self.task.actions[i].successor(&state) else {
                    continue;
                };
                if self.seen.contains_key(&next) {
                    continue;
                }
                let id = self.nodes.len() as u32;
                self.seen.insert(next.clone(), id);
                let Some(e) = self.relaxed.estimate(&next) else {
                    continue;
                };
                let goal = self.task.goal.holds(&next);
                self.nodes.push(Node {
                    state: next,
                    parent: n,
                    action: i as u32,
                    helpful: e.helpful.into(),
                    expanded: false,
                });
                if goal {
                    let out = ForwardOutcome::Plan(self.plan_to(id));
                    self.done = Some(out.clone());
                    return out;
                }
                if e.h_ff < self.best_h {
                    self.best_h = e.h_ff;
                    self.boost += BOOST;
                }
                self.counter += 1;
                let entry = Reverse((e.h_ff, self.counter, id));
                if helpful.binary_search(&(i as u32)).is_ok() {
                    self.helpful.push(entry);
                }
                self.open.push(entry);
            }
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
