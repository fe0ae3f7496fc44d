//! The wall-time bounds (`cycle_max_wall_ms`, `replan_max_wall_ms`) read the executive's wall clock, the one
//! `Executive::with_wall_clock` gives: a `ManualClock` here, moved past a bound while the executive plans,
//! trips it at a known step; one that stays put never does. No sleep, no real time.

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::exec::clock::{ManualClock, SharedClock};
use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::Executive;
use mavtempo_executive::exec::outcome::AttemptEnd;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_temporal::lang::load_problem_and_domain;
use mavtempo_temporal::model::Time;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_vehicle::MockVehicle;

/// Fig. 2's root plan: every goal an open condition, more repair than a cycle does.
fn fig2(cfg: ExecConfig, wall: SharedClock) -> Executive {
    let (d, p) = load_problem_and_domain(Path::new(repo!("domains/rover/problems/fig2.ixt")))
        .expect("fig2 loads");
    let plan = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    Executive::new(plan, cfg).with_wall_clock(wall)
}

/// A wall clock that the hand moves `tick` ms on each time the executive reads it.
fn ticking(hand: &ManualClock, tick: Time) -> SharedClock {
    let hand = hand.clone();
    Arc::new(move || {
        hand.advance(tick);
        mavtempo_executive::exec::clock::Clock::now(&hand)
    })
}

/// Repair steps of the first cycle, on a vehicle whose (mission) clock does not move.
fn first_cycle_steps(ex: &mut Executive) -> u64 {
    let _ = ex.cycle(&mut MockVehicle::new(), 0);
    let c = ex.cycles().records().first().expect("a cycle");
    let steps = c.events.iter().find_map(|e| match e {
        TraceEvent::RepairStep { steps, .. } => Some(*steps),
        _ => None,
    });
    steps.unwrap_or_else(|| panic!("no repair step in {:?}", c.events))
}

fn cycle_cfg() -> ExecConfig {
    ExecConfig {
        cycle_max_wall_ms: 1_000,
        repair_cycle_max_steps: 40,
        ..ExecConfig::default()
    }
}

#[test]
fn the_cycle_wall_bound_trips_on_a_manual_clock_moved_past_it() {
    // The bound is read once (r), then before each step: r+400 and r+800 allow two, r+1200 is past it.
    let hand = ManualClock::new(0);
    let mut ex = fig2(cycle_cfg(), ticking(&hand, 400));
    assert_eq!(first_cycle_steps(&mut ex), 2);
    assert!(hand_moved(&hand));
    // A wall clock that stays put never trips it: the cycle's step cap ends the repair share.
    let mut ex = fig2(cycle_cfg(), ManualClock::new(0).shared());
    assert_eq!(first_cycle_steps(&mut ex), 40);
}

fn hand_moved(hand: &ManualClock) -> bool {
    mavtempo_executive::exec::clock::Clock::now(hand) > 0
}

/// The ends of the first replanning's attempts.
fn attempt_ends(ex: &Executive) -> Vec<(AttemptEnd, u64)> {
    let rec = ex.replannings().last().expect("a replanning record");
    rec.attempts.iter().map(|a| (a.end, a.steps)).collect()
}

#[test]
fn the_replanning_wall_bound_trips_on_a_manual_clock_moved_past_it() {
    let cfg = ExecConfig {
        replan_max_wall_ms: 100_000,
        ..ExecConfig::default()
    };
    // 40 s a read: the bound is r0+100 s; the first attempt's half of what is left ends at r2+10 s, and
    // the next read (r3 = r2+40 s) is past it before any step.
    let hand = ManualClock::new(0);
    let mut ex = fig2(cfg.clone(), ticking(&hand, 40_000));
    let _ = ex.replan(&|| 0, &mut |_| {});
    let ends = attempt_ends(&ex);
    assert_eq!(ends.first(), Some(&(AttemptEnd::WallBudget, 0)), "{ends:?}");
    // The same replanning on a wall clock that stays put is not cut by it.
    let mut ex = fig2(cfg, ManualClock::new(0).shared());
    let _ = ex.replan(&|| 0, &mut |_| {});
    let ends = attempt_ends(&ex);
    assert!(
        ends.iter().all(|(end, _)| *end != AttemptEnd::WallBudget),
        "{ends:?}"
    );
    assert_eq!(
        ends.first().map(|e| e.0),
        Some(AttemptEnd::Solved),
        "{ends:?}"
    );
}
