//! `run_mission` against MockVehicle on its manual clock: the planner's shopping-day plan run to the end,
//! the report's goals, plan changes, resource samples and cycle times.

use crate::support::mission;
use crate::support::shopping;

use mavtempo_executive::exec::cycle_log::{cycles_of, last_index};
use mavtempo_executive::exec::executive::{Executive, Fate};
use mavtempo_executive::exec::mission::{run_mission, MissionEnd, MissionOptions};
use mavtempo_executive::exec::outcome::FateReason;
use mavtempo_executive::exec::pacer::MockPacer;
use mavtempo_executive::exec::trace::CycleRecord;

fn shopping_executive() -> Executive {
    shopping::day_executive(shopping::day_config())
}

#[test]
fn shopping_day_runs_to_the_end_and_reports() {
    let mut ex = shopping_executive();
    let mut v = shopping::day_vehicle();
    let opts = MissionOptions {
        time_limit_ms: 12 * 3_600_000,
        ..MissionOptions::default()
    };
    let mut seen = 0;
    let report = run_mission(
        &mut ex,
        &mut v,
        &mut MockPacer::default(),
        &opts,
        &mut |_, _| seen += 1,
    );
    assert_eq!(report.end, MissionEnd::Finished, "{:?}", report.goals);
    assert_eq!(report.goals.len(), 2);
    assert!(report.goals.iter().all(|g| g.fate == Fate::Achieved));
    assert_eq!(report.cycle_times.count, seen);
    assert!(report.cycle_times.p50_us <= report.cycle_times.p99_us);
    // No cycle is more than ts after the previous one (the wake-up rule's upper bound); within a run of
    // idle cycles recorded as one, the run's own span is at most ts per cycle.
    assert!(report.cycles.windows(2).all(|w| {
        let last = w[0].idle.as_ref().map_or(w[0].time_ms, |r| r.last_time_ms);
        w[1].time_ms - last <= 30_000
    }));
    assert!(report.cycles.iter().all(|c| c
        .idle
        .as_ref()
        .is_none_or(|r| { r.last_time_ms - c.time_ms <= 30_000 * (r.cycles as i64 - 1) })));
    assert!(
        shopping::launches(&report.cycles) >= 3,
        "go, buy, go home at least"
    );
    // Each report arrives when the mock said: the mission ends after the last action's duration.
    assert!(report.duration_ms >= 16 * 60_000 * 2 + 5 * 60_000);
    let json = serde_json::to_value(&report).expect("serialises");
    assert_eq!(json["goals"][0]["fate"], "achieved");
}

#[test]
fn time_limit_leaves_goals_pending_with_a_reason() {
    let mut ex = shopping_executive();
    let mut v = shopping::day_vehicle();
    let report = mission::run_mock(&mut ex, &mut v, 10 * 60_000);
    assert_eq!(report.end, MissionEnd::TimeLimit);
    assert!(report
        .goals
        .iter()
        .all(|g| g.fate == Fate::Pending && g.reason == Some(FateReason::TimeLimit)));
}

/// The vehicle falls silent mid-mission: once silent for the link timeout (mission time goes on: the mock's
/// manual clock stands for the companion's), the mission ends with the verdict and every goal still
/// pending is settled with it.
#[test]
fn a_vehicle_silent_for_the_link_timeout_is_lost() {
    let mut ex = shopping_executive();
    let mut v = shopping::day_vehicle();
    v.fall_silent_at(10 * 60_000);
    let opts = MissionOptions {
        time_limit_ms: 12 * 3_600_000,
        vehicle_lost_after: Some(std::time::Duration::from_secs(30)),
        ..MissionOptions::default()
    };
    let report = run_mission(
        &mut ex,
        &mut v,
        &mut MockPacer::default(),
        &opts,
        &mut |_, _| {},
    );
    assert_eq!(report.end, MissionEnd::VehicleLost { silent_s: 30 });
    assert_eq!(
        report.end.vehicle_lost().as_deref(),
        Some("vehicle lost: no heartbeat for 30 s")
    );
    // Seen within one timestep (30 s here) of the timeout.
    assert!(
        (10 * 60_000 + 30_000..=10 * 60_000 + 60_000).contains(&report.duration_ms),
        "{}",
        report.duration_ms
    );
    assert!(!report.goals.is_empty());
    for g in &report.goals {
        assert_eq!(g.fate, Fate::Pending, "{g:?}");
        assert_eq!(
            g.reason,
            Some(FateReason::VehicleLost { silent_s: 30 }),
            "{g:?}"
        );
    }
    let json = serde_json::to_value(&report).expect("serialises");
    assert_eq!(json["end"]["vehicle_lost"]["silent_s"], 30);
    assert_eq!(
        json["goals"][0]["reason"],
        "vehicle lost: no heartbeat for 30 s"
    );
}

