//! The hybrid planner's forward half (issue 32): a grounded, sequential problem searched state by state
//! with FF's relaxed-plan heuristic ([`relaxed`], [`search`]), whose plan is deordered ([`deorder`]) and
//! given to the POCL planner as a partial plan to complete ([`embed`]): its conditions linked, its threats
//! ordered, its timepoints scheduled by the STN, and the result checked like any other plan.
//!
//! A durative action is run *compressed*: its start happening, then its `over all` and `at end` conditions
//! checked in the state after the start effects, then its end effects — a sequence of such actions, each
//! after the previous ends, is a valid PDDL 2.1 plan. Problems that need two actions to overlap (required
//! concurrency) have no such sequence: the POCL search, run beside it, finds those.
//!
//! Numeric fluents are state variables of the state ([`State::nums`]): conditions compare expressions of
//! them, effects increase, decrease, scale or assign them, all evaluated in the state before the
//! happening (`?duration` the action's duration, evaluated in the state at its start).

pub mod deorder;
pub mod dominance;
pub mod embed;
pub mod novelty;
pub mod relaxed;
pub mod restarts;
pub mod search;
pub mod shortfall;

pub use embed::{embed, EmbedError};
pub use restarts::Restarting;
pub use search::{Forward, ForwardOutcome};

use crate::pddl::ast::{arithmetic, Cmp, NumOp};

/// A ground atom, numbered.
pub type AtomId = u32;

/// A ground numeric expression: constants (static functions already read), numeric state variables and
/// the action's `?duration`.
#[derive(Clone, Debug, PartialEq)]
pub enum NumExpr {
    Const(f64),
    Var(u32),
    Duration,
    Neg(Box<NumExpr>),
    /// `+ - * /`.
    Bin(char, Box<NumExpr>, Box<NumExpr>),
}

impl NumExpr {
    /// Its value with the variables `nums` and the duration `duration` (NaN where undefined: every
    /// comparison with it is false, as PDDL makes a condition on an undefined fluent).
    pub fn eval(&self, nums: &[f64], duration: f64) -> f64 {
        match self {
            NumExpr::Const(v) => *v,
            NumExpr::Var(i) => nums.get(*i as usize).copied().unwrap_or(f64::NAN),
            NumExpr::Duration => duration,
            NumExpr::Neg(x) => -x.eval(nums, duration),
            NumExpr::Bin(op, x, y) => {
                arithmetic(*op, x.eval(nums, duration), y.eval(nums, duration))
            }
        }
    }

    /// The variables it reads, into `out`.
    pub fn vars(&self, out: &mut Vec<u32>) {
        match self {
            NumExpr::Var(i) => out.push(*i),
            NumExpr::Const(_) | NumExpr::Duration => {}
            NumExpr::Neg(x) => x.vars(out),
            NumExpr::Bin(_, x, y) => {
                x.vars(out);
                y.vars(out);
            }
        }
    }
}

/// `lhs cmp rhs` on numeric state variables.
#[derive(Clone, Debug, PartialEq)]
pub struct NumCond {
    pub cmp: Cmp,
    pub lhs: NumExpr,
    pub rhs: NumExpr,
}

impl NumCond {
    /// The variable it bounds from below, when it is `v >= e` or `v > e` (or `e <= v`, `e < v`) with
    /// `e` reading no variable.
    pub fn lower_bound(&self) -> Option<u32> {
        let constant = |e: &NumExpr| {
            let mut vars = Vec::new();
            e.vars(&mut vars);
            vars.is_empty()
        };
        match (&self.lhs, &self.rhs, self.cmp) {
            (NumExpr::Var(v), r, Cmp::Ge | Cmp::Gt) if constant(r) => Some(*v),
            (l, NumExpr::Var(v), Cmp::Le | Cmp::Lt) if constant(l) => Some(*v),
            _ => None,
        }
    }
}

/// `(op var expr)`: `increase`, `decrease`, `assign`, `scale-up`, `scale-down`.
#[derive(Clone, Debug, PartialEq)]
pub struct NumEffect {
    pub op: NumOp,
    pub var: u32,
    pub expr: NumExpr,
}

/// A conjunction of ground literals and numeric comparisons.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cond {
    pub pos: Vec<AtomId>,
    pub neg: Vec<AtomId>,
    pub num: Vec<NumCond>,
}

impl Cond {
    /// Whether the conjunction holds in `state`.
    pub fn holds(&self, state: &State) -> bool {
        self.pos.iter().all(|&a| state.has(a))
            && self.neg.iter().all(|&a| !state.has(a))
            && self.num.iter().all(|c| {
                let (x, y) = (
                    c.lhs.eval(&state.nums, f64::NAN),
                    c.rhs.eval(&state.nums, f64::NAN),
                );
                c.cmp.holds(x, y)
            })
    }
}

/// One end of a durative action: what must hold just before it and what it changes (deletions first,
/// then additions, as PDDL applies them; numeric effects all evaluated in the state before it).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Happening {
    pub pre: Cond,
    pub add: Vec<AtomId>,
    pub del: Vec<AtomId>,
    pub num: Vec<NumEffect>,
}

