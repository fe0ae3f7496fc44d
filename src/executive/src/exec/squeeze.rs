//! Contingent durations are not squeezed (seed 1 §5: "the system only detects when non controllable
//! timepoints time out, but contingent durations can be squeezed during propagation"). Executing a start or
//! goal timepoint at `now` fixes it, and propagation may lower the upper bound of the end of an action that
//! is running — or is being launched in the same cycle: a move then has to be stopped short of its
//! destination, or a non-preemptive action times out although it behaves as modelled. Such a timepoint
//! waits (as a dynamic-controllability "wait") while it keeps at least one timestep of flexibility, i.e.
//! until the running action ends or waiting would cost the plan; then it is executed as the paper does.

use crate::model::Time;
use crate::plan::{ActionId, PartialPlan};
use crate::stn::{Timepoint, INF};

/// The action whose end's upper bound would be lowered by executing `tp` at `now`, if one would, with the
/// bound it would get. `actions` are the started actions and those whose start is executed at `now` too
/// (their end's bound counted from `now`); ended ones are skipped.
pub fn squeezed_running_end(
    plan: &PartialPlan,
    actions: &[ActionId],
    tp: Timepoint,
    now: Time,
) -> Option<(ActionId, Time)> {
    let stn = plan.temporal_network();
    let ends: Vec<(ActionId, Timepoint, Time)> = actions
        .iter()
        .map(|&a| (a, plan.action(a).start, plan.action(a).end))
        .filter(|&(a, st, end)| !plan.action(a).removed && st != tp && !stn.is_executed(end))
        .map(|(a, st, end)| {
            let natural = if stn.is_executed(st) {
                stn.ub(end)
            } else {
                stn.ub(end).min(now.saturating_add(stn.distance(st, end)))
            };
            (a, end, natural)
        })
        .collect();
    if ends.is_empty() {
        return None;
    }
    let d = stn.distances_from(tp);
    ends.into_iter().find_map(|(a, end, natural)| {
        let reach = d[end.index()];
        let ub = if reach >= INF { INF } else { now + reach };
        (ub < natural).then_some((a, ub))
    })
}

/// Whether `tp` should wait rather than squeeze one of `actions` (see [`squeezed_running_end`]): it would
/// squeeze one, and waiting one more timestep still leaves `tp` inside its window.
pub fn should_wait(
    plan: &PartialPlan,
    actions: &[ActionId],
    tp: Timepoint,
    now: Time,
    ts: Time,
) -> bool {
    now + ts <= plan.latest(tp) && squeezed_running_end(plan, actions, tp, now).is_some()
}
