//! `run_mission` against MockVehicle on its manual clock: the planner's shopping-day plan run to the end,
//! the report's goals, plan changes, resource samples and cycle times.

#[path = "common/mission.rs"]
mod mission;
#[path = "common/shopping.rs"]
mod shopping;

use mavtempo::exec::executive::{Executive, Fate};
use mavtempo::exec::mission::{run_mission, MissionEnd, MissionOptions};
use mavtempo::exec::outcome::FateReason;
use mavtempo::exec::pacer::MockPacer;

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
    assert_eq!(seen, report.cycles.len());
    assert_eq!(report.cycle_times.count, report.cycles.len());
    assert!(report.cycle_times.p50_us <= report.cycle_times.p99_us);
    // No cycle is more than ts after the previous one (the wake-up rule's upper bound).
    assert!(report
        .cycles
        .windows(2)
        .all(|w| w[1].time_ms - w[0].time_ms <= 30_000));
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
