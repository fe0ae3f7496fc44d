//! The copter on the PX4 profile over a real socket, as a real PX4 SIH quadrotor (`sihsim_quadx`) answered
//! the companion (sitl/src/autopilot/px4.rs names the PX4 sources): its estimator reads CONST_POS_MODE at
//! rest on the ground with its absolute position, NAV_TAKEOFF enters AUTO.TAKEOFF to an AMSL altitude and
//! PX4 switches to AUTO.LOITER by itself once up, and a landing disarms and hands back Hold.
#![allow(deprecated)]

use std::time::Duration;

use crate::support::*;
use mavlink::dialects::ardupilotmega::*;

/// PX4's custom_mode for main/sub (px4_custom_mode.h).
const fn px4_mode(main: u32, sub: u32) -> u32 {
    (main << 16) | (sub << 24)
}
const TAKEOFF: u32 = px4_mode(4, 2);
const HOLD: u32 = px4_mode(4, 3);
const LAND: u32 = px4_mode(4, 6);

/// A PX4 quadrotor (manual clock, port 0), boot delays off, and a client.
async fn px4_copter() -> (sitl::SimHandle, Gcs) {
    let mut cfg = sitl::SimConfig::for_tests();
    cfg.vehicle = sitl::VehicleKind::Copter;
    cfg.scenario = sitl::Scenario::parse(
        "[autopilot]\nprofile = \"px4\"\nready_after_s = 0.0\ngps_fix_after_s = 0.0\n",
        "test",
    )
    .expect("scenario");
    start_with(cfg).await
}

/// What `pick` reads from the last message it reads anything from, over the next `over` of sim time.
async fn last_sent<T>(
    sim: &sitl::SimHandle,
    gcs: &mut Gcs,
    over: Duration,
    pick: impl Fn(&MavMessage) -> Option<T>,
) -> Option<T> {
    sent_over(sim, gcs, over).await.iter().rev().find_map(pick)
}

async fn estimator_flags(sim: &sitl::SimHandle, gcs: &mut Gcs) -> EstimatorStatusFlags {
    last_sent(sim, gcs, Duration::from_secs(2), |m| match m {
        MavMessage::ESTIMATOR_STATUS(e) => Some(e.flags),
        _ => None,
    })
    .await
    .expect("ESTIMATOR_STATUS on the PX4 profile")
}

async fn heartbeat_mode(sim: &sitl::SimHandle, gcs: &mut Gcs) -> u32 {
    last_sent(sim, gcs, Duration::from_millis(1_100), |m| match m {
        MavMessage::HEARTBEAT(h) => Some(h.custom_mode),
        _ => None,
    })
    .await
    .expect("a HEARTBEAT")
}

#[tokio::test]
async fn at_rest_on_the_ground_the_estimator_says_constant_position_with_its_absolute_one() {
    let (sim, mut gcs) = px4_copter().await;
    let abs = EstimatorStatusFlags::ESTIMATOR_POS_HORIZ_ABS;
    let fused = EstimatorStatusFlags::ESTIMATOR_PRED_POS_HORIZ_ABS;
    let constant = EstimatorStatusFlags::ESTIMATOR_CONST_POS_MODE;
    let on_ground = estimator_flags(&sim, &mut gcs).await;
    assert!(on_ground.contains(abs | fused | constant), "{on_ground:?}");
    // Airborne: no longer at rest.
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let r = gcs
        .command(
            MavCmd::MAV_CMD_NAV_TAKEOFF,
            &[0.0, 0.0, 0.0, f32::NAN, f32::NAN, f32::NAN, 10.0],
        )
        .await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    run_until(&sim, 60, |s| -s.depth_m > 5.0).await;
    let flying = estimator_flags(&sim, &mut gcs).await;
    assert!(flying.contains(abs | fused), "{flying:?}");
    assert!(!flying.contains(constant), "{flying:?}");
}

#[tokio::test]
async fn takeoff_is_px4s_own_mode_then_it_loiters_by_itself_and_a_landing_hands_back_hold() {
    let (sim, mut gcs) = px4_copter().await;
    assert_eq!(heartbeat_mode(&sim, &mut gcs).await, HOLD);
    // Disarmed: refused for now.
    let takeoff = [0.0, 0.0, 0.0, f32::NAN, f32::NAN, f32::NAN, 12.0];
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_NAV_TAKEOFF, &takeoff).await,
        MavResult::MAV_RESULT_TEMPORARILY_REJECTED
    );
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    // COMMAND_INT in PX4's frame only; p7 AMSL (the sim's home is at 0 m).
    let (r, _) = gcs
        .command_int(MavCmd::MAV_CMD_NAV_TAKEOFF, [0.0; 4], 0, 0, 12.0)
        .await;
    assert_eq!(r, MavResult::MAV_RESULT_COMMAND_UNSUPPORTED_MAV_FRAME);
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_NAV_TAKEOFF, &takeoff).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(heartbeat_mode(&sim, &mut gcs).await, TAKEOFF);
    let up = run_until(&sim, 60, |s| s.custom_mode != TAKEOFF).await;
    assert_eq!(up.custom_mode, HOLD, "AUTO.LOITER once the takeoff is over");
    assert!((-up.depth_m - 12.0).abs() < 0.5, "{}", up.depth_m);
    assert!(up.armed);
    // AUTO.LAND: down, disarmed, and back in Hold.
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_DO_SET_MODE, &[1.0, 4.0, 6.0])
            .await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(heartbeat_mode(&sim, &mut gcs).await, LAND);
    let down = run_until(&sim, 120, |s| !s.armed).await;
    assert_eq!(down.custom_mode, HOLD);
    assert!(-down.depth_m < 0.1, "{}", down.depth_m);
}

#[tokio::test]
async fn a_takeoff_without_an_altitude_goes_to_mis_takeoff_alt() {
    let (sim, mut gcs) = px4_copter().await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let r = gcs
        .command(
            MavCmd::MAV_CMD_NAV_TAKEOFF,
            &[0.0, 0.0, 0.0, f32::NAN, f32::NAN, f32::NAN, f32::NAN],
        )
        .await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    let up = run_until(&sim, 60, |s| s.custom_mode == HOLD).await;
    assert!((-up.depth_m - 2.5).abs() < 0.3, "{}", up.depth_m);
}
