//! Complete replanning (seed 1 §3.6): P_ti extraction, T_end, goal rejection order.

use mavtempo_testkit::mapping;
use mavtempo_testkit::problems as common;

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::Executive;
use mavtempo_executive::exec::replan::{extract, goal_to_reject, Extracted};
use mavtempo_temporal::lang::{load_problem_and_domain, parse_domain, parse_problem};
use mavtempo_temporal::model::{GoalId, Value};
use mavtempo_temporal::plan::PartialPlan;

fn fig2() -> Executive {
    let (d, p) = load_problem_and_domain(Path::new(repo!("domains/rover/problems/fig2.ixt")))
        .expect("fig2 loads");
    let plan = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mapping = mapping::rover(&plan);
    Executive::new(plan, ExecConfig::default()).with_mapping(mapping)
}

#[test]
fn rejection_order_lowest_priority_then_least_flexibility() {
    let ex = fig2();
    let mut plan = ex.plan().clone();
    // g3 has priority 3; among the others (priority 1) the least st_ub − d_achiev is g2's (window 4 min,
    // d_achiev 55 s), then, with the same 30 min window, g5 (d_achiev 80 s), g4 (65 s), g1 (25 s).
    let mut order = Vec::new();
    while let Some(g) = goal_to_reject(&plan) {
        order.push(plan.problem().goals[g.index()].name.clone());
        plan.remove_goal(g);
    }
    assert_eq!(order, ["g2", "g5", "g4", "g1", "g3"]);
}

#[test]
fn p_ti_keeps_the_state_drops_incoherent_goals_and_puts_goals_after_t_end() {
    let mut ex = fig2();
    let at = ex.plan().domain().attr_id("AT_ROBOT").unwrap();
    let p1 = ex.plan().problem().object_id("p1").unwrap();
    let now = 9 * 60_000;
    ex.set_state_value((at, vec![]), now - 1_000, Value::Obj(p1));
    let storage = ex.resource("STORAGE").unwrap();
    ex.set_past_level(storage, (1.2, 1.4));
    // g1 achieved already: not in G_ti.
    ex.set_fate(
        GoalId(0),
        mavtempo_executive::exec::executive::Fate::Achieved,
        None,
    );
    let ext = extract(&ex, now, &[]).expect("P_ti");
    // S_ti = S_ts: the robot is at p1, the storage level its pessimistic bound.
    let init = ext
        .plan
        .problem()
        .initial
        .iter()
        .find(|f| f.attr == at)
        .expect("AT_ROBOT in the initial state");
    assert_eq!(init.value, Value::Obj(p1));
    assert!((ext.plan.problem().resources[storage.index()].level - 1.2).abs() < 1e-9);
    // g2 (st ≤ 4 min) and g3 (st ≤ 8 min) are no longer coherent with 9 min; g1 is done; g4, g5 remain.
    assert_eq!(ext.incoherent, vec![GoalId(1), GoalId(2)]);
    let active: Vec<u32> = ext
        .plan
        .goals()
        .iter()
        .filter(|g| g.active)
        .map(|g| g.goal.0)
        .collect();
    assert_eq!(active, vec![3, 4]);
    // T_end after now; each goal after T_end; new timepoints after T_end.
    assert!(ext.plan.temporal_network().lb(ext.t_end) >= now);
    for g in ext.plan.goals().iter().filter(|g| g.active) {
        assert!(ext
            .plan
            .temporal_network()
            .necessarily_before(ext.t_end, g.st));
    }
    let mut plan = ext.plan;
    let tp = plan.new_timepoint().unwrap();
    assert!(plan.temporal_network().necessarily_before(ext.t_end, tp));
    // Inserting actions lowers T_end's upper bound ("planning to plan").
    let before = plan.temporal_network().ub(ext.t_end);
    let g4 = plan
        .goals()
        .iter()
        .find(|g| g.active)
        .expect("g4 active")
        .st;
    plan.constrain(tp, g4, 600_000, mavtempo_temporal::stn::INF)
        .unwrap();
    assert!(plan.temporal_network().ub(ext.t_end) < before);
}

use std::cell::Cell;

use mavtempo_executive::exec::replan::{plan_until_limit, AttemptEnd};
use mavtempo_temporal::model::Time;
use mavtempo_temporal::planner::{Search, StepOutcome};

