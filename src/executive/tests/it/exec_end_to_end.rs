//! The planner's plan executed by the executive against MockVehicle with the manual clock: seed 2's
//! shopping day (go / buy), from the root plan to both goals achieved.

use crate::support::shopping;

use mavtempo_executive::exec::cycle::CycleOutcome;
use mavtempo_executive::exec::executive::Fate;
use mavtempo_executive::exec::trace::TraceEvent;

#[test]
fn shopping_day_planned_then_executed_achieves_both_goals() {
    let mut ex = shopping::day_executive(shopping::day_config());
    let mut v = shopping::day_vehicle();
    let mut t = 0;
    let out = loop {
        v.advance_to(t as u64);
        let out = ex.cycle(&mut v, t);
        let CycleOutcome::Continue { next, .. } = out else {
            break out;
        };
        if t > 12 * 3_600_000 {
            break out;
        }
        // Wake up as the live executive does: at the next due timepoint, at the latest one timestep later,
        // and right away when a message is coming (the report of a stopped action).
        let stopped = ex.cycles().last().is_some_and(|c| {
            c.events
                .iter()
                .any(|e| matches!(e, TraceEvent::Stop { .. }))
        });
        t = if stopped {
            t + 1
        } else {
            next.map_or(t + 30_000, |n| n.min(t + 30_000))
        };
    };
    assert_eq!(out, CycleOutcome::Finished, "{:?}", ex.goal_fates());
    assert!(ex.goal_fates().iter().all(|f| f.fate == Fate::Achieved));
    assert!(
        shopping::launches(ex.cycles().records()) >= 3,
        "go, buy, go home at least"
    );
}