/// Without a link timeout, a silent vehicle is waited for (the stepped simulator's missions).
#[test]
fn without_a_link_timeout_silence_is_no_verdict() {
    let mut ex = shopping_executive();
    let mut v = shopping::day_vehicle();
    v.fall_silent_at(0);
    let report = mission::run_mock(&mut ex, &mut v, 10 * 60_000);
    assert_eq!(report.end, MissionEnd::TimeLimit);
}

/// Issue 31: a 12-hour mission that mostly waits (the shopping day waits from mid-morning to its 20:00
/// goal), one cycle a second on the manual clock: every busy cycle is kept whole in the report, the idle
/// cycles between them as runs (count, span, longest cycle), so the record grows with what happened, not
/// with time.
#[test]
fn a_long_idle_mission_keeps_its_busy_cycles_and_a_bounded_record() {
    let cfg = mavtempo_executive::exec::config::ExecConfig {
        timestep_ms: 1_000,
        ..shopping::day_config()
    };
    let mut ex = shopping::day_executive(cfg);
    let mut v = shopping::day_vehicle();
    let opts = MissionOptions {
        time_limit_ms: 13 * 3_600_000,
        ..MissionOptions::default()
    };
    let mut busy: Vec<CycleRecord> = Vec::new();
    let mut seen = 0u64;
    let report = run_mission(
        &mut ex,
        &mut v,
        &mut MockPacer::default(),
        &opts,
        &mut |_, c| {
            seen += 1;
            if !c.events.is_empty() {
                busy.push(c.clone());
            }
        },
    );
    assert_eq!(report.end, MissionEnd::Finished, "{:?}", report.goals);
    assert!(
        report.duration_ms >= 11 * 3_600_000,
        "{}",
        report.duration_ms
    );
    let count = report.cycle_times.count as u64;
    assert_eq!(count, seen);
    assert!(count > 40_000, "{count} cycles");

    // Every busy cycle is a record of its own, as it ran.
    let json = |c: &CycleRecord| serde_json::to_value(c).expect("json");
    let kept: Vec<&CycleRecord> = report
        .cycles
        .iter()
        .filter(|c| c.idle.is_none() && !c.events.is_empty())
        .collect();
    assert_eq!(kept.len(), busy.len());
    assert!(kept.iter().zip(&busy).all(|(k, b)| json(k) == json(b)));
    // The records cover every cycle once, in order; the idle runs say what their cycles did.
    assert_eq!(report.cycles.iter().map(cycles_of).sum::<u64>(), count);
    assert!(report
        .cycles
        .windows(2)
        .all(|w| w[1].index == last_index(&w[0]) + 1));
    let runs: Vec<_> = report
        .cycles
        .iter()
        .filter_map(|c| c.idle.as_ref().map(|r| (c, r)))
        .collect();
    let longest = runs
        .iter()
        .max_by_key(|(_, r)| r.cycles)
        .expect("an idle run");
    assert!(longest.1.cycles > 30_000, "{:?}", longest.1);
    assert!(longest.1.last_time_ms - longest.0.time_ms >= 30_000 * 1_000 - 1_000);
    assert!(runs
        .iter()
        .all(|(_, r)| r.max_us <= report.cycle_times.max_us));
    // Bounded by what happened: a record per busy cycle and at most one idle run beside each.
    assert!(
        report.cycles.len() <= 2 * busy.len() + 1,
        "{} records",
        report.cycles.len()
    );
    let size = serde_json::to_string(&report.cycles).expect("json").len();
    assert!(
        size < 64 * 1024,
        "{size} bytes of cycle records for {count} cycles"
    );
}
