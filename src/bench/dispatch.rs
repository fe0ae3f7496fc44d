//! `mavtempo bench dispatch`: the cost of a goal-driven dispatch decision with each algorithm form
//! (Algorithm 2 at each decision vs the lookup in the marking of Algorithms 3–8), and the cost the marking
//! moves into planning (per plan-change notification).

use std::time::Instant;

use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use crate::dispatch::dispatcher::Dispatcher;
use crate::dispatch::graph::{
    ActionId, Change, Establisher, GoalId, GraphError, Link, LinkId, Node,
};
use crate::dispatch::marking::Marking;
use crate::dispatch::policy::{PolicyKind, StartWindow, SupportForm, Tick};
use crate::model::GoalOrigin;

/// Decisions are timed in batches of this many (one `Instant` read is as long as a marking lookup).
const BATCH: usize = 16;

/// One row of the benchmark.
#[derive(Clone, Debug, Serialize)]
pub struct DispatchFigure {
    pub actions: usize,
    pub links: usize,
    pub goals: usize,
    /// `search` (Algorithm 2) or `marking` (Algorithms 3–8).
    pub form: &'static str,
    pub decisions: usize,
    /// Per decision (policy + goal support), from batches of 16 decisions on random actions.
    pub mean_us: f64,
    pub p50_us: f64,
    pub p99_us: f64,
    /// Share of the decisions that dispatched (the windows open now, so about the share of actions that
    /// support an external goal; the same for both forms).
    pub dispatched_share: f64,
    /// Per plan-change notification during repair-like edits (a causal link removed, then restored by
    /// backtrack or added back; marking form only: the search form reads the plan as it is).
    pub update_mean_us: Option<f64>,
    pub update_p50_us: Option<f64>,
    pub update_p99_us: Option<f64>,
    pub updates: usize,
    /// Building the whole plan through its notifications (actions first, goals last: the worst order for
    /// the marking, each goal link marks its whole upstream at once); marking form only.
    pub build_ms: Option<f64>,
}

/// A plan-like causal structure: the changes that build it, in planning order.
#[derive(Clone, Debug)]
pub struct PlanLikeGraph {
    pub actions: usize,
    pub changes: Vec<Change>,
}

/// `n` actions on `n / 50 + 2` timelines (state attributes): each action's condition is supported by the
/// previous action of its timeline (the first by the initial state), a third also by an action of another
/// timeline; one goal per 10 actions, half of them external, supported by an action of the second half; the
/// last action of each timeline supports nothing (like seed 2's trailing `Go(home, ?)`).
pub fn plan_like(n: usize, seed: u64) -> PlanLikeGraph {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let timelines = n / 50 + 2;
    let mut changes = Vec::new();
    let mut last: Vec<Option<u32>> = vec![None; timelines];
    let mut link = 0u32;
    let mut add_link = |changes: &mut Vec<Change>, from: Establisher, to: Node| {
        changes.push(Change::LinkAdded(LinkId(link), Link { from, to }));
        link += 1;
    };
    for a in 0..n as u32 {
        let t = rng.gen_range(0..timelines);
        changes.push(Change::ActionAdded(ActionId(a)));
        let from = last[t].map_or(Establisher::Initial, |p| Establisher::Action(ActionId(p)));
        add_link(&mut changes, from, Node::Action(ActionId(a)));
        if a > 0 && rng.gen_bool(1.0 / 3.0) {
            let other = rng.gen_range(a.saturating_sub(40)..a);
            add_link(
                &mut changes,
                Establisher::Action(ActionId(other)),
                Node::Action(ActionId(a)),
            );
        }
        last[t] = Some(a);
    }
    let last: Vec<u32> = last.into_iter().flatten().collect();
    let candidates: Vec<u32> = (n as u32 / 2..n as u32)
        .filter(|a| !last.contains(a))
        .collect();
    for g in 0..(n / 10).max(1) as u32 {
        let kind = if g % 2 == 0 {
            GoalOrigin::External
        } else {
            GoalOrigin::Internal
        };
        changes.push(Change::GoalAdded(GoalId(g), kind));
        if let Some(&a) = candidates.choose(&mut rng) {
            add_link(
                &mut changes,
                Establisher::Action(ActionId(a)),
                Node::Goal(GoalId(g)),
            );
        }
    }
    PlanLikeGraph {
        actions: n,
        changes,
    }
}