impl Happening {
    fn apply(&self, state: &mut State, duration: f64) {
        for &a in &self.del {
            state.set(a, false);
        }
        for &a in &self.add {
            state.set(a, true);
        }
        if self.num.is_empty() {
            return;
        }
        let values: Vec<f64> = self
            .num
            .iter()
            .map(|e| {
                let old = state.nums.get(e.var as usize).copied().unwrap_or(f64::NAN);
                let v = e.expr.eval(&state.nums, duration);
                match e.op {
                    NumOp::Assign => v,
                    NumOp::Increase => old + v,
                    NumOp::Decrease => old - v,
                    NumOp::ScaleUp => old * v,
                    NumOp::ScaleDown => old / v,
                }
            })
            .collect();
        for (e, v) in self.num.iter().zip(values) {
            if let Some(x) = state.nums.get_mut(e.var as usize) {
                *x = v;
            }
        }
    }
}

/// A ground durative action: its PDDL name and arguments, its two happenings, its invariant and, when an
/// effect reads `?duration`, its duration (`(= ?duration e)`, evaluated in the state at its start).
#[derive(Clone, Debug, PartialEq)]
pub struct GroundAction {
    pub name: String,
    pub args: Vec<String>,
    pub start: Happening,
    pub over_all: Cond,
    pub end: Happening,
    pub duration: Option<NumExpr>,
}

impl GroundAction {
    /// The state after the action run compressed from `state`, or `None` when it does not apply there.
    pub fn successor(&self, state: &State) -> Option<State> {
        if !self.start.pre.holds(state) {
            return None;
        }
        let d = self
            .duration
            .as_ref()
            .map_or(f64::NAN, |e| e.eval(&state.nums, f64::NAN));
        let mut s = state.clone();
        self.start.apply(&mut s, d);
        if !self.over_all.holds(&s) || !self.end.pre.holds(&s) {
            return None;
        }
        self.end.apply(&mut s, d);
        Some(s)
    }

    /// What it reads (conditions of any kind, numeric expressions of its effects and duration): atoms,
    /// and numeric variable `i` as `n_atoms + i`.
    pub fn reads(&self, n_atoms: usize) -> Vec<AtomId> {
        let conds = [&self.start.pre, &self.over_all, &self.end.pre];
        let mut out: Vec<AtomId> = conds
            .iter()
            .flat_map(|c| c.pos.iter().chain(&c.neg).copied())
            .collect();
        let mut vars = Vec::new();
        for c in conds {
            for n in &c.num {
                n.lhs.vars(&mut vars);
                n.rhs.vars(&mut vars);
            }
        }
        for h in [&self.start, &self.end] {
            for e in &h.num {
                e.expr.vars(&mut vars);
            }
        }
        if let Some(d) = &self.duration {
            d.vars(&mut vars);
        }
        out.extend(vars.into_iter().map(|v| n_atoms as AtomId + v));
        out
    }

    /// What it changes (adds or deletes at either end, numeric variables as in [`Self::reads`]).
    pub fn writes(&self, n_atoms: usize) -> Vec<AtomId> {
        [&self.start, &self.end]
            .into_iter()
            .flat_map(|h| {
                h.add
                    .iter()
                    .chain(&h.del)
                    .copied()
                    .chain(h.num.iter().map(|e| n_atoms as AtomId + e.var))
            })
            .collect()
    }
}

/// A ground problem: atoms, numeric state variables, the initial state, the goal and the actions.
#[derive(Clone, Debug, Default)]
pub struct GroundTask {
    /// Each atom's text, for messages.
    pub atoms: Vec<String>,
    pub init: Vec<AtomId>,
    /// Each numeric variable's text.
    pub nums: Vec<String>,
    /// Their initial values (NaN: undefined).
    pub init_nums: Vec<f64>,
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
        s.nums = self.init_nums.clone().into_boxed_slice();
        s
    }
}

/// A state: the set of true atoms, as a bit set, and the values of the numeric variables.
#[derive(Clone, Debug)]
pub struct State {
    bits: Box<[u64]>,
    pub nums: Box<[f64]>,
}

impl PartialEq for State {
    /// Numeric values compared bit for bit (NaN equals NaN: an undefined fluent is one value).
    fn eq(&self, other: &Self) -> bool {
        self.bits == other.bits
            && self.nums.len() == other.nums.len()
            && self
                .nums
                .iter()
                .zip(other.nums.iter())
                .all(|(a, b)| key(*a) == key(*b))
    }
}

impl Eq for State {}

impl std::hash::Hash for State {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        self.bits.hash(h);
        for v in self.nums.iter() {
            key(*v).hash(h);
        }
    }
}

/// A value's bits, `-0.0` as `0.0`.
fn key(v: f64) -> u64 {
    if v == 0.0 {
        0
    } else {
        v.to_bits()
    }
}

impl State {
    pub fn empty(n_atoms: usize) -> Self {
        State {
            bits: vec![0; n_atoms.div_ceil(64)].into_boxed_slice(),
            nums: Box::new([]),
        }
    }

    /// Its true atoms, as bits (states with the same atoms have the same bits).
    pub fn atoms(&self) -> &[u64] {
        &self.bits
    }

    pub fn has(&self, a: AtomId) -> bool {
        let i = a as usize;
        self.bits
            .get(i / 64)
            .is_some_and(|w| w >> (i % 64) & 1 == 1)
    }

    pub fn set(&mut self, a: AtomId, on: bool) {
        let i = a as usize;
        if let Some(w) = self.bits.get_mut(i / 64) {
            if on {
                *w |= 1 << (i % 64);
            } else {
                *w &= !(1 << (i % 64));
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod test_tasks;
