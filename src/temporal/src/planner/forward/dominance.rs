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

#[cfg(test)]
mod tests {
    use super::super::search::{Forward, ForwardOutcome};
    use super::super::test_tasks::{line, tank, ENERGY};
    use super::*;

    #[test]
    fn less_energy_with_the_same_atoms_is_dominated_more_is_not() {
        let t = line(3, 0, 50.0);
        let mut d = Dominance::new(&t);
        let s = t.initial_state();
        assert!(!d.dominated(&s), "nothing recorded yet");
        d.record(&s);
        let mut less = s.clone();
        less.nums[ENERGY as usize] = 42.0;
        let mut more = s.clone();
        more.nums[ENERGY as usize] = 58.0;
        let mut elsewhere = less.clone();
        elsewhere.set(0, false);
        elsewhere.set(1, true);
        assert!(d.dominated(&less));
        assert!(d.dominated(&s), "equal is covered");
        assert!(!d.dominated(&more));
        assert!(!d.dominated(&elsewhere), "other atoms: not comparable");
    }

    #[test]
    fn a_variable_read_only_by_an_upper_bound_must_be_equal() {
        // The tank's level is bounded from below by `spill` too: more is better. Take the bound away and
        // it is only read by `seal`'s upper bound: values must then be equal to compare.
        let mut t = tank(5.0, 2.0);
        t.actions[0].start.pre.num.clear();
        let mut d = Dominance::new(&t);
        let s = t.initial_state();
        d.record(&s);
        let mut less = s.clone();
        less.nums[0] = 4.0;
        assert!(!d.dominated(&less));
    }

    #[test]
    fn a_plan_through_dominated_states_is_still_found() {
        // Every state before the goal has the atoms of the first and less in the tank: all deferred,
        // and still expanded once nothing else is left.
        let t = tank(6.0, 2.0);
        let mut f = Forward::new(t.clone());
        let ForwardOutcome::Plan(plan) = f.run(1_000) else {
            panic!("the tank can be drained");
        };
        let names: Vec<&str> = plan
            .iter()
            .map(|&a| t.actions[a as usize].name.as_str())
            .collect();
        assert_eq!(names, ["spill", "spill", "spill", "spill", "seal"]);
        // Below what it holds minus all it can spill: no plan, and the search says so.
        let mut f = Forward::new(tank(3.0, -1.0));
        assert_eq!(f.run(1_000), ForwardOutcome::Exhausted);
    }
}
