//! Numeric dominance between states, for the search's order: a state with the same true atoms as one
//! already evaluated, no more of any resource and the same value of every other numeric variable that
//! matters, is *dominated* — whatever it can do, the earlier state could do with what it had. On a
//! problem with a consumable resource (a rover's energy) the states that differ only by what was spent
//! wandering are countless, each with the same estimate; the search defers them.
//!
//! The order of the variables' values is a heuristic judgement, not a proof: a resource is a variable
//! some condition bounds from below, and one with an upper bound too (a recharge allowed only under 80)
//! is still counted as "more is better". So a dominated state is deferred, never dropped: the search
//! stays complete. A variable nothing reads (a metric's running total, only ever increased) is ignored.

use std::collections::HashMap;

use super::{GroundTask, State};

/// How a numeric variable's values compare between two states.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Order {
    /// More is at least as good.
    MoreIsBetter,
    /// Only equal values are comparable.
    Equal,
    /// Nothing reads it: its value never changes what applies.
    Ignored,
}

/// The numeric vectors evaluated so far, per set of true atoms.
#[derive(Clone, Debug, Default)]
pub struct Dominance {
    order: Vec<Order>,
    seen: HashMap<Box<[u64]>, Vec<Box<[f64]>>>,
}

impl Dominance {
    pub fn new(task: &GroundTask) -> Self {
        let n = task.nums.len();
        let mut order = vec![Order::Ignored; n];
        let conds = task
            .actions
            .iter()
            .flat_map(|a| [&a.start.pre, &a.over_all, &a.end.pre])
            .chain([&task.goal])
            .flat_map(|c| &c.num);
        let mut lower = vec![false; n];
        let mut read = vec![false; n];
        let mut vars = Vec::new();
        for c in conds {
            if let Some(v) = c.lower_bound() {
                if let Some(l) = lower.get_mut(v as usize) {
                    *l = true;
                }
            }
            c.lhs.vars(&mut vars);
            c.rhs.vars(&mut vars);
        }
        for a in &task.actions {
            for e in a.start.num.iter().chain(&a.end.num) {
                e.expr.vars(&mut vars);
            }
            if let Some(d) = &a.duration {
                d.vars(&mut vars);
            }
        }
        for v in vars {
            if let Some(r) = read.get_mut(v as usize) {
                *r = true;
            }
        }
        for (v, o) in order.iter_mut().enumerate() {
            *o = if lower[v] {
                Order::MoreIsBetter
            } else if read[v] {
                Order::Equal
            } else {
                Order::Ignored
            };
        }
        Dominance {
            order,
            seen: HashMap::new(),
        }
    }

    /// How much of its resources the step from `before` to `after` consumed, each resource as a share of
    /// its level before, in thousandths summed: the search's tie-breaker between states of equal
    /// estimate (what was produced is not counted back: a refuel is no reason to prefer a state).
    pub fn consumed(&self, before: &State, after: &State) -> u32 {
        let mut total = 0.0;
        for (v, o) in self.order.iter().enumerate() {
            if *o != Order::MoreIsBetter {
                continue;
            }
            let (a, b) = (before.nums[v], after.nums[v]);
            if a.is_finite() && b.is_finite() && a > 0.0 && b < a {
                total += (a - b) / a;
            }
        }
        (total * 1000.0).min(f64::from(u32::MAX / 2)) as u32
    }

    /// Whether numeric vector `a` is at least as good as `b` on every variable.
    fn covers(&self, a: &[f64], b: &[f64]) -> bool {
        self.order
            .iter()
            .zip(a.iter().zip(b))
            .all(|(o, (x, y))| match o {
                Order::MoreIsBetter => x >= y || (x.is_nan() && y.is_nan()),
                Order::Equal => x.to_bits() == y.to_bits() || x == y,
                Order::Ignored => true,
            })
    }

    /// Whether `state` is dominated by a state recorded before (never by itself: the search records a
    /// state once, when it evaluates it).
    pub fn dominated(&self, state: &State) -> bool {
        if self.order.is_empty() {
            return false;
        }
        self.seen
            .get(state.atoms())
            .is_some_and(|vs| vs.iter().any(|v| self.covers(v, &state.nums)))
    }

    /// Records an evaluated state.
    pub fn record(&mut self, state: &State) {
        if self.order.is_empty() {
            return;
        }
        self.seen
            .entry(state.atoms().into())
            .or_default()
            .push(state.nums.clone());
    }
}
