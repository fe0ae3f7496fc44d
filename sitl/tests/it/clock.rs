//! The sim clock: paced at a speed-up (>= 200x must work) and deterministic for a seed + scenario.
#![allow(deprecated)]

use std::time::Duration;

use crate::support::*;
use mavlink::dialects::ardupilotmega::*;

#[tokio::test]
async fn a_mission_runs_paced_at_500x() {
    let mut cfg = sitl::SimConfig::for_tests();
    cfg.clock = sitl::ClockMode::Paced;
    cfg.speedup = 500.0;
    let (sim, mut gcs) = start_with(cfg).await;
    let items = vec![
        waypoint(HOME, 0.0, 0.0),
        waypoint(HOME, 60.0, 0.0),
        waypoint(HOME, 60.0, 60.0),
    ];
    start_auto(&mut gcs, &items).await;
    let s = sim
        .wait_for(Duration::from_secs(30), |s| s.mission_complete)
        .await
        .expect("mission completes");
    assert!(
        s.time_ms > 20_000,
        "two 60 m legs take > 20 s of sim time: {}",
        s.time_ms
    );
    // Telemetry carries the sim clock.
    let t = u64::from(expect_msg!(gcs, SYSTEM_TIME).await.time_boot_ms);
    assert!(t <= sim.now_ms());
}

/// Runs the same inputs on a fresh manual-clock sim; returns the final ground truth.
async fn scripted_run(seed: u64) -> sitl::Snapshot {
    let mut cfg = sitl::SimConfig::for_tests();
    cfg.seed = seed;
    cfg.scenario = sitl::Scenario::parse(
        r#"[[slow_zones]]
center_m = [20.0, 10.0]
radius_m = 8.0
[[faults]]
when = { on = "waypoint_reached", value = 2 }
fault = { kind = "battery_drop", percent = 7.5 }
"#,
        "det",
    )
    .expect("scenario");
    let (sim, mut gcs) = start_with(cfg).await;
    let mut items = vec![waypoint(HOME, 0.0, 0.0)];
    for (n, e) in [(20.0, 0.0), (20.0, 20.0), (0.0, 20.0)] {
        items.push(waypoint(HOME, n, e));
        items.push(item(
            MavCmd::MAV_CMD_IMAGE_START_CAPTURE,
            [0.0, 0.0, 1.0, 0.0],
        ));
    }
    upload_ok(&mut gcs, &items).await;
    gcs.arm().await;
    gcs.set_mode(10).await;
    for _ in 0..900 {
        sim.step(Duration::from_millis(100)).await.expect("step");
    }
    let s = sim.snapshot();
    sim.stop().await;
    s
}

#[tokio::test]
async fn same_seed_and_scenario_give_the_same_run() {
    let a = scripted_run(7).await;
    let b = scripted_run(7).await;
    assert!(a.mission_complete);
    assert_eq!(a.pictures_ok, 3);
    assert_eq!(a, b);
    let c = scripted_run(8).await;
    assert_ne!(
        a.storage_used_mib, c.storage_used_mib,
        "picture sizes follow the seed"
    );
    assert_eq!(
        (a.north_m, a.east_m),
        (c.north_m, c.east_m),
        "the seed does not move the vehicle"
    );
}

#[tokio::test]
async fn the_speedup_bench_completes_its_mission() {
    let r = sitl::bench::measure_speedup(200.0, 2, 20.0)
        .await
        .expect("bench runs");
    assert_eq!(r.speedup_requested, 200.0);
    assert!(
        r.sim_s > 5.0,
        "two 20 m legs take seconds of sim time: {r:?}"
    );
    assert!(r.speedup_achieved > 0.0 && r.speedup_ceiling > 0.0, "{r:?}");
}
