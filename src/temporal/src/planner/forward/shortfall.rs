//! The relaxed plan's resource shortfall (Sapa's resource adjustment, Do & Kambhampati 2003): the
//! relaxation of [`super::relaxed`] ignores how much of a numeric resource its actions consume — a
//! condition `energy >= 8` true in the state stays true however many moves the relaxed plan makes. On a
//! problem where the resource runs out (a rover that must recharge in the sun) every state on the way
//! has the same estimate, and the search wanders through states that differ only by their energy.
//!
//! Here a *resource* is a numeric variable some condition bounds from below. The consumption of each
//! resource by the relaxed plan's actions is summed (each effect evaluated in the state); what exceeds
//! the resource's value, less what the plan's own producers of it give, is the shortfall, and the
//! cheapest reachable producer is added as many times as it takes to cover it (its conditions join the
//! relaxed plan, so its helpful actions lead towards it). A producer's yield is evaluated in the state
//! with the resource at 0: a recharge to full, whose duration depends on the energy, yields its whole
//! capacity.

use super::{GroundAction, GroundTask, NumEffect, State};
use crate::pddl::ast::NumOp;

/// A producer added to the relaxed plan, `times` times.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Added {
    pub action: u32,
    pub times: u32,
    /// Whether applying it now is worth it: it would give at least half of what is missing (or of a
    /// full yield, when more is missing). A refuel that only tops up a nearly full tank is not.
    pub worth_now: bool,
}

/// The resources of a ground task and the actions that consume and produce them, precomputed once.
#[derive(Clone, Debug, Default)]
pub struct Shortfall {
    /// Per variable, whether a condition bounds it from below.
    resource: Vec<bool>,
    /// Per variable, the actions with an effect that may raise it.
    producers: Vec<Vec<u32>>,
    /// Per action, its effects on resources.
    effects: Vec<Vec<NumEffect>>,
    /// Per action, its duration (NaN when it has none).
    durations: Vec<Option<super::NumExpr>>,
}

/// The change an effect makes to its variable in `state` (NaN when undefined).
fn change(e: &NumEffect, state: &State, duration: f64) -> f64 {
    let old = state.nums.get(e.var as usize).copied().unwrap_or(f64::NAN);
    let v = e.expr.eval(&state.nums, duration);
    match e.op {
        NumOp::Increase => v,
        NumOp::Decrease => -v,
        NumOp::Assign => v - old,
        NumOp::ScaleUp => old * v - old,
        NumOp::ScaleDown => old / v - old,
    }
}

impl Shortfall {
    pub fn new(task: &GroundTask) -> Self {
        let n = task.nums.len();
        let mut resource = vec![false; n];
        for a in &task.actions {
            for c in [&a.start.pre, &a.over_all, &a.end.pre]
                .into_iter()
                .flat_map(|c| &c.num)
            {
                if let Some(r) = c.lower_bound().and_then(|v| resource.get_mut(v as usize)) {
                    *r = true;
                }
            }
        }
        let mut producers = vec![Vec::new(); n];
        let mut effects = Vec::with_capacity(task.actions.len());
        for (i, a) in task.actions.iter().enumerate() {
            let on_resources: Vec<NumEffect> = num_effects(a)
                .filter(|e| resource.get(e.var as usize).copied().unwrap_or(false))
                .cloned()
                .collect();
            for e in &on_resources {
                let may_raise = !matches!(e.op, NumOp::Decrease)
                    || !matches!(e.expr, super::NumExpr::Const(c) if c >= 0.0);
                if may_raise {
                    if let Some(p) = producers.get_mut(e.var as usize) {
                        if p.last() != Some(&(i as u32)) {
                            p.push(i as u32);
                        }
                    }
                }
            }
            effects.push(on_resources);
        }
        Shortfall {
            resource,
            producers,
            effects,
            durations: task.actions.iter().map(|a| a.duration.clone()).collect(),
        }
    }

    /// Whether the task has a resource at all (when not, [`Self::cover`] has nothing to do).
    pub fn any(&self) -> bool {
        self.resource.iter().any(|&r| r)
    }

    fn duration(&self, act: u32, state: &State) -> f64 {
        self.durations
            .get(act as usize)
            .and_then(|d| d.as_ref())
            .map_or(f64::NAN, |d| d.eval(&state.nums, f64::NAN))
    }

    /// What action `act` does to each resource in `state`, as `(variable, change)`.
    fn changes<'a>(&'a self, act: u32, state: &'a State) -> impl Iterator<Item = (u32, f64)> + 'a {
        let d = self.duration(act, state);
        self.effects
            .get(act as usize)
            .into_iter()
            .flatten()
            .map(move |e| (e.var, change(e, state, d)))
    }

    /// What action `act` gives resource `v` in `state`.
    fn yield_of(&self, act: u32, v: usize, state: &State) -> f64 {
        self.changes(act, state)
            .filter(|&(w, _)| w as usize == v)
            .map(|(_, c)| c)
            .sum()
    }

