//! The `[autopilot] profile = "px4"` behaviours over a real socket, on the manual clock: what a real PX4
//! (main, SIH rover) answers and refuses where ArduPilot would not (sitl/src/autopilot/px4.rs names the PX4
//! sources): COMMAND_INT frames, DO_REPOSITION's change-mode bit, arming rejected after boot with its
//! pre-arm bit in SYS_STATUS, no EKF_STATUS_REPORT but ESTIMATOR_STATUS, its custom modes, no camera.
#![allow(deprecated)]

use std::time::Duration;

use crate::support::*;
use mavlink::dialects::ardupilotmega::*;

const PX4: &str = "[autopilot]\nprofile = \"px4\"\n";
/// The PX4 profile with the boot delays off, for tests about something else.
const PX4_READY: &str =
    "[autopilot]\nprofile = \"px4\"\nready_after_s = 0.0\ngps_fix_after_s = 0.0\n";

/// PX4's custom_mode for main/sub (px4_custom_mode.h).
fn px4_mode(main: u32, sub: u32) -> u32 {
    (main << 16) | (sub << 24)
}

const HOLD: (u32, u32) = (4, 3);

async fn set_px4_mode(gcs: &mut Gcs, (main, sub): (u32, u32)) -> MavResult {
    gcs.command(MavCmd::MAV_CMD_DO_SET_MODE, &[1.0, main as f32, sub as f32])
        .await
}

/// The last HEARTBEAT among `msgs`.
fn last_heartbeat(msgs: &[MavMessage]) -> HEARTBEAT_DATA {
    msgs.iter()
        .rev()
        .find_map(|m| match m {
            MavMessage::HEARTBEAT(h) => Some(h.clone()),
            _ => None,
        })
        .expect("a HEARTBEAT")
}

/// What the sim streams over the next 2 s.
async fn streamed(sim: &sitl::SimHandle, gcs: &mut Gcs) -> Vec<MavMessage> {
    sent_over(sim, gcs, Duration::from_secs(2)).await
}

async fn reposition_in(gcs: &mut Gcs, frame: MavFrame, north: f64, flags: f32) -> MavResult {
    let wp = waypoint(HOME, north, 0.0);
    gcs.command_int_in(
        frame,
        MavCmd::MAV_CMD_DO_REPOSITION,
        [-1.0, flags, 0.0, f32::NAN],
        (wp.x, wp.y, 10.0),
    )
    .await
    .0
}

