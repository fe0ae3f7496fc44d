//! The Dala run of seed 1 §5 (Figs. 5-6): the two plan repairs, on domains/rover/problems/dala.ixt planned by
//! the planner and executed by `run_mission` against MockVehicle on its manual clock (deterministic), with
//! the paper's ts = 2 s and μ = 60 %. Plan repair is budgeted at 12 planning steps per cycle, about the
//! paper's rate (50 steps in 4 cycles), so that repairs span several cycles as in Fig. 6.
//! (a) the slow move(l0, l1) is stopped late-preemptively at ub − ts, well before W1; plan repair moves the
//!     rover on from where it stopped; the communication in W1 still happens and every goal is achieved.
//! (b) a picture ends too early: a new end timepoint at the report's time, plan repair (its smaller image is
//!     an over-production of STORAGE), and the PTU move that follows is launched 1 ms later (the next
//!     cycle), never postponed.

use crate::support::mission;
use mavtempo_testkit::mapping;
use mavtempo_testkit::stops;

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::{Executive, Fate};
use mavtempo_executive::exec::mission::{MissionEnd, MissionReport};
use mavtempo_executive::exec::report_timing::Timing;
use mavtempo_executive::exec::resource_report::LevelVerdict;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_temporal::lang::load_problem_and_domain;
use mavtempo_temporal::model::Time;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_temporal::planner::{Budget, Search, StepOutcome};
use mavtempo_vehicle::mock::Outcome;
use mavtempo_vehicle::ReportStatus;
use mavtempo_vehicle::{Enu, MockVehicle};

const TS: Time = 2_000;
/// W1 as dala.ixt predicts it: from 150 s to 330 s.
const W1: (Time, Time) = (150_000, 330_000);

fn executive() -> Executive {
    let (d, p) = load_problem_and_domain(Path::new(repo!("domains/rover/problems/dala.ixt")))
        .expect("shipped problem");
    let root = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mut search = Search::new(root);
    assert_eq!(search.run(Budget::steps(20_000)), StepOutcome::Solved);
    let cfg = ExecConfig {
        timestep_ms: TS,
        repair_share: 0.6,
        replan_slack_ms: TS,
        repair_max_steps: Some(20),
        ..ExecConfig::default()
    };
    let plan = search.into_plan();
    let mapping = mapping::rover(&plan);
    Executive::new(plan, cfg).with_mapping(mapping)
}

/// Dala as the domain describes it: PTU turns in 3 s, pictures in 8 s of 0.9 slot (the storage level is
/// measured after each picture and after the download, as in Fig. 8), moves at 0.45 m/s.
/// `first_picture` is the first picture's outcome; `moves` the durations of the moves, in order.
fn dala(first_picture: Outcome, moves: &[u64]) -> MockVehicle {
    let mut v = MockVehicle::new();
    v.set_level("STORAGE", 3.0);
    v.script("move_ptu", Outcome::nominal(3_000));
    v.script("take_picture", first_picture);
    for level in [1.2, 0.3, 1.6] {
        v.script(
            "take_picture",
            Outcome::nominal(8_000).with_level("STORAGE", level),
        );
    }
    v.script(
        "download_images",
        Outcome::nominal(20_000).with_level("STORAGE", 2.5),
    );
    v.script("communicate", Outcome::nominal(40_000));
    for &ms in moves {
        v.script("move", Outcome::nominal(ms));
    }
    v
}

fn run(v: &mut MockVehicle) -> MissionReport {
    let mut ex = executive();
    mission::run_mock(&mut ex, v, 30 * 60_000)
}

/// Every trace event with its cycle's index and time.
fn events(r: &MissionReport) -> Vec<(u64, Time, TraceEvent)> {
    r.cycles
        .iter()
        .flat_map(|c| {
            c.events
                .iter()
                .map(move |e| (c.index, c.time_ms, e.clone()))
        })
        .collect()
}

/// Launches: (cycle, time, action).
fn launches(r: &MissionReport) -> Vec<(u64, Time, String)> {
    events(r)
        .into_iter()
        .filter_map(|(i, t, e)| match e {
            TraceEvent::Launch { action, .. } => Some((i, t, action)),
            _ => None,
        })
        .collect()
}

/// The first launch of `action` among `launches`.
fn first_launch<'a>(launches: &'a [(u64, Time, String)], action: &str) -> &'a (u64, Time, String) {
    launches
        .iter()
        .find(|(_, _, a)| a == action)
        .unwrap_or_else(|| panic!("{action} is launched: {launches:?}"))
}

/// The cycle and time of the first trace event that `is` accepts; `what` says which in a failure.
fn first_event(
    ev: &[(u64, Time, TraceEvent)],
    what: &str,
    is: impl Fn(&TraceEvent) -> bool,
) -> (u64, Time) {
    ev.iter()
        .find(|(_, _, e)| is(e))
        .map(|(i, t, _)| (*i, *t))
        .unwrap_or_else(|| panic!("{what}: {ev:?}"))
}

fn all_achieved(r: &MissionReport) {
    assert_eq!(r.end, MissionEnd::Finished, "{:?}", r.goals);
    assert_eq!(r.goals.len(), 7);
    for g in &r.goals {
        assert_eq!(g.fate, Fate::Achieved, "{g:?}");
    }
}

