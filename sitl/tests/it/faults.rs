//! Each fault kind of a scenario file, observed over a socket (and on the ground-truth snapshot).
#![allow(deprecated)]

use std::time::Duration;

use crate::support::*;
use mavlink::dialects::ardupilotmega::*;

const STEP: Duration = Duration::from_millis(100);

/// A sim (as [`start`]) whose scenario has the one fault `fault` (inline-table body), injected `when`.
async fn start_with_fault(when: &str, fault: &str) -> (sitl::SimHandle, Gcs) {
    start(&format!(
        "[[faults]]\nwhen = {{ {when} }}\nfault = {{ {fault} }}\n"
    ))
    .await
}

#[tokio::test]
async fn command_fails_answers_the_injected_result_then_recovers() {
    let (sim, mut gcs) = start(
        r#"[[faults]]
when = { at_s = 0.0 }
fault = { kind = "command_fails", command = 400, result = "failed" }
[[faults]]
when = { on = "mode_changed", value = 15 }
fault = { kind = "command_fails", command = 192, result = "denied", count = 2 }
"#,
    )
    .await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_FAILED);
    assert!(Gcs::texts(&gcs.sync().await)
        .iter()
        .any(|t| t == "Command 400 refused (injected fault)"));
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(gcs.set_mode(15).await, MavResult::MAV_RESULT_ACCEPTED);
    let wp = waypoint(HOME, 10.0, 0.0);
    for expected in [
        MavResult::MAV_RESULT_DENIED,
        MavResult::MAV_RESULT_DENIED,
        MavResult::MAV_RESULT_ACCEPTED,
    ] {
        let (r, _) = gcs.reposition(&wp, false, 0.0).await;
        assert_eq!(r, expected);
    }
    assert!(sim.snapshot().armed);
}

fn captures(msgs: &[MavMessage]) -> Vec<(i32, bool)> {
    msgs.iter()
        .filter_map(|m| match m {
            MavMessage::CAMERA_IMAGE_CAPTURED(c) => {
                Some((c.image_index, c.capture_result == MavBool::MAV_BOOL_TRUE))
            }
            _ => None,
        })
        .collect()
}

#[tokio::test]
async fn picture_fails_on_the_first_picture_only() {
    let (sim, mut gcs) = start_with_fault(
        r#"on = "picture_started", value = 0"#,
        r#"kind = "picture_fails""#,
    )
    .await;
    capture(&mut gcs).await;
    sim.step(Duration::from_secs(2)).await.expect("step");
    capture(&mut gcs).await;
    sim.step(Duration::from_secs(2)).await.expect("step");
    let seen = gcs.sync().await;
    assert_eq!(captures(&seen), vec![(0, false), (1, true)]);
    assert!(Gcs::texts(&seen)
        .iter()
        .any(|t| t == "Camera: capture failed"));
    let s = sim.snapshot();
    assert_eq!((s.pictures_ok, s.pictures_failed), (1, 1));
    assert!(
        (2.0..=4.0).contains(&s.storage_used_mib),
        "{}",
        s.storage_used_mib
    );
}

