//! Identity, modes, arming and commands over a real socket, with ArduPilot's COMMAND_ACK results.
#![allow(deprecated)]

use std::time::Duration;

use crate::support::*;
use mavlink::dialects::ardupilotmega::*;
use mavlink::MavlinkVersion;

#[tokio::test]
async fn heartbeat_identifies_an_ardupilot_rover() {
    let (sim, mut gcs) = start("").await;
    sim.step(Duration::from_secs(1)).await.expect("step");
    let hb = expect_msg!(gcs, HEARTBEAT).await;
    assert_eq!(hb.mavtype, MavType::MAV_TYPE_GROUND_ROVER);
    assert_eq!(hb.autopilot, MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA);
    assert_eq!(hb.custom_mode, 0);
    assert_eq!(
        hb.base_mode.bits(),
        65,
        "MANUAL disarmed as observed on ArduPilot"
    );
    assert_eq!(
        gcs.last_header.map(|h| (h.system_id, h.component_id)),
        Some((1, 1))
    );
}

#[tokio::test]
async fn auv_heartbeat_is_a_submarine_with_ardusub_modes() {
    let mut cfg = sitl::SimConfig::for_tests();
    cfg.vehicle = sitl::VehicleKind::Auv;
    let (sim, mut gcs) = start_with(cfg).await;
    assert_eq!(gcs.set_mode(4).await, MavResult::MAV_RESULT_ACCEPTED);
    let hb = expect_msg!(gcs, HEARTBEAT).await;
    assert_eq!(hb.mavtype, MavType::MAV_TYPE_SUBMARINE);
    assert_eq!(hb.custom_mode, 4);
    assert_eq!(sim.snapshot().mode, "GUIDED");
}

#[tokio::test]
async fn arming_is_refused_when_the_battery_is_low_unless_forced() {
    let (sim, mut gcs) = start("[battery]\ninitial_pct = 10.0\n").await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_FAILED);
    let texts = gcs.sync().await;
    assert!(texts.iter().any(|m| matches!(m, MavMessage::STATUSTEXT(t)
        if t.text.to_str().unwrap_or("").starts_with("PreArm: Battery"))));
    assert!(!sim.snapshot().armed);
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, &[1.0, 21196.0])
            .await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert!(sim.snapshot().armed);
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, &[]).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert!(!sim.snapshot().armed);
}

#[tokio::test]
async fn modes_follow_rover_numbering_and_auto_needs_a_mission() {
    let (sim, mut gcs) = start("").await;
    assert_eq!(gcs.set_mode(10).await, MavResult::MAV_RESULT_FAILED);
    let seen = gcs.sync().await;
    assert!(seen.iter().any(|m| matches!(m, MavMessage::STATUSTEXT(t)
        if t.text.to_str().unwrap_or("") == "No Mission. Can't set AUTO.")));
    for (n, name) in [(4, "HOLD"), (15, "GUIDED"), (11, "RTL"), (0, "MANUAL")] {
        assert_eq!(gcs.set_mode(n).await, MavResult::MAV_RESULT_ACCEPTED);
        assert_eq!(sim.snapshot().mode, name);
    }
    assert_eq!(gcs.set_mode(7).await, MavResult::MAV_RESULT_FAILED);
    // Legacy SET_MODE is acknowledged as DO_SET_MODE.
    gcs.send(MavMessage::SET_MODE(SET_MODE_DATA {
        custom_mode: 4,
        target_system: 1,
        base_mode: MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED,
    }))
    .await;
    assert_eq!(
        gcs.ack_of(MavCmd::MAV_CMD_DO_SET_MODE).await.0,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(sim.snapshot().mode, "HOLD");
}

#[tokio::test]
async fn unknown_commands_are_unsupported() {
    let (_sim, mut gcs) = start("").await;
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_DO_PARACHUTE, &[]).await,
        MavResult::MAV_RESULT_UNSUPPORTED
    );
}

