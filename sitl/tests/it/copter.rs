//! The copter over a real socket, as ArduCopter answers (sitl/src/autopilot/copter.rs cites the sources):
//! identity and mode numbers, takeoff only armed in GUIDED and landed, altitude held, the landed state in
//! EXTENDED_SYS_STATE, LAND and RTL landing and disarming, hover drain, and the auto-disarm on the ground.
#![allow(deprecated)]

use std::time::Duration;

use crate::support::*;
use mavlink::dialects::ardupilotmega::*;

const GUIDED: u32 = 4;
const LOITER: u32 = 5;
const RTL: u32 = 6;
const LAND: u32 = 9;

/// A copter sim (manual clock, port 0) with `scenario`, and a client.
async fn copter(scenario: &str) -> (sitl::SimHandle, Gcs) {
    let mut cfg = sitl::SimConfig::for_tests();
    cfg.vehicle = sitl::VehicleKind::Copter;
    cfg.scenario = sitl::Scenario::parse(scenario, "test").expect("scenario");
    start_with(cfg).await
}

async fn takeoff(gcs: &mut Gcs, alt: f32) -> MavResult {
    gcs.command(
        MavCmd::MAV_CMD_NAV_TAKEOFF,
        &[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, alt],
    )
    .await
}

/// GUIDED, armed, takeoff to `alt` and wait until it is there (bounded in sim time).
async fn airborne(sim: &sitl::SimHandle, gcs: &mut Gcs, alt: f32) {
    assert_eq!(gcs.set_mode(GUIDED).await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(takeoff(gcs, alt).await, MavResult::MAV_RESULT_ACCEPTED);
    run_until(sim, 120, |s| {
        (-s.depth_m - f64::from(alt)).abs() < 0.2 && s.landed_state == 2
    })
    .await;
}

async fn landed_state(sim: &sitl::SimHandle, gcs: &mut Gcs) -> MavLandedState {
    gcs.drain();
    assert_eq!(
        gcs.request_message(245).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    sim.step(Duration::from_millis(10)).await.expect("step");
    expect_msg!(gcs, EXTENDED_SYS_STATE).await.landed_state
}

#[tokio::test]
async fn a_copter_is_a_quadrotor_with_arducopter_modes() {
    let (sim, mut gcs) = copter("").await;
    for (mode, name) in [
        (GUIDED, "GUIDED"),
        (LOITER, "HOLD"),
        (LAND, "LAND"),
        (RTL, "RTL"),
    ] {
        assert_eq!(
            gcs.set_mode(mode).await,
            MavResult::MAV_RESULT_ACCEPTED,
            "{name}"
        );
        assert_eq!(sim.snapshot().mode, name);
        let hb = expect_msg!(gcs, HEARTBEAT).await;
        assert_eq!(hb.mavtype, MavType::MAV_TYPE_QUADROTOR);
        assert_eq!(hb.custom_mode, mode);
    }
    // Rover's GUIDED (15) is no copter mode.
    assert_eq!(gcs.set_mode(15).await, MavResult::MAV_RESULT_FAILED);
}

#[tokio::test]
async fn takeoff_needs_guided_armed_and_the_ground() {
    let (sim, mut gcs) = copter("").await;
    // Disarmed, and in STABILIZE: refused.
    assert_eq!(takeoff(&mut gcs, 10.0).await, MavResult::MAV_RESULT_FAILED);
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(takeoff(&mut gcs, 10.0).await, MavResult::MAV_RESULT_FAILED);
    // COMMAND_INT in another frame than GLOBAL_RELATIVE_ALT: DENIED.
    assert_eq!(gcs.set_mode(GUIDED).await, MavResult::MAV_RESULT_ACCEPTED);
    let (r, _) = gcs
        .command_int(MavCmd::MAV_CMD_NAV_TAKEOFF, [0.0; 4], 0, 0, 10.0)
        .await;
    assert_eq!(r, MavResult::MAV_RESULT_DENIED);
    assert_eq!(
        landed_state(&sim, &mut gcs).await,
        MavLandedState::MAV_LANDED_STATE_ON_GROUND
    );
    assert_eq!(
        takeoff(&mut gcs, 10.0).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    sim.step(Duration::from_secs(2)).await.expect("step");
    assert_eq!(
        landed_state(&sim, &mut gcs).await,
        MavLandedState::MAV_LANDED_STATE_TAKEOFF
    );
    let s = run_until(&sim, 60, |s| s.landed_state == 2).await;
    assert!((-s.depth_m - 10.0).abs() < 0.25, "{}", s.depth_m);
    // Flying: a second takeoff is refused.
    assert_eq!(takeoff(&mut gcs, 20.0).await, MavResult::MAV_RESULT_FAILED);
    // The altitude is held, and reported above home in GLOBAL_POSITION_INT.
    sim.step(Duration::from_secs(10)).await.expect("step");
    gcs.drain();
    sim.step(Duration::from_secs(1)).await.expect("step");
    let p = expect_msg!(gcs, GLOBAL_POSITION_INT).await;
    assert!((p.relative_alt - 10_000).abs() < 250, "{}", p.relative_alt);
}

#[tokio::test]
async fn a_landed_copter_does_not_move_and_a_flying_one_flies_at_the_target_altitude() {
    let (sim, mut gcs) = copter("").await;
    assert_eq!(gcs.set_mode(GUIDED).await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let wp = waypoint(HOME, 40.0, 0.0);
    let (r, _) = gcs.reposition(&wp, true, 15.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    sim.step(Duration::from_secs(5)).await.expect("step");
    assert!(sim.snapshot().north_m.abs() < 1e-6, "moved on the ground");
    assert_eq!(
        takeoff(&mut gcs, 10.0).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    run_until(&sim, 60, |s| s.landed_state == 2).await;
    let (r, _) = gcs.reposition(&wp, true, 15.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    let s = run_until(&sim, 120, |s| s.north_m > 39.0 && s.speed_mps < 0.05).await;
    assert!((-s.depth_m - 15.0).abs() < 0.1, "{}", s.depth_m);
}

#[tokio::test]
async fn land_and_rtl_touch_down_and_disarm() {
    let (sim, mut gcs) = copter("").await;
    airborne(&sim, &mut gcs, 12.0).await;
    // NAV_LAND enters LAND: landing, then on the ground and disarmed where it was.
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_NAV_LAND, &[]).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(sim.snapshot().mode, "LAND");
    sim.step(Duration::from_secs(1)).await.expect("step");
    assert_eq!(
        landed_state(&sim, &mut gcs).await,
        MavLandedState::MAV_LANDED_STATE_LANDING
    );
    let s = run_until(&sim, 60, |s| !s.armed).await;
    assert_eq!(s.landed_state, 1);
    assert!(s.depth_m.abs() < 0.06);
    // Up again, away, then RTL: home at RTL_ALT (15 m) at least, down, disarmed.
    airborne(&sim, &mut gcs, 10.0).await;
    let (r, _) = gcs.reposition(&waypoint(HOME, 0.0, 60.0), true, 10.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    run_until(&sim, 120, |s| s.east_m > 59.0).await;
    assert_eq!(gcs.set_mode(RTL).await, MavResult::MAV_RESULT_ACCEPTED);
    let mut top: f64 = 0.0;
    for _ in 0..2000 {
        sim.step(Duration::from_millis(100)).await.expect("step");
        top = top.max(-sim.snapshot().depth_m);
        if !sim.snapshot().armed {
            break;
        }
    }
    let s = sim.snapshot();
    assert!(!s.armed && s.landed_state == 1, "{s:?}");
    assert!(
        s.north_m.hypot(s.east_m) <= 2.0,
        "landed away from home: {s:?}"
    );
    assert!(top > 14.5, "the return climbed to {top} m only");
    assert!(s.statustexts.iter().any(|t| t == "Land complete"));
}

#[tokio::test]
async fn hovering_drains_the_battery_and_an_idle_armed_copter_disarms() {
    let (sim, mut gcs) =
        copter("[battery]\ninitial_pct = 90.0\ndrain_pct_per_min = 0.0\nrecharge_pct_per_min = 0.0\nhover_pct_per_min = 6.0\n").await;
    // Armed on the ground without a takeoff: disarmed after DISARM_DELAY (10 s), battery untouched.
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    sim.step(Duration::from_secs(9)).await.expect("step");
    assert!(sim.snapshot().armed);
    run_until(&sim, 3, |s| !s.armed).await;
    assert!((sim.snapshot().battery_pct - 90.0).abs() < 1e-9);
    airborne(&sim, &mut gcs, 5.0).await;
    let before = sim.snapshot().battery_pct;
    sim.step(Duration::from_secs(60)).await.expect("step");
    let drained = before - sim.snapshot().battery_pct;
    assert!(
        (drained - 6.0).abs() < 0.05,
        "hovering 60 s drained {drained} %"
    );
}

#[tokio::test]
async fn a_headwind_slows_the_leg_it_covers() {
    let wind = "[[faults]]\nwhen = { at_s = 1.0 }\nfault = { kind = \"slow_zone\", zone = { center_m = [50.0, 0.0], radius_m = 100.0, speed_factor = 0.3 } }\n";
    let (sim, mut gcs) = copter(wind).await;
    airborne(&sim, &mut gcs, 10.0).await;
    let (r, _) = gcs.reposition(&waypoint(HOME, 60.0, 0.0), true, 10.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    let mut fastest: f64 = 0.0;
    for _ in 0..300 {
        sim.step(Duration::from_millis(100)).await.expect("step");
        fastest = fastest.max(sim.snapshot().speed_mps);
    }
    assert!(
        fastest <= 0.3 * 5.0 + 1e-6,
        "flew at {fastest} m/s in the wind"
    );
}
