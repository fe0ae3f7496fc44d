//! Scenario tests of the STN as the executive and the planner use it (the random ones are in
//! `src/temporal/tests/it/stn_props.rs`).

use super::*;

/// An action `[st, et]` with a duration interval, after `prev`.
fn action(stn: &mut Stn, prev: Timepoint, dmin: Time, dmax: Time) -> (Timepoint, Timepoint) {
    let (st, et) = (stn.add_timepoint(), stn.add_timepoint());
    stn.add_constraint(st, et, dmin, dmax).unwrap();
    stn.add_precedence(prev, st).unwrap();
    (st, et)
}

/// A new STN with its origin and a first action `[st, et]` after it.
fn with_action(dmin: Time, dmax: Time) -> (Stn, Timepoint, Timepoint, Timepoint) {
    let mut stn = Stn::new();
    let o = stn.origin();
    let (st, et) = action(&mut stn, o, dmin, dmax);
    (stn, o, st, et)
}

#[test]
fn bounds_follow_a_chain_and_a_deadline() {
    let (mut stn, o, st1, et1) = with_action(10, 20);
    let (st2, et2) = action(&mut stn, et1, 5, 5);
    assert_eq!((stn.lb(st1), stn.ub(st1)), (1, INF));
    assert_eq!((stn.lb(et2), stn.ub(et2)), (1 + 10 + 1 + 5, INF));
    stn.add_constraint(o, et2, 0, 100).unwrap();
    assert_eq!(stn.ub(et2), 100);
    assert_eq!(stn.ub(st2), 95);
    assert_eq!(stn.ub(et1), 94);
    assert_eq!(stn.ub(st1), 84);
    assert!(stn.necessarily_before(st1, et2));
    assert!(!stn.possibly_before(et2, st1));
    assert_eq!(stn.delay_bounds(st1, et2), (10 + 1 + 5, 99));
}

#[test]
fn negative_cycle_is_reported_with_its_constraints_and_nothing_changes() {
    let (mut stn, o, st1, et1) = with_action(10, 20);
    let deadline = stn.add_constraint(o, et1, 0, 15).unwrap();
    let before: Vec<_> = stn.timepoints().map(|t| (stn.lb(t), stn.ub(t))).collect();
    // st1 no earlier than 10 contradicts duration ≥ 10 and deadline 15.
    let err = stn.add_constraint(o, st1, 10, INF).unwrap_err();
    assert!(err.total() < 0);
    let duration = stn
        .constraints_of(et1)
        .find(|(_, k)| k.from == st1)
        .unwrap()
        .0;
    assert_eq!(err.constraints(), vec![duration, deadline]);
    assert!(err.cycle.iter().any(|e| e.source == EdgeSource::New));
    let after: Vec<_> = stn.timepoints().map(|t| (stn.lb(t), stn.ub(t))).collect();
    assert_eq!(before, after);
    assert_eq!(stn.constraints().count(), 3);
}

#[test]
fn save_and_restore_undo_everything_after_the_level() {
    let (mut stn, o, _, et1) = with_action(10, 20);
    let level = stn.save();
    let bounds = (stn.lb(et1), stn.ub(et1));
    let (st2, _) = action(&mut stn, et1, 3, 4);
    stn.add_constraint(o, st2, 0, 30).unwrap();
    stn.execute(et1, 12).unwrap();
    assert_eq!(stn.ub(et1), 12);
    stn.restore(level);
    assert_eq!(stn.num_timepoints(), 3);
    assert_eq!((stn.lb(et1), stn.ub(et1)), bounds);
    assert!(!stn.is_executed(et1));
    assert_eq!(stn.constraints().count(), 2);
}

