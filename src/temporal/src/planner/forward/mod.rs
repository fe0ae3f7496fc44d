//! The hybrid planner's forward half (issue 32): a grounded, sequential problem searched state by state
//! with FF's relaxed-plan heuristic ([`relaxed`], [`search`]), whose plan is deordered ([`deorder`]) and
//! given to the POCL planner as a partial plan to complete ([`embed`]): its conditions linked, its threats
//! ordered, its timepoints scheduled by the STN, and the result checked like any other plan.
//!
//! A durative action is run *compressed*: its start happening, then its `over all` and `at end` conditions
//! checked in the state after the start effects, then its end effects — a sequence of such actions, each
//! after the previous ends, is a valid PDDL 2.1 plan. Problems that need two actions to overlap (required
//! concurrency) have no such sequence: the POCL search, run beside it, finds those.

pub mod deorder;
pub mod embed;
pub mod relaxed;
pub mod search;

pub use embed::{embed, EmbedError};
pub use search::{Forward, ForwardOutcome};

/// A ground atom, numbered.
pub type AtomId = u32;

/// A conjunction of ground literals.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Cond {
    pub pos: Vec<AtomId>,
    pub neg: Vec<AtomId>,
}

impl Cond {
    /// Whether the conjunction holds in `state`.
    pub fn holds(&self, state: &State) -> bool {
        self.pos.iter().all(|&a| state.has(a)) && self.neg.iter().all(|&a| !state.has(a))
    }
}

/// One end of a durative action: what must hold just before it and what it changes (deletions first,
/// then additions, as PDDL applies them).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Happening {
    pub pre: Cond,
    pub add: Vec<AtomId>,
    pub del: Vec<AtomId>,
}

impl Happening {
    fn apply(&self, state: &mut State) {
        for &a in &self.del {
            state.set(a, false);
        }
        for &a in &self.add {
            state.set(a, true);
        }
    }
}

/// A ground durative action: its PDDL name and arguments, its two happenings and its invariant.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GroundAction {
    pub name: String,
    pub args: Vec<String>,
    pub start: Happening,
    pub over_all: Cond,
    pub end: Happening,
}

impl GroundAction {
    /// The state after the action run compressed from `state`, or `None` when it does not apply there.
    pub fn successor(&self, state: &State) -> Option<State> {
        if !self.start.pre.holds(state) {
            return None;
        }
        let mut s = state.clone();
        self.start.apply(&mut s);
        if !self.over_all.holds(&s) || !self.end.pre.holds(&s) {
            return None;
        }
        self.end.apply(&mut s);
        Some(s)
    }

    /// The atoms it reads (conditions of any kind).
    pub fn reads(&self) -> impl Iterator<Item = AtomId> + '_ {
        [&self.start.pre, &self.over_all, &self.end.pre]
            .into_iter()
            .flat_map(|c| c.pos.iter().chain(&c.neg).copied())
    }

    /// The atoms it changes (adds or deletes at either end).
    pub fn writes(&self) -> impl Iterator<Item = AtomId> + '_ {
        [&self.start, &self.end]
            .into_iter()
            .flat_map(|h| h.add.iter().chain(&h.del).copied())
    }
}

/// A ground problem: atoms, the initial state, the goal and the actions.
#[derive(Clone, Debug, Default)]
pub struct GroundTask {
    /// Each atom's text, for messages.
    pub atoms: Vec<String>,
    pub init: Vec<AtomId>,
    pub goal: Cond,
    pub actions: Vec<GroundAction>,
}

impl GroundTask {
    /// The initial state.
    pub fn initial_state(&self) -> State {
        let mut s = State::empty(self.atoms.len());
        for &a in &self.init {
            s.set(a, true);
        }
        s
    }
}

/// A state: the set of true atoms, as a bit set.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct State(Box<[u64]>);

impl State {
    pub fn empty(n_atoms: usize) -> Self {
        State(vec![0; n_atoms.div_ceil(64)].into_boxed_slice())
    }

    pub fn has(&self, a: AtomId) -> bool {
        let i = a as usize;
        self.0.get(i / 64).is_some_and(|w| w >> (i % 64) & 1 == 1)
    }

    pub fn set(&mut self, a: AtomId, on: bool) {
        let i = a as usize;
        if let Some(w) = self.0.get_mut(i / 64) {
            if on {
                *w |= 1 << (i % 64);
            } else {
                *w &= !(1 << (i % 64));
            }
        }
    }
}