/// The limit l = T_end_ub − d of a search.
fn limit(s: &Search, t_end: mavtempo_temporal::stn::Timepoint, slack: Time) -> Time {
    s.plan().temporal_network().ub(t_end) - slack
}

/// A clock that moves 10 s of mission time each time it is read: planning takes mission time, and T_end
/// (g2 within 4 min) is reached after a few reads, long before the search could finish.
#[test]
fn the_time_limit_stops_a_replanning() {
    let ex = fig2();
    let slack = ex.config().replan_slack_ms;
    let ext = extract(&ex, 0, &[]).expect("P_ti");
    let l0 = ext.plan.temporal_network().ub(ext.t_end) - slack;
    assert!(l0 > 0 && l0 < 4 * 60_000, "l0 = {l0}");
    let t = Cell::new(0);
    let clock = || {
        let now = t.get();
        t.set(now + 10_000);
        now
    };
    let mut search = Search::new(ext.plan.clone());
    let end = plan_until_limit(&mut search, ext.t_end, slack, 100_000, &clock);
    assert_eq!(end, AttemptEnd::TimeLimit);
    // One read per step: stopped at the first read at or past the limit as it then was.
    let steps = search.steps() as Time;
    assert!(
        steps * 10_000 >= limit(&search, ext.t_end, slack),
        "{steps} steps"
    );
    assert!(steps * 10_000 < l0 + 10_000, "{steps} steps");
    // The same attempt with a clock that does not move plans on (the limit is what stopped it).
    let mut frozen = Search::new(ext.plan);
    let end = plan_until_limit(&mut frozen, ext.t_end, slack, 100_000, &|| 0);
    assert_eq!(end, AttemptEnd::Solved);
    assert!(frozen.steps() > search.steps());
}

/// Fig. 2 replanned completely with a clock that moves 10 s each time it is read.
fn fig2_replanned_on_a_moving_clock() -> Executive {
    let mut ex = fig2();
    let t = Cell::new(0);
    let clock = || {
        let now = t.get();
        t.set(now + 10_000);
        now
    };
    let _ = ex.replan(&clock, &mut |_| {});
    ex
}

/// Through `Executive::replan`: the moving clock makes the first attempt stop at l, a goal is rejected.
#[test]
fn replan_reports_the_time_limit_and_rejects_a_goal() {
    let ex = fig2_replanned_on_a_moving_clock();
    let outcomes: Vec<AttemptEnd> = ex
        .pending_events()
        .iter()
        .filter_map(|e| match e {
            mavtempo_executive::exec::trace::TraceEvent::Replan(a) => Some(a.end),
            _ => None,
        })
        .collect();
    assert_eq!(
        outcomes.first(),
        Some(&AttemptEnd::TimeLimit),
        "{outcomes:?}"
    );
    // The same as data in the executive's record of the replanning.
    let rec = ex.replannings().last().expect("a replanning record");
    assert_eq!(rec.attempts[0].end, AttemptEnd::TimeLimit);
    assert!(!rec.rejected.is_empty());
    assert!(ex
        .goal_fates()
        .iter()
        .any(|g| g.fate == mavtempo_executive::exec::executive::Fate::Rejected));
}

