//! Contingent durations are not squeezed (seed 1 §5: "the system only detects when non controllable
//! timepoints time out, but contingent durations can be squeezed during propagation"; the fix it names,
//! dynamic controllability of an STNU, docs/stnu.md). The plan's dispatchable network
//! ([`PartialPlan::dispatch_network`], Morris 2014) gives each controllable timepoint its *waits* `(a, δ)`:
//! not before start(a) + δ unless a's end — decided by the world — has been observed. A start or goal
//! timepoint due now is held while one of its waits is pending, for an action started (or launched in the
//! same cycle); it goes as soon as that end is reported (reactive dispatch). Waiting stops when one more
//! timestep would leave the timepoint no flexibility: it is then executed as the paper does, and a
//! squeezed end is handled by timeout and repair. On a plan that is not DC, the waits of every part the
//! check gets through still apply.

use mavtempo_temporal::model::Time;
use mavtempo_temporal::plan::{ActionId, DcPlan, PartialPlan};
use mavtempo_temporal::stn::Timepoint;

/// A pending wait: `tp` waits for the end of `action` or for `until`, whichever comes first.
#[derive(Copy, Clone, Eq, PartialEq, Debug)]
pub struct PendingWait {
    pub action: ActionId,
    pub until: Time,
}

/// The latest-ending wait of `tp` still pending at `now`: its action started, or is among `launching`
/// (started at `now` in this cycle), its end not observed, and `start + δ` not reached.
pub fn pending_wait(
    plan: &PartialPlan,
    dc: &DcPlan,
    launching: &[ActionId],
    tp: Timepoint,
    now: Time,
) -> Option<PendingWait> {
    dc.waits_on(tp)
        .filter_map(|(a, delay)| {
            let act = plan.action(a);
            if act.removed || plan.is_executed(act.end) {
                return None;
            }
            let start = match plan.temporal_network().executed_at(act.start) {
                Some(s) => s,
                None if launching.contains(&a) => now,
                None => return None,
            };
            let until = start.saturating_add(delay);
            (until > now).then_some(PendingWait { action: a, until })
        })
        .max_by_key(|w| w.until)
}

/// Whether `tp` waits (see [`pending_wait`]): a wait is pending and one more timestep still leaves `tp`
/// inside its window.
pub fn should_wait(
    plan: &PartialPlan,
    dc: &DcPlan,
    launching: &[ActionId],
    tp: Timepoint,
    now: Time,
    ts: Time,
) -> bool {
    now + ts <= plan.latest(tp) && pending_wait(plan, dc, launching, tp, now).is_some()
}