    /// The producers to add to relaxed plan `plan` in `state` to cover its shortfall of each resource;
    /// `cost(act)` is a producer's relaxed cost (`None`: unreachable), the cheapest reachable one with a
    /// positive yield is taken.
    pub fn cover(
        &self,
        plan: &[u32],
        state: &State,
        cost: impl Fn(u32) -> Option<u32>,
    ) -> Vec<Added> {
        let mut balance: Vec<f64> = state.nums.to_vec();
        for &act in plan {
            for (v, c) in self.changes(act, state) {
                if let Some(b) = balance.get_mut(v as usize) {
                    *b += c;
                }
            }
        }
        let mut out = Vec::new();
        for (v, &b) in balance.iter().enumerate() {
            // NaN (an undefined level) is no shortfall.
            if !self.resource[v] || b.is_nan() || b >= 0.0 {
                continue;
            }
            // A producer's yield where the resource is spent: what a recharge to full gives is then
            // its whole capacity, not the little that tops up the state's level.
            let mut spent = state.clone();
            spent.nums[v] = 0.0;
            let best = self.producers[v]
                .iter()
                .filter_map(|&p| {
                    let gives = self.yield_of(p, v, &spent);
                    let c = cost(p)?;
                    (gives > 0.0 && gives.is_finite()).then_some((c, p, gives))
                })
                .min_by(|x, y| x.0.cmp(&y.0).then(x.1.cmp(&y.1)));
            if let Some((_, action, gives)) = best {
                let times = (-b / gives).ceil().min(f64::from(u16::MAX)) as u32;
                let now = self.yield_of(action, v, state);
                let worth_now = now >= 0.5 * gives.min(-b);
                out.push(Added {
                    action,
                    times,
                    worth_now,
                });
            }
        }
        out
    }
}

fn num_effects(a: &GroundAction) -> impl Iterator<Item = &NumEffect> {
    a.start.num.iter().chain(&a.end.num)
}

#[cfg(test)]
mod tests {
    use super::super::relaxed::Relaxed;
    use super::super::test_tasks::{line, ENERGY};
    use super::*;

    fn names(t: &GroundTask, acts: &[u32]) -> Vec<String> {
        acts.iter()
            .map(|&a| t.actions[a as usize].name.clone())
            .collect()
    }

    #[test]
    fn energy_is_a_resource_and_the_recharge_its_producer() {
        let t = line(4, 0, 50.0);
        let s = Shortfall::new(&t);
        assert!(s.any());
        let recharge = t.actions.len() as u32 - 1;
        assert_eq!(s.producers[ENERGY as usize], vec![recharge]);
    }

    #[test]
    fn a_relaxed_plan_that_spends_more_than_the_rover_has_counts_a_recharge() {
        // Three moves (24) from waypoint 0, the sun there: with 50 nothing is short; with 10 one
        // recharge (a whole fill of 80) covers the 14 missing, and applying it now is worth it.
        let t = line(4, 0, 50.0);
        let mut r = Relaxed::new(&t);
        let plenty = r.estimate(&t.initial_state()).expect("reachable");
        assert_eq!(plenty.h_ff, 3);
        assert_eq!(names(&t, &plenty.helpful), vec!["move-0-1"]);
        let mut low = t.initial_state();
        low.nums[ENERGY as usize] = 10.0;
        let short = r.estimate(&low).expect("reachable");
        assert_eq!(short.h_ff, 4, "three moves and a recharge");
        assert!(names(&t, &short.helpful).contains(&"recharge-0".to_string()));
    }

    #[test]
    fn a_recharge_that_would_only_top_up_is_counted_but_not_helpful() {
        // 78 of 80 and nine moves (72) to go from waypoint 0: nothing short. With a tenth waypoint
        // farther (9 moves = 72 plus 8): still enough. Make it 11 moves (88): 10 short, and a recharge
        // now gives 2, under half of the 10: counted, not helpful.
        let t = line(12, 0, 78.0);
        let mut r = Relaxed::new(&t);
        let e = r.estimate(&t.initial_state()).expect("reachable");
        assert_eq!(e.h_ff, 12, "eleven moves and one recharge");
        assert_eq!(names(&t, &e.helpful), vec!["move-0-1"]);
        // Far from full, the same recharge is worth it.
        let mut low = t.initial_state();
        low.nums[ENERGY as usize] = 20.0;
        let e = r.estimate(&low).expect("reachable");
        assert!(names(&t, &e.helpful).contains(&"recharge-0".to_string()));
    }

    #[test]
    fn without_a_reachable_producer_nothing_is_added() {
        // The sun at the far end: the recharge needs the moves it would pay for. The cover still
        // names it (its conditions are relaxed-reachable), and the estimate stays finite.
        let t = line(4, 3, 10.0);
        let mut r = Relaxed::new(&t);
        let e = r.estimate(&t.initial_state());
        assert!(e.is_some());
        let s = Shortfall::new(&t);
        assert!(s.cover(&[], &t.initial_state(), |_| None).is_empty());
    }
}
