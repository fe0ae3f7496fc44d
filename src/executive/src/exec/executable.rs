//! Definitions 2–5 of seed 1 §3.1: executable timepoint, achievable goal, executable action, executable plan.

use mavtempo_temporal::model::{GoalId, Time};
use mavtempo_temporal::plan::{ActionId, PartialPlan};
use mavtempo_temporal::stn::{Stn, Timepoint};

/// The timepoints that must directly precede `tp` (a constraint stated between them forces `p ≤ tp`),
/// the origin excluded. A synchronisation (`[0, 0]`) orders neither: both are executed together.
pub fn direct_predecessors(stn: &Stn, tp: Timepoint) -> Vec<Timepoint> {
    let origin = stn.origin();
    let mut out: Vec<Timepoint> = stn
        .constraints_of(tp)
        .filter(|(_, k)| !(k.lb == 0 && k.ub == 0))
        .filter_map(|(_, k)| {
            if k.to == tp && k.from != tp && k.lb >= 0 {
                Some(k.from)
            } else if k.from == tp && k.to != tp && k.ub <= 0 {
                Some(k.to)
            } else {
                None
            }
        })
        .filter(|&p| p != origin)
        .collect();
    out.sort();
    out.dedup();
    out
}

/// Definition 2: every direct predecessor is executed (`T^p_lb = T^p_ub`, before t — or earlier in this same
/// cycle, since §3.2 executes precedence-ordered timepoints of one cycle in order) and `t ∈ [T_lb, T_ub]`.
pub fn timepoint_executable(stn: &Stn, tp: Timepoint, t: Time) -> bool {
    !stn.is_executed(tp)
        && stn.lb(tp) <= t
        && t <= stn.ub(tp)
        && direct_predecessors(stn, tp)
            .iter()
            .all(|&p| stn.executed_at(p).is_some_and(|at| at <= t))
}

/// A_t^f: the actions involved in the flaws F_t (footnote 6).
pub fn flawed_actions(plan: &mut PartialPlan) -> Vec<ActionId> {
    let flaws = plan.flaws();
    let mut out: Vec<ActionId> = flaws
        .iter()
        .flat_map(|f| plan.involved_actions(f))
        .collect();
    out.sort();
    out.dedup();
    out
}

/// Definition 3: `st^g` is executable and g is not in F_t (its condition is not open).
pub fn goal_achievable(plan: &PartialPlan, g: GoalId, t: Time) -> bool {
    plan.goals().iter().any(|pg| {
        pg.goal == g
            && pg.active
            && plan.cond(pg.cond).link.is_some()
            && timepoint_executable(plan.temporal_network(), pg.st, t)
    })
}

/// Definition 4: a future action whose start timepoint is executable and which is not in A_t^f.
pub fn action_executable(plan: &PartialPlan, a: ActionId, t: Time, flawed: &[ActionId]) -> bool {
    !flawed.contains(&a) && timepoint_executable(plan.temporal_network(), plan.action(a).start, t)
}

/// Definition 5: the networks are consistent (the plan refuses inconsistent changes, so they always are)
/// and `RA_t ∩ A_t^f = ∅`.
pub fn plan_executable(running: &[ActionId], flawed: &[ActionId]) -> bool {
    running.iter().all(|a| !flawed.contains(a))
}