/// Runs the benchmark on plans of each size, `decisions` decisions per form.
pub fn run(
    sizes: &[usize],
    decisions: usize,
    seed: u64,
) -> Result<Vec<DispatchFigure>, GraphError> {
    let mut out = Vec::new();
    for &n in sizes {
        let plan = plan_like(n, seed ^ n as u64);
        // Build through the notifications, timing each (the planning-time cost of the marking form).
        let mut marking = Marking::new();
        let t0 = Instant::now();
        for c in &plan.changes {
            marking.apply(c)?;
        }
        let build_ms = t0.elapsed().as_secs_f64() * 1e3;
        let mut update_us = Vec::with_capacity(2 * n);
        repair_like_edits(&mut marking, &mut update_us, n, seed)?;
        let links = marking.graph().links().count();
        let goals = marking.graph().goals().count();
        let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(n as u64));
        let queries: Vec<(ActionId, StartWindow, Tick)> = (0..decisions)
            .map(|_| {
                let a = ActionId(rng.gen_range(0..n as u32));
                let lb = rng.gen_range(0..3_600_000);
                let window = StartWindow {
                    lb,
                    ub: lb + rng.gen_range(0..36_000_000),
                };
                (a, window, Tick::new(lb, 1_000))
            })
            .collect();
        for form in [SupportForm::Search, SupportForm::Marking] {
            let mut d = Dispatcher::new(PolicyKind::GoalDriven(form));
            let mut samples = Vec::with_capacity(decisions / BATCH + 1);
            let mut dispatched = 0usize;
            for batch in queries.chunks(BATCH) {
                let t0 = Instant::now();
                for &(a, window, tick) in batch {
                    let decision = d.decide(a, window, tick, marking.graph(), &marking);
                    dispatched += usize::from(std::hint::black_box(decision).is_dispatch());
                }
                samples.push(t0.elapsed().as_secs_f64() * 1e6 / batch.len() as f64);
            }
            let (mean, p50, p99) = stats(&mut samples);
            let marking_form = form == SupportForm::Marking;
            let upd = stats(&mut update_us.clone());
            out.push(DispatchFigure {
                actions: n,
                links,
                goals,
                form: match form {
                    SupportForm::Search => "search",
                    SupportForm::Marking => "marking",
                },
                decisions: queries.len(),
                mean_us: mean,
                p50_us: p50,
                p99_us: p99,
                dispatched_share: dispatched as f64 / queries.len().max(1) as f64,
                update_mean_us: marking_form.then_some(upd.0),
                update_p50_us: marking_form.then_some(upd.1),
                update_p99_us: marking_form.then_some(upd.2),
                updates: if marking_form { update_us.len() } else { 0 },
                build_ms: marking_form.then_some(build_ms),
            });
        }
    }
    Ok(out)
}

/// Plan repair in miniature: remove a random causal link (split), then either backtrack (restore) or
/// re-add it (merge); each notification is timed.
fn repair_like_edits(
    marking: &mut Marking,
    update_us: &mut Vec<f64>,
    n: usize,
    seed: u64,
) -> Result<(), GraphError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_mul(31).wrapping_add(n as u64));
    let mut links: Vec<(LinkId, Link)> = marking.graph().links().collect();
    links.sort_by_key(|(l, _)| *l);
    for _ in 0..n {
        let Some(&(l, link)) = links.choose(&mut rng) else {
            break;
        };
        let level = marking.save();
        let t0 = Instant::now();
        marking.apply(&Change::LinkRemoved(l))?;
        update_us.push(t0.elapsed().as_secs_f64() * 1e6);
        if rng.gen_bool(0.5) {
            marking.restore(level);
        } else {
            let t0 = Instant::now();
            marking.apply(&Change::LinkAdded(l, link))?;
            update_us.push(t0.elapsed().as_secs_f64() * 1e6);
        }
    }
    Ok(())
}

/// (mean, p50, p99) of `v` (sorted in place); zeros when empty.
fn stats(v: &mut [f64]) -> (f64, f64, f64) {
    if v.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    v.sort_by(f64::total_cmp);
    let pick = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    (
        v.iter().sum::<f64>() / v.len() as f64,
        pick(0.5),
        pick(0.99),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dispatch::search::search_for_goal;

    #[test]
    fn plan_like_graphs_have_both_kinds_of_action_and_the_forms_agree() {
        let plan = plan_like(200, 7);
        let mut m = Marking::new();
        for c in &plan.changes {
            m.apply(c).unwrap();
        }
        let marked = (0..200)
            .filter(|&a| m.supports_external_goal(ActionId(a)))
            .count();
        assert!(marked > 10 && marked < 190, "{marked} of 200 marked");
        for a in 0..200 {
            let a = ActionId(a);
            assert_eq!(m.supports_external_goal(a), search_for_goal(m.graph(), a));
        }
    }

    #[test]
    fn run_reports_both_forms_per_size() {
        let figs = run(&[60], 64, 1).unwrap();
        assert_eq!(figs.len(), 2);
        assert_eq!(figs[0].dispatched_share, figs[1].dispatched_share);
        assert!(figs[1].update_mean_us.is_some() && figs[0].update_mean_us.is_none());
        assert!(figs
            .iter()
            .all(|f| f.decisions == 64 && f.p99_us >= f.p50_us));
    }
}