#[test]
fn executing_fixes_the_timepoint_and_due_lists_the_others() {
    let (mut stn, o, st1, et1) = with_action(10, 20);
    let (st2, et2) = action(&mut stn, o, 5, 5);
    assert_eq!(stn.due(0).count(), 0);
    assert_eq!(stn.due(1).collect::<Vec<_>>(), vec![st1, st2]);
    stn.execute(st1, 3).unwrap();
    assert_eq!(stn.executed_at(st1), Some(3));
    assert_eq!((stn.lb(et1), stn.ub(et1)), (13, 23));
    assert_eq!(stn.due(13).collect::<Vec<_>>(), vec![et1, st2, et2]);
    assert_eq!(stn.due(12).collect::<Vec<_>>(), vec![st2, et2]);
    // Too late for a bound: rejected, nothing executed.
    assert!(stn.execute(et1, 24).is_err());
    assert!(!stn.is_executed(et1));
    assert!(stn.is_executed(o));
}

/// §3.3 of the IxTeT-eXeC paper: a report comes too early for a failed action's end timepoint; a new end
/// timepoint is set to the current time, constrained before the executable timepoints, and the failed one
/// is relaxed (its constraints removed); the network is recomputed and stays consistent.
#[test]
fn early_report_relaxes_the_failed_end_timepoint() {
    let (mut stn, o, st1, et1) = with_action(50, 60);
    let (st2, et2) = action(&mut stn, et1, 10, 10);
    stn.add_constraint(o, et2, 0, 200).unwrap();
    stn.execute(st1, 1).unwrap();
    let now = 20; // earlier than lb(et1) = 51
    assert!(now < stn.lb(et1));
    let new_end = stn.add_timepoint();
    stn.execute(new_end, now).unwrap();
    stn.add_precedence(new_end, st2).unwrap();
    let removed = stn.relax_timepoint(et1);
    assert_eq!(removed.len(), 2);
    assert_eq!(stn.constraints_of(et1).count(), 0);
    assert_eq!((stn.lb(et1), stn.ub(et1)), (0, INF));
    // st2 only waits for the new end now.
    assert_eq!(stn.lb(st2), now + 1);
    assert_eq!(stn.predecessors(st2).collect::<Vec<_>>(), vec![new_end]);
    assert_eq!(stn.successors(new_end).collect::<Vec<_>>(), vec![st2]);
    assert_eq!(stn.ub(et2), 200);
}

#[test]
fn removing_an_execution_unexecutes() {
    let (mut stn, _, st1, et1) = with_action(10, 20);
    let c = stn.execute(st1, 5).unwrap();
    stn.remove_constraint(c);
    assert!(!stn.is_executed(st1));
    assert_eq!((stn.lb(et1), stn.ub(et1)), (11, INF));
}

#[test]
fn open_bounds_are_one_unit_inside() {
    assert_eq!((open_lower(0), open_upper(10)), (1, 9));
    assert_eq!((open_lower(-INF), open_upper(INF)), (-INF, INF));
    let mut stn = Stn::new();
    let (a, b) = (stn.add_timepoint(), stn.add_timepoint());
    // b − a ∈ ]0, 3[
    stn.add_constraint(a, b, open_lower(0), open_upper(3))
        .unwrap();
    assert_eq!(stn.delay_bounds(a, b), (1, 2));
}

#[test]
fn tighten_narrows_and_is_undone_by_restore() {
    let (mut stn, _, st1, et1) = with_action(10, 20);
    let c = stn
        .constraints_of(et1)
        .find(|(_, k)| k.from == st1)
        .unwrap()
        .0;
    let level = stn.save();
    stn.tighten(c, 12, 30).unwrap();
    assert_eq!((stn.constraint(c).lb, stn.constraint(c).ub), (12, 20));
    assert_eq!(stn.lb(et1), 13);
    assert!(stn.tighten(c, 25, INF).is_err());
    assert_eq!(stn.constraint(c).lb, 12);
    stn.restore(level);
    assert_eq!(stn.constraint(c).lb, 10);
    assert_eq!(stn.lb(et1), 11);
}

#[test]
fn distance_between_unrelated_branches_goes_through_the_origin() {
    let (mut stn, o, a, _) = with_action(1, 2);
    let (b, _) = action(&mut stn, o, 1, 2);
    stn.add_constraint(o, b, 0, 40).unwrap();
    assert_eq!(stn.distance(a, b), 40 - 1);
    assert_eq!(stn.distance(b, a), INF);
    assert!(stn.possibly_before(a, b) && stn.possibly_before(b, a));
}