#[tokio::test]
async fn a_slow_zone_appears_and_caps_the_speed() {
    let (sim, mut gcs) = start_with_fault(
        "at_s = 1.0",
        r#"kind = "slow_zone", zone = { center_m = [30.0, 0.0], radius_m = 20.0, speed_factor = 0.2 }"#,
    )
    .await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let wp = waypoint(HOME, 60.0, 0.0);
    let (r, _) = gcs.reposition(&wp, true, 0.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    let before = run_until(&sim, 30, |s| s.north_m > 5.0).await;
    assert!(
        before.speed_mps > 3.0,
        "full speed before the zone: {}",
        before.speed_mps
    );
    // Deep inside the zone, after braking: 5 m/s x 0.2.
    let inside = run_until(&sim, 60, |s| s.north_m > 25.0).await;
    assert!(inside.speed_mps <= 1.0 + 1e-6, "{}", inside.speed_mps);
}

#[tokio::test]
async fn battery_drops_when_the_vehicle_starts_moving() {
    let (sim, mut gcs) = start_with_fault(
        r#"on = "moving""#,
        r#"kind = "battery_drop", percent = 40.0"#,
    )
    .await;
    sim.step(Duration::from_secs(2)).await.expect("step");
    let still = sim.snapshot().battery_pct;
    assert!(still > 97.0);
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let wp = waypoint(HOME, 30.0, 0.0);
    gcs.reposition(&wp, true, 0.0).await;
    let s = run_until(&sim, 10, |s| s.speed_mps > 0.0).await;
    assert!(
        s.battery_pct < still - 39.0,
        "{} -> {}",
        still,
        s.battery_pct
    );
    gcs.drain();
    sim.step(Duration::from_secs(1)).await.expect("step");
    let pct = expect_msg!(gcs, BATTERY_STATUS).await.battery_remaining;
    assert!(pct <= 59, "{pct}");
}

#[tokio::test]
async fn storage_capacity_shrinks() {
    let (sim, mut gcs) = start(
        r#"[camera]
storage_capacity_mib = 12.0
[[faults]]
when = { at_s = 1.0 }
fault = { kind = "storage_shrink", mib = 5.0 }
"#,
    )
    .await;
    sim.step(Duration::from_secs(2)).await.expect("step");
    gcs.request_message(261).await;
    let total = expect_msg!(gcs, STORAGE_INFORMATION).await.total_capacity;
    assert_eq!(total, 7.0);
}

#[tokio::test]
async fn navigation_fails_with_no_map_stops_and_refuses_auto_for_a_while() {
    let (sim, mut gcs) = start_with_fault(
        r#"on = "waypoint_reached", value = 1"#,
        r#"kind = "nav_fails", duration_s = 5.0"#,
    )
    .await;
    let items = vec![
        waypoint(HOME, 0.0, 0.0),
        waypoint(HOME, 15.0, 0.0),
        waypoint(HOME, 15.0, 30.0),
    ];
    upload_ok(&mut gcs, &items).await;
    gcs.arm().await;
    assert_eq!(gcs.set_mode(10).await, MavResult::MAV_RESULT_ACCEPTED);
    let failed = run_until(&sim, 60, |s| s.mode == "HOLD").await;
    assert!(failed.statustexts.iter().any(|t| t == sitl::NAV_FAIL_TEXT));
    let stopped = run_until(&sim, 10, |s| s.speed_mps < 0.01).await;
    sim.step(Duration::from_secs(1)).await.expect("step");
    assert!(
        (sim.snapshot().distance_m - stopped.distance_m).abs() < 0.01,
        "still moving"
    );
    assert_eq!(gcs.set_mode(10).await, MavResult::MAV_RESULT_FAILED);
    sim.step(Duration::from_secs(5)).await.expect("step");
    assert_eq!(gcs.set_mode(10).await, MavResult::MAV_RESULT_ACCEPTED);
    let done = run_until(&sim, 60, |s| s.mission_complete).await;
    assert!((done.east_m - 30.0).abs() < 3.5);
}

#[tokio::test]
async fn a_foreign_mode_change_holds_the_rover_mid_mission() {
    let (sim, mut gcs) = start_with_fault(
        r#"on = "moving", delay_s = 3.0"#,
        r#"kind = "mode_change", mode = 4"#,
    )
    .await;
    let items = vec![waypoint(HOME, 0.0, 0.0), waypoint(HOME, 40.0, 0.0)];
    upload_ok(&mut gcs, &items).await;
    gcs.arm().await;
    assert_eq!(gcs.set_mode(10).await, MavResult::MAV_RESULT_ACCEPTED);
    let held = run_until(&sim, 30, |s| s.mode == "HOLD").await;
    assert!(
        held.distance_m > 1.0 && held.distance_m < 30.0,
        "{}",
        held.distance_m
    );
    let stopped = run_until(&sim, 10, |s| s.speed_mps < 0.01).await;
    assert!(!stopped.mission_complete);
    assert!(stopped.armed, "a mode change does not disarm");
}

fn boot_times(msgs: &[MavMessage]) -> Vec<u32> {
    msgs.iter()
        .filter_map(|m| match m {
            MavMessage::SYSTEM_TIME(t) => Some(t.time_boot_ms),
            _ => None,
        })
        .collect()
}

#[tokio::test]
async fn link_blackout_silences_both_directions_for_its_duration() {
    let (sim, mut gcs) =
        start_with_fault("at_s = 2.0", r#"kind = "link_blackout", duration_s = 3.0"#).await;
    sim.step(Duration::from_millis(2500)).await.expect("step");
    assert!(sim.snapshot().link_blackout);
    // Sent in the blackout: lost.
    gcs.send_arm_to(1).await;
    for _ in 0..45 {
        sim.step(STEP).await.expect("step");
    }
    assert!(!sim.snapshot().link_blackout);
    let seen = gcs.sync().await;
    let times = boot_times(&seen);
    assert!(
        times.iter().any(|&t| t < 2000) && times.iter().any(|&t| t >= 5000),
        "{times:?}"
    );
    assert!(
        times.iter().all(|&t| !(2000..5000).contains(&t)),
        "{times:?}"
    );
    assert!(!seen.iter().any(|m| matches!(m, MavMessage::COMMAND_ACK(a) if a.command == MavCmd::MAV_CMD_COMPONENT_ARM_DISARM)));
    assert!(!sim.snapshot().armed);
    assert!(sim.snapshot().frames_dropped > 0);
}

#[tokio::test]
async fn link_loss_drops_frames_for_its_duration() {
    let (sim, mut gcs) = start_with_fault(
        "at_s = 1.0",
        r#"kind = "link_quality", loss = 1.0, duration_s = 2.0"#,
    )
    .await;
    for _ in 0..40 {
        sim.step(STEP).await.expect("step");
    }
    let times = boot_times(&gcs.sync().await);
    assert!(
        times.iter().all(|&t| !(1000..3000).contains(&t)),
        "{times:?}"
    );
    assert!(times.iter().any(|&t| t >= 3000), "{times:?}");
}

#[tokio::test]
async fn link_duplication_sends_every_frame_twice() {
    let (sim, mut gcs) =
        start_with_fault("at_s = 0.0", r#"kind = "link_quality", duplicate = 1.0"#).await;
    sim.step(Duration::from_secs(3)).await.expect("step");
    let times = boot_times(&gcs.sync().await);
    assert!(
        times.len() >= 4 && times.len().is_multiple_of(2),
        "{times:?}"
    );
    for pair in times.chunks(2) {
        assert_eq!(pair[0], pair[1], "{times:?}");
    }
}

#[tokio::test]
async fn link_reordering_swaps_frames() {
    let (sim, mut gcs) =
        start_with_fault("at_s = 0.0", r#"kind = "link_quality", reorder = 1.0"#).await;
    sim.step(Duration::from_secs(5)).await.expect("step");
    // Inbound frames are reordered too: this one is held back, and overtaken by the sync's command.
    gcs.send(MavMessage::HEARTBEAT(HEARTBEAT_DATA::default()))
        .await;
    let seqs: Vec<u8> = gcs
        .sync_frames()
        .await
        .iter()
        .map(|f| f.1.sequence)
        .collect();
    assert!(seqs.len() >= 10, "{seqs:?}");
    assert!(
        seqs.windows(2).any(|w| w[1] != w[0].wrapping_add(1)),
        "in order: {seqs:?}"
    );
    let mut sorted = seqs.clone();
    sorted.sort_unstable();
    sorted.dedup();
    assert_eq!(
        sorted.len(),
        seqs.len(),
        "frames lost or duplicated: {seqs:?}"
    );
}

#[tokio::test]
async fn downlink_runs_in_visibility_windows_at_the_injected_rate() {
    let (sim, mut gcs) = start(
        r#"[[visibility_windows]]
start_s = 5.0
end_s = 30.0
rate_mib_per_s = 0.5
[[faults]]
when = { on = "downlink_started", occurrence = 1 }
fault = { kind = "downlink_rate", mib_per_s = 0.1 }
"#,
    )
    .await;
    capture(&mut gcs).await;
    sim.step(Duration::from_secs(2)).await.expect("step");
    let stored = sim.snapshot().storage_used_mib;
    assert!(stored >= 2.0);
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_USER_1, &[1.0]).await,
        MavResult::MAV_RESULT_DENIED,
        "no visibility before 5 s"
    );
    sim.step(Duration::from_secs(4)).await.expect("step");
    let (r, p) = gcs
        .command_long(MavCmd::MAV_CMD_USER_1, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        .await;
    assert_eq!((r, p), (MavResult::MAV_RESULT_IN_PROGRESS, 0));
    let t0 = sim.now_ms();
    sim.step(Duration::from_secs(10)).await.expect("step");
    let s = sim.snapshot();
    let sent = stored - s.storage_used_mib;
    let expected = 0.1 * (s.time_ms - t0) as f64 / 1000.0;
    assert!(
        (sent - expected).abs() < 0.05,
        "sent {sent}, expected {expected}"
    );
    assert!(s.downlink_active);
    // Progress reports, then FAILED when the window closes at 30 s with data left.
    sim.step(Duration::from_secs(20)).await.expect("step");
    let seen = gcs.sync().await;
    let acks: Vec<(MavResult, u8)> = seen
        .iter()
        .filter_map(|m| match m {
            MavMessage::COMMAND_ACK(a) if a.command == MavCmd::MAV_CMD_USER_1 => {
                Some((a.result, a.progress))
            }
            _ => None,
        })
        .collect();
    assert!(
        acks.iter()
            .any(|(r, p)| *r == MavResult::MAV_RESULT_IN_PROGRESS && *p > 0),
        "{acks:?}"
    );
    assert_eq!(
        acks.last().map(|a| a.0),
        Some(MavResult::MAV_RESULT_FAILED),
        "{acks:?}"
    );
    assert!(!sim.snapshot().downlink_active);
}

#[tokio::test]
async fn injected_faults_apply_at_once() {
    let (sim, mut gcs) = start("").await;
    sim.inject(sitl::Fault::BatteryDrop { percent: 50.0 })
        .expect("inject");
    sim.step(STEP).await.expect("step");
    assert!(sim.snapshot().battery_pct < 50.0);
    assert_eq!(
        gcs.arm().await,
        MavResult::MAV_RESULT_ACCEPTED,
        "48% still arms"
    );
}

#[tokio::test]
async fn reboot_goes_silent_then_boots_disarmed_in_manual_where_it_stood() {
    let (sim, mut gcs) = start_with_fault("at_s = 5.0", r#"kind = "reboot", silent_s = 3.0"#).await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let (r, _) = gcs.reposition(&waypoint(HOME, 30.0, 0.0), true, 0.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    let moving = run_until(&sim, 10, |s| s.time_ms >= 4_900).await;
    assert!(moving.armed && moving.speed_mps > 0.1, "{moving:?}");
    let down = run_until(&sim, 10, |s| s.time_ms >= 5_100).await;
    assert!(down.link_blackout && !down.armed, "{down:?}");
    assert_eq!(down.mode, "MANUAL");
    let halted = run_until(&sim, 10, |s| s.time_ms >= 9_000).await;
    let up = run_until(&sim, 10, |s| s.time_ms >= 10_000).await;
    assert!(!up.link_blackout && !up.armed, "{up:?}");
    // Disarmed, it coasted to a halt and stays where it stopped, short of the target.
    assert!(up.speed_mps < 0.01, "{up:?}");
    assert!(
        (up.north_m - halted.north_m).abs() < 0.01,
        "{halted:?} {up:?}"
    );
    assert!(up.north_m > moving.north_m && up.north_m < 29.0, "{up:?}");
    gcs.drain();
    sim.step(Duration::from_millis(1_500)).await.expect("step");
    let msgs = gcs.sync().await;
    let clock: Vec<u32> = msgs
        .iter()
        .filter_map(|m| match m {
            MavMessage::SYSTEM_TIME(t) => Some(t.time_boot_ms),
            MavMessage::GLOBAL_POSITION_INT(p) => Some(p.time_boot_ms),
            _ => None,
        })
        .collect();
    assert!(
        !clock.is_empty() && clock.iter().all(|&t| t < 4_000),
        "time_boot_ms from 0 again: {clock:?}"
    );
    // Re-armed and moving again on the same commands.
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let (r, _) = gcs.reposition(&waypoint(HOME, 30.0, 0.0), true, 0.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    run_until(&sim, 120, |s| s.north_m > 29.0).await;
}

/// IMAGE_START_CAPTURE of one picture with `confirmation` (0: a new request, 1: a re-send); it must be
/// accepted.
async fn send_capture(gcs: &mut Gcs, confirmation: u8) {
    gcs.send(MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
        param1: 1.0,
        param3: 1.0,
        command: MavCmd::MAV_CMD_IMAGE_START_CAPTURE,
        target_system: 1,
        target_component: 1,
        confirmation,
        ..Default::default()
    }))
    .await;
    assert_eq!(
        gcs.ack_of(MavCmd::MAV_CMD_IMAGE_START_CAPTURE).await.0,
        MavResult::MAV_RESULT_ACCEPTED,
        "confirmation {confirmation}"
    );
}

#[tokio::test]
async fn a_resent_capture_is_answered_again_not_taken_twice() {
    let (sim, mut gcs) = start("").await;
    send_capture(&mut gcs, 0).await;
    // Its ACK was lost, say: the companion sends it again with confirmation 1.
    send_capture(&mut gcs, 1).await;
    let s = run_until(&sim, 30, |s| s.pictures_ok + s.pictures_failed > 0).await;
    run_until(&sim, 30, |x| x.time_ms >= s.time_ms + 15_000).await;
    assert_eq!(sim.snapshot().pictures_ok, 1, "one picture, not two");
    // A new request (confirmation 0) is a new picture.
    send_capture(&mut gcs, 0).await;
    let s = run_until(&sim, 30, |s| s.pictures_ok == 2).await;
    // Long after, the same request re-sent (its first copy lost on the way) is a new picture too.
    run_until(&sim, 30, |x| x.time_ms >= s.time_ms + 20_000).await;
    send_capture(&mut gcs, 1).await;
    run_until(&sim, 30, |s| s.pictures_ok == 3).await;
}