#[tokio::test]
async fn command_int_needs_global_int_and_reposition_its_change_mode_bit() {
    let (sim, mut gcs) = start(PX4_READY).await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    // Frame 0 (MAV_FRAME_GLOBAL), as the companion sent it to ArduPilot: PX4 answers 9 and does nothing.
    let r = reposition_in(&mut gcs, MavFrame::MAV_FRAME_GLOBAL, 30.0, 1.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_COMMAND_UNSUPPORTED_MAV_FRAME);
    assert_eq!(r as u32, 9);
    let r = reposition_in(
        &mut gcs,
        MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT,
        30.0,
        1.0,
    )
    .await;
    assert_eq!(r, MavResult::MAV_RESULT_COMMAND_UNSUPPORTED_MAV_FRAME);
    // Without the change-mode bit: UNSUPPORTED.
    let r = reposition_in(&mut gcs, MavFrame::MAV_FRAME_GLOBAL_INT, 30.0, 0.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_UNSUPPORTED);
    sim.step(Duration::from_secs(3)).await.expect("step");
    assert!(sim.snapshot().distance_m < 0.01, "{:?}", sim.snapshot());
    // GLOBAL_INT with the bit: Hold (AUTO/LOITER) and on its way.
    let r = reposition_in(&mut gcs, MavFrame::MAV_FRAME_GLOBAL_INT, 30.0, 1.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    let s = run_until(&sim, 120, |s| s.north_m > 28.0).await;
    assert_eq!(s.custom_mode, px4_mode(4, 3));
}

#[tokio::test]
async fn a_reposition_disarmed_changes_the_mode_and_sets_no_target() {
    let (sim, mut gcs) = start(PX4_READY).await;
    let r = reposition_in(&mut gcs, MavFrame::MAV_FRAME_GLOBAL_INT, 30.0, 1.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    sim.step(Duration::from_secs(10)).await.expect("step");
    let s = sim.snapshot();
    assert_eq!(s.custom_mode, px4_mode(4, 3));
    assert!(s.distance_m < 0.01, "drove to a target set disarmed: {s:?}");
}

#[tokio::test]
async fn arming_is_rejected_until_the_checks_pass_and_sys_status_tells_it() {
    let (sim, mut gcs) = start(PX4).await;
    sim.step(Duration::from_secs(1)).await.expect("step");
    let seen = streamed(&sim, &mut gcs).await;
    // PX4 SIH's rover boots in Hold (AUTO/LOITER).
    assert_eq!(last_heartbeat(&seen).custom_mode, px4_mode(4, 3));
    let prearm = |msgs: &[MavMessage]| {
        msgs.iter()
            .rev()
            .find_map(|m| match m {
                MavMessage::SYS_STATUS(s) => Some(
                    s.onboard_control_sensors_health
                        .contains(MavSysStatusSensor::MAV_SYS_STATUS_PREARM_CHECK),
                ),
                _ => None,
            })
            .expect("a SYS_STATUS")
    };
    assert!(!prearm(&seen));
    let r = gcs.arm().await;
    assert_eq!(r, MavResult::MAV_RESULT_TEMPORARILY_REJECTED);
    let texts = Gcs::texts_with_severity(&gcs.sync().await);
    assert!(texts
        .iter()
        .all(|(s, _)| *s == MavSeverity::MAV_SEVERITY_CRITICAL));
    let said: Vec<&str> = texts.iter().map(|(_, t)| t.as_str()).collect();
    // The second text is 51 characters: two STATUSTEXT chunks.
    assert_eq!(
        said,
        [
            "Preflight Fail: heading estimate not stable",
            "Arming denied: Resolve system health failures firs",
            "t"
        ]
    );
    assert!(!sim.snapshot().armed);
    let s = run_until(&sim, 60, |_| true).await;
    let ready_ms = 5_000;
    sim.step(Duration::from_millis(ready_ms - s.time_ms))
        .await
        .expect("step");
    let seen = streamed(&sim, &mut gcs).await;
    assert!(prearm(&seen));
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    assert!(sim.snapshot().armed);
    let h = last_heartbeat(&gcs.sync().await);
    assert_eq!(h.autopilot, MavAutopilot::MAV_AUTOPILOT_PX4);
}

#[tokio::test]
async fn ekf_status_report_is_denied_and_estimator_status_streams() {
    let (sim, mut gcs) = start(PX4).await;
    assert_eq!(
        gcs.request_message(193).await,
        MavResult::MAV_RESULT_DENIED,
        "EKF_STATUS_REPORT"
    );
    assert_eq!(
        gcs.request_message(180).await,
        MavResult::MAV_RESULT_DENIED,
        "CAMERA_FEEDBACK"
    );
    let flags = |msgs: &[MavMessage]| {
        msgs.iter()
            .rev()
            .find_map(|m| match m {
                MavMessage::ESTIMATOR_STATUS(e) => Some(e.flags),
                _ => None,
            })
            .expect("an ESTIMATOR_STATUS")
    };
    let before = flags(&sent_over(&sim, &mut gcs, Duration::from_millis(1_500)).await);
    assert!(before.contains(EstimatorStatusFlags::ESTIMATOR_CONST_POS_MODE));
    assert!(!before.contains(EstimatorStatusFlags::ESTIMATOR_POS_HORIZ_ABS));
    // No home before the fix: nothing to send, DENIED (ArduPilot accepts and sends nothing).
    assert_eq!(gcs.request_message(242).await, MavResult::MAV_RESULT_DENIED);
    sim.step(Duration::from_secs(1)).await.expect("step");
    // Disarmed, the rover is "landed" and at rest (RoverLandDetector: landed = !armed): EKF2 says
    // CONST_POS_MODE with its absolute position, GNSS fused (PRED_POS_HORIZ_ABS).
    let at_rest = flags(&streamed(&sim, &mut gcs).await);
    assert!(at_rest.contains(
        EstimatorStatusFlags::ESTIMATOR_POS_HORIZ_ABS
            | EstimatorStatusFlags::ESTIMATOR_PRED_POS_HORIZ_ABS
            | EstimatorStatusFlags::ESTIMATOR_CONST_POS_MODE
    ));
    assert_eq!(
        gcs.request_message(242).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    // Armed once the pre-arm checks pass (the profile's 5 s after boot).
    sim.step(Duration::from_secs(5)).await.expect("step");
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let armed = flags(&streamed(&sim, &mut gcs).await);
    assert!(armed.contains(EstimatorStatusFlags::ESTIMATOR_POS_HORIZ_ABS));
    assert!(!armed.contains(EstimatorStatusFlags::ESTIMATOR_CONST_POS_MODE));
}

#[tokio::test]
async fn modes_are_px4_custom_modes_and_hold_is_loiter() {
    let (sim, mut gcs) = start(PX4).await;
    // Before the fix a mode that needs a position is rejected for now, with PX4's words.
    assert_eq!(
        set_px4_mode(&mut gcs, (4, 5)).await,
        MavResult::MAV_RESULT_TEMPORARILY_REJECTED
    );
    let texts = Gcs::texts(&gcs.sync().await);
    assert!(
        texts.contains(&"Switching to Return is currently not available".to_string()),
        "{texts:?}"
    );
    sim.step(Duration::from_secs(3)).await.expect("step");
    assert_eq!(
        set_px4_mode(&mut gcs, (1, 0)).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(
        set_px4_mode(&mut gcs, HOLD).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    let h = last_heartbeat(&streamed(&sim, &mut gcs).await);
    assert_eq!(h.custom_mode, px4_mode(4, 3));
    assert_eq!(h.custom_mode, 50_593_792);
    // ArduPilot's GUIDED number in p2 is no PX4 main mode the sim knows: refused.
    assert_eq!(gcs.set_mode(15).await, MavResult::MAV_RESULT_FAILED);
    assert_eq!(
        set_px4_mode(&mut gcs, (1, 0)).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(sim.snapshot().custom_mode, px4_mode(1, 0));
    // AUTO/MISSION with no mission is refused, as ArduPilot's AUTO is.
    assert_ne!(
        set_px4_mode(&mut gcs, (4, 4)).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
}

#[tokio::test]
async fn without_a_camera_component_image_start_capture_is_unsupported() {
    let (sim, mut gcs) = start(PX4_READY).await;
    let r = gcs.image_start_capture([0.0, 0.0, 1.0]).await;
    assert_eq!(r, MavResult::MAV_RESULT_UNSUPPORTED);
    sim.step(Duration::from_secs(3)).await.expect("step");
    assert_eq!(sim.snapshot().pictures_ok, 0);
    // With a MAVLink camera declared (`camera = "mavlink"`), the picture is taken and confirmed.
    let (sim, mut gcs) = start(&format!("{PX4_READY}camera = \"mavlink\"\n")).await;
    let seen = shoot(&sim, &mut gcs, Duration::from_secs(5)).await;
    assert!(seen.iter().any(
        |m| matches!(m, MavMessage::CAMERA_IMAGE_CAPTURED(c) if c.capture_result.bits() == 1)
    ));
}

#[tokio::test]
async fn a_mission_is_flown_from_item_0_with_no_home_item() {
    let (sim, mut gcs) = start(PX4_READY).await;
    // Item 0 is a real waypoint on PX4 (ArduPilot would replace it with home).
    let items = vec![waypoint(HOME, 30.0, 0.0), waypoint(HOME, 30.0, 30.0)];
    assert_eq!(
        gcs.upload(&items).await,
        MavMissionResult::MAV_MISSION_ACCEPTED
    );
    assert_eq!(sim.snapshot().mission_total, 2);
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(
        set_px4_mode(&mut gcs, (4, 4)).await,
        MavResult::MAV_RESULT_ACCEPTED,
        "Mission"
    );
    let s = run_until(&sim, 120, |s| s.mission_complete).await;
    assert!(
        (s.north_m - 30.0).abs() < 3.5 && (s.east_m - 30.0).abs() < 3.5,
        "{s:?}"
    );
    let mut reached = Vec::new();
    while reached.last() != Some(&1) {
        reached.push(expect_msg!(gcs, MISSION_ITEM_REACHED).await.seq);
    }
    assert_eq!(reached, vec![0, 1], "item 0 flown first");
}