#[test]
fn slow_move_is_stopped_before_w1_and_the_rover_moves_on_after_repair() {
    // The first move never arrives on its own (obstacles): stopped where it is, 4 m short of l1 = (9, 0).
    // The moves after it take what 0.45 m/s gives.
    let mut v = dala(
        Outcome::nominal(8_000).with_level("STORAGE", 2.1),
        &[600_000, 9_200, 11_300, 21_000, 23_200],
    );
    stops::move_stops_at(&mut v, Enu::new(5.0, 1.0, 0.0));
    let r = run(&mut v);
    let ev = events(&r);
    let l = launches(&r);
    let started = first_launch(&l, "move(l0, l1)").1;
    // Late-preemptive: END at ub − ts, ub being the slowest 9 m (0.3 m/s: 30 s) — before W1, no timeout.
    let (stop_cycle, stopped) = first_event(
        &ev,
        "the slow move is stopped",
        |e| matches!(e, TraceEvent::Stop { action, .. } if action == "move(l0, l1)"),
    );
    assert_eq!(stopped, started + 30_000 - TS);
    assert!(stopped < W1.0);
    assert!(!ev
        .iter()
        .any(|(_, _, e)| matches!(e, TraceEvent::Timeout { .. })));
    assert!(ev.iter().any(|(i, _, e)| *i > stop_cycle
        && matches!(e, TraceEvent::Report { action, status, .. }
            if action == "move(l0, l1)" && *status == ReportStatus::Interrupted)));
    // Plan repair, not replanning, spread over several cycles: a move from the new location where the rover
    // stopped to l1, launched once (from the last executable node, before the repair's end at the latest).
    assert_eq!(r.counters.replans, 0);
    let (repaired, _) = first_event(&ev, "the plan is repaired", |e| {
        matches!(e, TraceEvent::RepairDone { .. })
    });
    let steps: Vec<u64> = ev
        .iter()
        .filter(|(i, _, _)| *i > stop_cycle && *i < repaired)
        .filter_map(|(_, _, e)| match e {
            TraceEvent::RepairStep { steps, .. } => Some(*steps),
            _ => None,
        })
        .collect();
    assert!(steps.len() >= 2, "repair steps: {steps:?}");
    let new_moves: Vec<_> = l
        .iter()
        .filter(|(_, _, a)| a.starts_with("move(") && !a.starts_with("move(l"))
        .collect();
    assert_eq!(new_moves.len(), 1, "{l:?}");
    let (move_cycle, _, new_move) = new_moves[0];
    assert!(new_move.starts_with("move(L") && new_move.ends_with(", l1)"));
    assert!(*move_cycle > stop_cycle && *move_cycle <= repaired + 1);
    // The communication still happens in W1.
    let comm = first_launch(&l, "communicate(W1)");
    assert!(comm.1 >= W1.0 && comm.1 + 40_000 <= W1.1, "{comm:?}");
    all_achieved(&r);
}

#[test]
fn early_picture_end_gets_a_new_end_timepoint_and_the_ptu_move_starts_at_once() {
    // The first picture ends after 3 s instead of 5 to 20, its image smaller than planned (0.7 slot instead
    // of 0.8 to 1): an over-production of STORAGE, so plan repair is requested.
    let mut v = dala(
        Outcome::nominal(3_000).with_level("STORAGE", 2.3),
        &[20_000, 11_300, 21_000, 23_200],
    );
    let r = run(&mut v);
    let ev = events(&r);
    let l = launches(&r);
    let shot = first_launch(&l, "take_picture(l0)").1;
    let (report_cycle, reported) = first_event(&ev, "the picture's report is too early", |e| {
        matches!(e, TraceEvent::Report { action, timing, .. }
            if action == "take_picture(l0)" && *timing == Timing::TooEarly)
    });
    assert_eq!(reported, shot + 3_000);
    assert!(ev.iter().any(|(i, _, e)| *i == report_cycle
        && matches!(e, TraceEvent::Level { resource, verdict, .. }
            if resource == "STORAGE" && matches!(verdict, LevelVerdict::OverProduction { .. }))));
    // Repaired, not replanned.
    assert!(ev
        .iter()
        .any(|(i, _, e)| *i >= report_cycle && matches!(e, TraceEvent::RepairDone { .. })));
    assert_eq!(r.counters.replans, 0);
    // The new end timepoint is at the report's time; the PTU move that follows starts as soon as the
    // repaired plan allows: its root keeps unexecuted timepoints after the report's cycle (repair.rs,
    // `not_before(now + 1)`), so 1 ms later, in the very next cycle, and it is never postponed.
    let ptu = l
        .iter()
        .find(|(_, t, a)| a == "move_ptu(DOWN, FORWARD)" && *t >= reported)
        .expect("the PTU turns back");
    assert_eq!((ptu.0, ptu.1), (report_cycle + 1, reported + 1), "{l:?}");
    assert!(!ev.iter().any(|(_, t, e)| *t <= reported
        && matches!(e, TraceEvent::Postponed { action } if action == "move_ptu(DOWN, FORWARD)")));
    all_achieved(&r);
}