/// DONE is reached by `slow` (100 s, tried first, but it needs READY, which nothing makes true: a dead end
/// one step later) or by `fast` (`fast_s` seconds); goal g wants DONE within 300 s.
fn alternatives(fast_s: u32) -> Executive {
    let d = parse_domain(
        "alt.ixt",
        &format!(
            "domain alt;
             attribute DONE(): bool;
             attribute READY(): bool;
             task slow() (st, et) {{
                 hold(READY(): true, (st, et));
                 event(DONE(): (false, true), et);
                 (et - st) in [100, 100];
             }} nonPreemptive
             task fast() (st, et) {{
                 event(DONE(): (false, true), et);
                 (et - st) in [{fast_s}, {fast_s}];
             }} nonPreemptive"
        ),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let p = parse_problem(
        "alt-problem.ixt",
        "problem p; domain alt; horizon 30min;
         initial { DONE() = false; READY() = false; }
         goal g { hold(DONE(): true, (st, et)); st in [0, 300s]; }",
        &d,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let plan = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    Executive::new(plan, ExecConfig::default())
}

/// A clock standing at 0 for its first read, then at `t`.
fn jumps_to(t: Time) -> impl Fn() -> Time {
    let reads = Cell::new(0u32);
    move || {
        let n = reads.get();
        reads.set(n + 1);
        if n == 0 {
            0
        } else {
            t
        }
    }
}

/// P_ti of `alternatives(fast_s)` with its replanning slack, and the depth-first search that took step 1
/// (inserting `slow`) from it, with l after that step.
fn after_step_1(fast_s: u32) -> (Extracted, Time, Search, Time) {
    let ex = alternatives(fast_s);
    let slack = ex.config().replan_slack_ms;
    let ext = extract(&ex, 0, &[]).expect("P_ti");
    let mut probe = Search::depth_first(ext.plan.clone());
    assert_eq!(probe.step(), StepOutcome::Progress);
    let l1 = limit(&probe, ext.t_end, slack);
    (ext, slack, probe, l1)
}

/// §3.6's exception (on plain depth-first search, whose step order the test spells out): past l, a step
/// that backtracks and raises l is taken and planning goes on. Step 1
/// inserts `slow` (T_end_ub falls from 300 s to 200 s); the clock then stands exactly at l; step 2 is the
/// backtrack to `fast`, which raises T_end_ub to 290 s: planning goes on and finds the plan.
#[test]
fn a_backtrack_that_raises_l_continues_past_the_limit() {
    let (ext, slack, mut probe, l1) = after_step_1(10);
    assert!(probe.next_is_backtrack(), "step 2 should be the backtrack");
    assert_eq!(l1, 200_000 - 1 - slack);

    let mut search = Search::depth_first(ext.plan.clone());
    let end = plan_until_limit(&mut search, ext.t_end, slack, 1_000, &jumps_to(l1));
    assert_eq!(end, AttemptEnd::Solved, "after {} steps", search.steps());
    assert_eq!(search.backtracks(), 1);
    assert!(limit(&search, ext.t_end, slack) > l1);

    // The same clock one read earlier, at the limit before step 1: that step is no backtrack, so planning
    // stops at once.
    let l0 = limit(&Search::depth_first(ext.plan.clone()), ext.t_end, slack);
    let mut search = Search::depth_first(ext.plan);
    let end = plan_until_limit(&mut search, ext.t_end, slack, 1_000, &|| l0);
    assert_eq!(end, AttemptEnd::TimeLimit);
    assert_eq!(search.steps(), 0);
}

/// A backtrack past l that does not raise it (`fast` is as long as `slow`) does not keep planning going.
#[test]
fn a_backtrack_that_does_not_raise_l_stops_at_the_limit() {
    let (ext, slack, _, l1) = after_step_1(100);
    let mut search = Search::depth_first(ext.plan);
    let end = plan_until_limit(&mut search, ext.t_end, slack, 1_000, &jumps_to(l1));
    assert_eq!(end, AttemptEnd::TimeLimit);
    assert_eq!(
        search.steps(),
        2,
        "the backtrack is taken, then planning stops"
    );
}

/// With a clock that never moves, the attempt's hard step cap still ends it.
#[test]
fn a_frozen_clock_cannot_run_an_attempt_unbounded() {
    let ex = fig2();
    let ext = extract(&ex, 0, &[]).expect("P_ti");
    let mut search = Search::depth_first(ext.plan);
    let end = plan_until_limit(
        &mut search,
        ext.t_end,
        ex.config().replan_slack_ms,
        7,
        &|| 0,
    );
    assert_eq!(end, AttemptEnd::StepCap);
    assert_eq!(search.steps(), 7);
}

/// Each attempt of a complete replanning has one goal fewer and half the steps of the one before (never
/// under a sixteenth of the first): the whole replanning is bounded, whatever the number of goals.
#[test]
fn replanning_attempts_halve_their_step_cap() {
    use mavtempo_executive::exec::replan::attempt_cap;
    let caps: Vec<u64> = (1..=8).map(|k| attempt_cap(100_000, k)).collect();
    assert_eq!(
        caps,
        [100_000, 50_000, 25_000, 12_500, 6_250, 6_250, 6_250, 6_250]
    );
    // Six goals dropped one by one: within 2.1 times the first attempt's cap.
    let total: u64 = (1..=7).map(|k| attempt_cap(100_000, k)).sum();
    assert!(total <= 210_000, "{total}");
    assert_eq!(attempt_cap(1, 9), 1);
    assert_eq!(attempt_cap(100_000, usize::MAX), 6_250);
}

/// Among goals of the same priority and flexibility, the newest is abandoned first.
#[test]
fn equal_goals_the_newest_is_abandoned_first() {
    let ex = fig2();
    let mut plan = ex.plan().clone();
    // g4 and g5 differ only by d_achiev; make g5 like g4: then the newer, g5, goes first.
    let mut p = (**plan.problem()).clone();
    p.goals[4].achieve = p.goals[3].achieve;
    plan.set_problem(Arc::new(p));
    plan.remove_goal(GoalId::from_index(1));
    assert_eq!(goal_to_reject(&plan), Some(GoalId::from_index(4)));
}

/// A goal that cannot be achieved even alone (a target 500 m away: the last leg alone needs 250 % of the
/// battery) is rejected before the first attempt, with why — even at the highest priority — and the
/// replanning keeps every other goal instead of abandoning them one attempt at a time.
#[test]
fn an_unreachable_goal_is_rejected_first_with_why_and_the_others_are_kept() {
    let d = mavtempo_temporal::lang::load_domain(Path::new(repo!("domains/rover/rover.ixt")))
        .expect("rover");
    let p = common::fig2_with_far_target(&d, 500.0, 5);
    let plan = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mut ex = Executive::new(plan, ExecConfig::default());
    let result = ex.replan(&|| 0, &mut |_| {});
    assert!(
        matches!(
            result,
            mavtempo_executive::exec::replan::ReplanResult::Plan(_)
        ),
        "{result:?}"
    );
    for g in ex.goal_fates() {
        if g.name == "gfar" {
            assert_eq!(g.fate, mavtempo_executive::exec::executive::Fate::Rejected);
            assert!(
                matches!(&g.reason, Some(mavtempo_executive::exec::outcome::FateReason::Unreachable { why, .. })
                    if why.contains("BATTERY")),
                "{:?}",
                g.reason
            );
        } else {
            assert_eq!(
                g.fate,
                mavtempo_executive::exec::executive::Fate::Pending,
                "{}",
                g.name
            );
        }
    }
}

/// Seed 1 §3.6's order after a failed attempt: P_ti is extracted again; goals whose constraints the time
/// spent planning made inconsistent are rejected, and only if there are none is one goal abandoned. So
/// between two attempts either every goal that left was rejected for its window, or exactly one was
/// abandoned — never one abandoned and another rejected for its window in the same round.
#[test]
fn between_two_attempts_either_windows_passed_or_one_goal_is_abandoned() {
    use mavtempo_executive::exec::outcome::FateReason;
    let ex = fig2_replanned_on_a_moving_clock();
    let rec = ex.replannings().last().expect("a replanning record");
    assert!(rec.attempts.len() >= 2, "{:?}", rec.attempts);
    let fates = ex.goal_fates();
    let reason = |name: &str| {
        fates
            .iter()
            .find(|f| f.name == name)
            .and_then(|f| f.reason.clone())
    };
    let mut windows_passed = 0;
    for pair in rec.attempts.windows(2) {
        let left: Vec<&String> = pair[0]
            .goals
            .iter()
            .filter(|g| !pair[1].goals.contains(g))
            .collect();
        let passed = left
            .iter()
            .filter(|g| matches!(reason(g), Some(FateReason::WindowPassed { .. })))
            .count();
        let abandoned = left
            .iter()
            .filter(|g| matches!(reason(g), Some(FateReason::Abandoned { .. })))
            .count();
        assert!(
            (passed == left.len() && abandoned == 0) || (left.len() == 1 && abandoned == 1),
            "between attempts {} and {}: {left:?} left ({passed} windows passed, {abandoned} abandoned)",
            pair[0].attempt,
            pair[1].attempt
        );
        windows_passed += passed;
    }
    // The moving clock passes g2's window (4 min) during the first attempt: the round drops it for that.
    assert!(windows_passed >= 1, "{:?}", rec.attempts);
}