#[tokio::test]
async fn reposition_needs_command_int_and_the_mode_bit_outside_guided() {
    let (sim, mut gcs) = start("").await;
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_DO_REPOSITION, &[]).await,
        MavResult::MAV_RESULT_COMMAND_INT_ONLY
    );
    let target = waypoint(HOME, 20.0, 10.0);
    let (r, _) = gcs.reposition(&target, false, 0.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_DENIED);
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let (r, _) = gcs.reposition(&target, true, 0.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(sim.snapshot().mode, "GUIDED");
    let s = run_until(&sim, 60, |s| {
        ((s.north_m - 20.0).powi(2) + (s.east_m - 10.0).powi(2)).sqrt() < 0.5 && s.speed_mps < 0.05
    })
    .await;
    assert_eq!(s.mode, "GUIDED");
}

#[tokio::test]
async fn set_position_target_is_ignored_outside_guided() {
    let (sim, mut gcs) = start("").await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let target = waypoint(HOME, -15.0, 0.0);
    let spt = MavMessage::SET_POSITION_TARGET_GLOBAL_INT(SET_POSITION_TARGET_GLOBAL_INT_DATA {
        lat_int: target.x,
        lon_int: target.y,
        target_system: 1,
        target_component: 1,
        coordinate_frame: MavFrame::MAV_FRAME_GLOBAL,
        type_mask: PositionTargetTypemask::from_bits_truncate(0b0000_1111_1111_1000),
        ..Default::default()
    });
    gcs.send(spt.clone()).await;
    gcs.sync().await;
    sim.step(Duration::from_secs(5)).await.expect("step");
    assert!(sim.snapshot().distance_m < 0.01, "moved in MANUAL");
    assert_eq!(gcs.set_mode(15).await, MavResult::MAV_RESULT_ACCEPTED);
    gcs.send(spt).await;
    gcs.sync().await;
    run_until(&sim, 60, |s| {
        (s.north_m + 15.0).abs() < 1.0 && s.east_m.abs() < 1.0
    })
    .await;
}

/// How many GLOBAL_POSITION_INTs `seen` holds.
fn positions(seen: &[MavMessage]) -> usize {
    seen.iter()
        .filter(|m| matches!(m, MavMessage::GLOBAL_POSITION_INT(_)))
        .count()
}

#[tokio::test]
async fn message_intervals_and_data_streams_are_honoured_in_sim_time() {
    let (sim, mut gcs) = start("").await;
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL, &[33.0, 100_000.0])
            .await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    let seen = sent_over(&sim, &mut gcs, Duration::from_secs(2)).await;
    let gpi = positions(&seen);
    assert!(
        (19..=21).contains(&gpi),
        "{gpi} GLOBAL_POSITION_INT in 2 s at 10 Hz"
    );
    // Stop everything with REQUEST_DATA_STREAM(ALL, stop).
    gcs.stop_all_streams().await;
    let seen = sent_over(&sim, &mut gcs, Duration::from_secs(3)).await;
    assert!(
        !seen.iter().any(|m| matches!(m, MavMessage::SYS_STATUS(_))),
        "SYS_STATUS still streamed"
    );
    // POSITION stream at 2 Hz.
    gcs.send(MavMessage::REQUEST_DATA_STREAM(REQUEST_DATA_STREAM_DATA {
        req_message_rate: 2,
        target_system: 1,
        target_component: 1,
        req_stream_id: MavDataStream::MAV_DATA_STREAM_POSITION,
        start_stop: 1,
    }))
    .await;
    let seen = sent_over(&sim, &mut gcs, Duration::from_secs(3)).await;
    let gpi = positions(&seen);
    assert!((5..=7).contains(&gpi), "{gpi}");
}

#[tokio::test]
async fn request_message_sends_storage_information_and_time_matches_the_clock() {
    let (sim, mut gcs) = start("[camera]\nstorage_capacity_mib = 9.5\n").await;
    assert_eq!(
        gcs.request_message(261).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    let si = expect_msg!(gcs, STORAGE_INFORMATION).await;
    assert_eq!(si.total_capacity, 9.5);
    assert_eq!(si.used_capacity, 0.0);
    assert_eq!(
        gcs.request_message(9999).await,
        MavResult::MAV_RESULT_UNSUPPORTED
    );
    sim.step(Duration::from_millis(2500)).await.expect("step");
    let now = sim.now_ms();
    gcs.sync().await; // forget the streamed SYSTEM_TIMEs
    assert_eq!(gcs.request_message(2).await, MavResult::MAV_RESULT_ACCEPTED);
    let st = expect_msg!(gcs, SYSTEM_TIME).await;
    assert_eq!(u64::from(st.time_boot_ms), now);
    assert_eq!(
        st.time_unix_usec,
        sitl::SimConfig::default().epoch_unix_us + now * 1000
    );
}

#[tokio::test]
async fn a_mavlink1_peer_is_answered_in_mavlink1() {
    let (_sim, mut gcs) = start("").await;
    gcs.version = MavlinkVersion::V1;
    assert_eq!(gcs.set_mode(4).await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(gcs.last_version, Some(MavlinkVersion::V1));
    gcs.version = MavlinkVersion::V2;
    assert_eq!(gcs.set_mode(0).await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(gcs.last_version, Some(MavlinkVersion::V2));
}

#[tokio::test]
async fn udp_peers_are_answered() {
    let mut cfg = sitl::SimConfig::for_tests();
    cfg.listen = "udpin:127.0.0.1:0".into();
    let sim = sitl::spawn(cfg).await.expect("spawn");
    assert!(sim.client_address().starts_with("udpout:127.0.0.1:"));
    let sock = tokio::net::UdpSocket::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let mut buf = Vec::new();
    let hb = MavMessage::HEARTBEAT(HEARTBEAT_DATA::default());
    let header = mavlink::MavHeader {
        system_id: 255,
        component_id: 190,
        sequence: 0,
    };
    mavlink::write_versioned_msg(&mut buf, MavlinkVersion::V2, header, &hb).expect("encode");
    sock.send_to(&buf, sim.local_addr()).await.expect("send");
    // The sim learns the peer when the datagram is handled; then a step sends it telemetry.
    let deadline = tokio::time::Instant::now() + WAIT;
    let mut rbuf = vec![0u8; 4096];
    loop {
        sim.step(Duration::from_secs(1)).await.expect("step");
        match tokio::time::timeout(Duration::from_millis(50), sock.recv_from(&mut rbuf)).await {
            Ok(Ok((n, _))) => {
                let mut r = mavlink::MavlinkReader::new(&rbuf[..n]);
                let (_, m) = r.read_any_message::<MavMessage>().expect("a frame");
                let _ = m;
                break;
            }
            _ if tokio::time::Instant::now() > deadline => panic!("no UDP telemetry"),
            _ => {}
        }
    }
}

#[tokio::test]
async fn messages_for_other_components_are_not_answered() {
    let (sim, mut gcs) = start("").await;
    // A goal upload for the companion (component 191) is not the autopilot's business.
    gcs.send(MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
        count: 2,
        target_system: 1,
        target_component: 191,
        ..Default::default()
    }))
    .await;
    // Nor is an arm for system 2.
    gcs.send_arm_to(2).await;
    let seen = gcs.sync().await;
    assert!(!seen.iter().any(|m| matches!(
        m,
        MavMessage::MISSION_REQUEST_INT(_)
            | MavMessage::MISSION_REQUEST(_)
            | MavMessage::COMMAND_ACK(_)
    )));
    assert!(!sim.snapshot().armed);
}

#[tokio::test]
async fn the_auv_dives_to_a_guided_depth() {
    let mut cfg = sitl::SimConfig::for_tests();
    cfg.vehicle = sitl::VehicleKind::Auv;
    let (sim, mut gcs) = start_with(cfg).await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let wp = waypoint(HOME, 10.0, 0.0);
    let (r, _) = gcs.reposition(&wp, true, -5.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    run_until(&sim, 60, |s| {
        (s.depth_m - 5.0).abs() < 0.01 && s.north_m > 9.0
    })
    .await;
    gcs.drain();
    sim.step(Duration::from_secs(1)).await.expect("step");
    let alt = expect_msg!(gcs, GLOBAL_POSITION_INT).await.alt;
    assert_eq!(alt, -5000);
}

/// Targets that cannot be places are refused, over the socket: DO_REPOSITION to latitude 214° or with a NaN
/// altitude or speed is DENIED, a mission item at longitude 214.7° ends the upload with INVALID_PARAM6_Y, and
/// the SITL keeps its heartbeat and accepts a sane target afterwards.
#[tokio::test]
async fn absurd_targets_are_refused_and_the_vehicle_goes_on() {
    let (sim, mut gcs) = start("").await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    let good = waypoint(HOME, 20.0, 10.0);
    let cases: [(i32, i32, f32, f32); 3] = [
        (2_140_000_000, good.y, 0.0, -1.0),
        (good.x, good.y, f32::NAN, -1.0),
        (good.x, good.y, 0.0, f32::INFINITY),
    ];
    for (x, y, z, speed) in cases {
        let (r, _) = gcs
            .command_int(
                MavCmd::MAV_CMD_DO_REPOSITION,
                [speed, 1.0, 0.0, 0.0],
                x,
                y,
                z,
            )
            .await;
        assert_eq!(
            r,
            MavResult::MAV_RESULT_DENIED,
            "x {x} y {y} z {z} speed {speed}"
        );
    }
    assert!(
        sim.snapshot().distance_m < 0.01,
        "moved towards an absurd target"
    );
    // Longitude 214.7° (i32::MAX ×1e-7): beyond ±180°.
    let mut far = waypoint(HOME, 5.0, 5.0);
    far.y = i32::MAX;
    let items = vec![waypoint(HOME, 0.0, 0.0), far];
    assert_eq!(
        gcs.upload(&items).await,
        MavMissionResult::MAV_MISSION_INVALID_PARAM6_Y
    );
    let beats = sent_over(&sim, &mut gcs, Duration::from_secs(2)).await;
    assert!(
        beats.iter().any(|m| matches!(m, MavMessage::HEARTBEAT(_))),
        "no heartbeat after the refusals"
    );
    let (r, _) = gcs.reposition(&good, true, 0.0).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
}

/// One peer cannot silence the vehicle for the others: SET_MESSAGE_INTERVAL stopping HEARTBEAT (-1), slowing
/// it below 1 Hz or with a NaN interval is DENIED, REQUEST_DATA_STREAM ALL stop leaves it on, and both
/// peers keep receiving HEARTBEAT; a sane interval on another message is still accepted.
#[tokio::test]
async fn heartbeat_cannot_be_switched_off() {
    let (sim, mut a) = start("").await;
    let mut b = Gcs::connect(sim.local_addr()).await;
    b.sysid = 254;
    for interval in [-1.0, 5e6, f32::NAN] {
        assert_eq!(
            a.command(MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL, &[0.0, interval])
                .await,
            MavResult::MAV_RESULT_DENIED,
            "HEARTBEAT interval {interval}"
        );
    }
    assert_eq!(
        a.command(MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL, &[33.0, f32::INFINITY])
            .await,
        MavResult::MAV_RESULT_DENIED,
        "an infinite interval"
    );
    assert_eq!(
        a.command(MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL, &[33.0, -1.0])
            .await,
        MavResult::MAV_RESULT_ACCEPTED,
        "GLOBAL_POSITION_INT may stop"
    );
    a.stop_all_streams().await;
    a.sync().await;
    b.sync().await;
    sim.step(Duration::from_secs(3)).await.expect("step");
    for (name, peer) in [("a", &mut a), ("b", &mut b)] {
        let msgs = peer.sync().await;
        let beats = msgs
            .iter()
            .filter(|m| matches!(m, MavMessage::HEARTBEAT(_)))
            .count();
        assert!(beats >= 2, "peer {name}: {beats} heartbeats in 3 s");
        assert!(
            !msgs
                .iter()
                .any(|m| matches!(m, MavMessage::GLOBAL_POSITION_INT(_))),
            "peer {name}: GLOBAL_POSITION_INT was stopped"
        );
    }
}
