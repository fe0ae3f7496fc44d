//! The mission protocol as ArduPilot runs it, seen from an independent client over a socket.
#![allow(deprecated)]

use std::time::Duration;

use crate::support::*;
use mavlink::dialects::ardupilotmega::*;

fn square() -> Vec<MISSION_ITEM_INT_DATA> {
    vec![
        waypoint(HOME, 0.0, 0.0),
        waypoint(HOME, 20.0, 0.0),
        waypoint(HOME, 20.0, 20.0),
        waypoint(HOME, 0.0, 20.0),
    ]
}

fn count(n: u16) -> MavMessage {
    MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
        count: n,
        target_system: 1,
        target_component: 1,
        ..Default::default()
    })
}

async fn next_request(gcs: &mut Gcs) -> u16 {
    expect_msg!(gcs, MISSION_REQUEST_INT).await.seq
}

async fn mission_ack(gcs: &mut Gcs) -> MavMissionResult {
    expect_msg!(gcs, MISSION_ACK).await.mavtype
}

/// MISSION_REQUEST_LIST of `mission_type`; the MISSION_COUNT that answers.
async fn list_count(gcs: &mut Gcs, mission_type: MavMissionType) -> MISSION_COUNT_DATA {
    gcs.send(MavMessage::MISSION_REQUEST_LIST(
        MISSION_REQUEST_LIST_DATA {
            target_system: 1,
            target_component: 1,
            mission_type,
        },
    ))
    .await;
    expect_msg!(gcs, MISSION_COUNT).await
}

/// MISSION_CLEAR_ALL; the MISSION_ACK's result.
async fn clear_all(gcs: &mut Gcs) -> MavMissionResult {
    gcs.send(MavMessage::MISSION_CLEAR_ALL(MISSION_CLEAR_ALL_DATA {
        target_system: 1,
        target_component: 1,
        ..Default::default()
    }))
    .await;
    mission_ack(gcs).await
}

/// Asks for stored item `seq` with MISSION_REQUEST_INT (`legacy`: MISSION_REQUEST); the item that answers,
/// MISSION_ITEM_INT or MISSION_ITEM.
async fn request_item(gcs: &mut Gcs, seq: u16, legacy: bool) -> MavMessage {
    let request = if legacy {
        MavMessage::MISSION_REQUEST(MISSION_REQUEST_DATA {
            seq,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        })
    } else {
        MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
            seq,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        })
    };
    gcs.send(request).await;
    gcs.expect("the requested mission item", |m| match m {
        MavMessage::MISSION_ITEM_INT(i) if i.seq == seq => Some(m.clone()),
        MavMessage::MISSION_ITEM(i) if i.seq == seq => Some(m.clone()),
        _ => None,
    })
    .await
}

#[tokio::test]
async fn a_silent_uploader_is_re_requested_then_cancelled() {
    let (sim, mut gcs) = start("").await;
    gcs.send(count(3)).await;
    assert_eq!(next_request(&mut gcs).await, 0);
    // Re-requested (after 300 ms here, ~1 s on ArduPilot) ...
    assert_eq!(next_request(&mut gcs).await, 0);
    // ... then cancelled (1.5 s here, 8 s on ArduPilot).
    assert_eq!(
        mission_ack(&mut gcs).await,
        MavMissionResult::MAV_MISSION_OPERATION_CANCELLED
    );
    let texts = Gcs::texts(&gcs.sync().await);
    assert!(
        texts.iter().any(|t| t == "Mission upload timeout"),
        "{texts:?}"
    );
    assert_eq!(sim.snapshot().mission_total, 0);
}

#[tokio::test]
async fn one_uploader_at_a_time_and_wrong_seq_keeps_the_upload_open() {
    let (sim, mut a) = start("").await;
    let mut b = Gcs::connect(sim.local_addr()).await;
    b.sysid = 254;
    a.send(count(2)).await;
    assert_eq!(next_request(&mut a).await, 0);
    b.send(count(2)).await;
    assert_eq!(
        mission_ack(&mut b).await,
        MavMissionResult::MAV_MISSION_DENIED
    );
    let items = square();
    let mut wrong = items[1].clone();
    wrong.seq = 1;
    wrong.target_system = 1;
    a.send(MavMessage::MISSION_ITEM_INT(wrong)).await;
    assert_eq!(
        mission_ack(&mut a).await,
        MavMissionResult::MAV_MISSION_INVALID_SEQUENCE
    );
    for seq in 0..2u16 {
        let mut it = items[usize::from(seq)].clone();
        it.seq = seq;
        it.target_system = 1;
        a.send(MavMessage::MISSION_ITEM_INT(it)).await;
        if seq == 0 {
            // Skip re-requests of item 0 that crossed it on a slow machine.
            while next_request(&mut a).await == 0 {}
        }
    }
    assert_eq!(
        mission_ack(&mut a).await,
        MavMissionResult::MAV_MISSION_ACCEPTED
    );
    assert_eq!(sim.snapshot().mission_total, 1);
}

#[tokio::test]
async fn legacy_items_and_requests_round_trip_with_home_as_item_zero() {
    let (_sim, mut gcs) = start("").await;
    let items = square();
    let result = gcs
        .upload_with(items.len() as u16, |seq| {
            let it = &items[usize::from(seq)];
            MavMessage::MISSION_ITEM(MISSION_ITEM_DATA {
                x: (f64::from(it.x) * 1e-7) as f32,
                y: (f64::from(it.y) * 1e-7) as f32,
                seq,
                command: MavCmd::MAV_CMD_NAV_WAYPOINT,
                frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
                target_system: 1,
                target_component: 1,
                autocontinue: 1,
                // A bogus item 0: ArduPilot replaces it with home.
                z: if seq == 0 { 123.0 } else { 0.0 },
                ..Default::default()
            })
        })
        .await;
    assert_eq!(result, MavMissionResult::MAV_MISSION_ACCEPTED);
    gcs.send(MavMessage::MISSION_REQUEST_LIST(
        MISSION_REQUEST_LIST_DATA {
            target_system: 1,
            target_component: 1,
            ..Default::default()
        },
    ))
    .await;
    let n = expect_msg!(gcs, MISSION_COUNT).await.count;
    assert_eq!(n, 4);
    // Modern request -> MISSION_ITEM_INT; legacy request -> MISSION_ITEM.
    let MavMessage::MISSION_ITEM_INT(home) = request_item(&mut gcs, 0, false).await else {
        panic!("MISSION_REQUEST_INT not answered with MISSION_ITEM_INT");
    };
    assert_eq!((home.x, home.y, home.z), (435_615_000, 14_778_000, 0.0));
    let MavMessage::MISSION_ITEM(it) = request_item(&mut gcs, 2, true).await else {
        panic!("MISSION_REQUEST not answered with MISSION_ITEM");
    };
    assert!((f64::from(it.x) - f64::from(items[2].x) * 1e-7).abs() < 1e-5);
    assert!((f64::from(it.y) - f64::from(items[2].y) * 1e-7).abs() < 1e-5);
}

#[tokio::test]
async fn legacy_request_kind_asks_with_mission_request() {
    let mut cfg = sitl::SimConfig::for_tests();
    cfg.mission_request = sitl::MissionRequestKind::Legacy;
    let (_sim, mut gcs) = start_with(cfg).await;
    gcs.send(count(2)).await;
    let seq = gcs
        .expect("MISSION_REQUEST", |m| match m {
            MavMessage::MISSION_REQUEST(r) => Some(r.seq),
            MavMessage::MISSION_REQUEST_INT(_) => panic!("asked with MISSION_REQUEST_INT"),
            _ => None,
        })
        .await;
    assert_eq!(seq, 0);
}

#[tokio::test]
async fn clear_is_refused_in_auto_and_mission_current_reports_state() {
    let (sim, mut gcs) = start("").await;
    let state = |m: &MavMessage| match m {
        MavMessage::MISSION_CURRENT(c) => Some((c.seq, c.total, c.mission_state, c.mission_mode)),
        _ => None,
    };
    sim.step(Duration::from_secs(1)).await.expect("step");
    let (_, total, st, _) = gcs.expect("MISSION_CURRENT", state).await;
    assert_eq!((total, st), (0, MissionState::MISSION_STATE_NO_MISSION));
    upload_ok(&mut gcs, &square()).await;
    gcs.drain();
    sim.step(Duration::from_secs(1)).await.expect("step");
    let (_, total, st, _) = gcs.expect("MISSION_CURRENT", state).await;
    assert_eq!((total, st), (3, MissionState::MISSION_STATE_NOT_STARTED));
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_MISSION_START, &[]).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(sim.snapshot().mode, "AUTO");
    gcs.drain();
    sim.step(Duration::from_secs(1)).await.expect("step");
    let (seq, _, st, mode) = gcs.expect("MISSION_CURRENT", state).await;
    assert_eq!((seq, st, mode), (1, MissionState::MISSION_STATE_ACTIVE, 1));
    assert_eq!(
        clear_all(&mut gcs).await,
        MavMissionResult::MAV_MISSION_ERROR
    );
    assert_eq!(sim.snapshot().mission_total, 3);
    // Jump to item 3, then finish.
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_DO_SET_MISSION_CURRENT, &[3.0])
            .await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(
        gcs.command(MavCmd::MAV_CMD_DO_SET_MISSION_CURRENT, &[9.0])
            .await,
        MavResult::MAV_RESULT_DENIED
    );
    run_until(&sim, 60, |s| s.mission_complete).await;
    let reached = expect_msg!(gcs, MISSION_ITEM_REACHED).await.seq;
    assert_eq!(reached, 3, "items 1 and 2 were skipped");
    gcs.drain();
    sim.step(Duration::from_secs(1)).await.expect("step");
    let (_, _, st, _) = gcs.expect("MISSION_CURRENT", state).await;
    assert_eq!(st, MissionState::MISSION_STATE_COMPLETE);
    // Out of AUTO the mission can be cleared.
    assert_eq!(gcs.set_mode(4).await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(
        clear_all(&mut gcs).await,
        MavMissionResult::MAV_MISSION_ACCEPTED
    );
    assert_eq!(sim.snapshot().mission_total, 0);
}

#[tokio::test]
async fn auto_runs_loiter_speed_camera_servo_and_rtl_items() {
    let (sim, mut gcs) = start("[sampler]\nservo = 9\nduration_s = 2.0\n").await;
    let mut loiter = waypoint(HOME, 20.0, 0.0);
    loiter.command = MavCmd::MAV_CMD_NAV_LOITER_TIME;
    loiter.param1 = 10.0;
    let items = vec![
        waypoint(HOME, 0.0, 0.0),
        item(MavCmd::MAV_CMD_DO_CHANGE_SPEED, [1.0, 2.0, -1.0, 0.0]),
        loiter,
        item(MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 0.0, 1.0, 0.0]),
        item(MavCmd::MAV_CMD_DO_SET_SERVO, [9.0, 1900.0, 0.0, 0.0]),
        waypoint(HOME, 20.0, 20.0),
        item(MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH, [0.0; 4]),
    ];
    start_auto(&mut gcs, &items).await;
    // DO_CHANGE_SPEED: 2 m/s on the first leg.
    let s = run_until(&sim, 30, |s| s.north_m > 8.0).await;
    assert!(s.speed_mps <= 2.0 + 1e-6, "{}", s.speed_mps);
    // LOITER_TIME: 10 s at the first point, where the picture and the sample are taken.
    let arrived = run_until(&sim, 30, |s| {
        s.statustexts.iter().any(|t| t.contains("Loiter for 10"))
    })
    .await;
    let left = run_until(&sim, 60, |s| {
        s.statustexts.iter().any(|t| t == "Finished active loiter")
    })
    .await;
    assert!(left.time_ms - arrived.time_ms >= 10_000);
    assert_eq!(left.pictures_ok, 1);
    assert!(left.samples >= 1, "the sampler collects while loitering");
    let s = run_until(&sim, 120, |s| s.mission_complete).await;
    assert!(s.north_m.hypot(s.east_m) <= 3.5, "RTL ends at home: {s:?}");
    let seen = gcs.sync().await;
    let captured: Vec<_> = seen
        .iter()
        .filter_map(|m| match m {
            MavMessage::CAMERA_IMAGE_CAPTURED(c) => Some((c.image_index, c.capture_result)),
            _ => None,
        })
        .collect();
    assert_eq!(captured, vec![(0, MavBool::MAV_BOOL_TRUE)]);
    let reached: Vec<u16> = seen
        .iter()
        .filter_map(|m| match m {
            MavMessage::MISSION_ITEM_REACHED(r) => Some(r.seq),
            _ => None,
        })
        .collect();
    assert_eq!(reached, vec![1, 2, 5, 6]);
    let texts = Gcs::texts(&seen);
    assert!(texts.iter().any(|t| t == "Sampler deployed"), "{texts:?}");
}

/// The fence list over the mission protocol (mission_type FENCE), as ArduPilot keeps it: a ground station
/// uploads a polygon and a circle, downloads them back, reads and sets FENCE_* parameters; the mission list
/// is untouched. A scenario's `[fence]` holds one from boot.
#[tokio::test]
async fn a_fence_is_uploaded_downloaded_and_its_parameters_read() {
    let fence = MavMissionType::MAV_MISSION_TYPE_FENCE;
    let (_sim, mut gcs) = start("").await;
    let mut items: Vec<MISSION_ITEM_INT_DATA> = [(0.0, 0.0), (0.0, 50.0), (50.0, 0.0)]
        .iter()
        .map(|&(n, e)| MISSION_ITEM_INT_DATA {
            command: MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION,
            param1: 3.0,
            ..waypoint(HOME, n, e)
        })
        .collect();
    items.push(MISSION_ITEM_INT_DATA {
        command: MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION,
        param1: 5.0,
        ..waypoint(HOME, 10.0, 10.0)
    });
    let n = items.len() as u16;
    gcs.send(MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
        count: n,
        target_system: 1,
        target_component: 1,
        mission_type: fence,
        opaque_id: 0,
    }))
    .await;
    for _ in 0..n {
        let r = expect_msg!(gcs, MISSION_REQUEST_INT).await;
        assert_eq!(r.mission_type, fence);
        let mut it = items[usize::from(r.seq)].clone();
        it.seq = r.seq;
        it.target_system = 1;
        it.target_component = 1;
        it.mission_type = fence;
        gcs.send(MavMessage::MISSION_ITEM_INT(it)).await;
    }
    let ack = expect_msg!(gcs, MISSION_ACK).await;
    assert_eq!(
        (ack.mavtype, ack.mission_type),
        (MavMissionResult::MAV_MISSION_ACCEPTED, fence)
    );
    // Downloaded back whole, with no home item in front.
    let c = list_count(&mut gcs, fence).await;
    assert_eq!((c.count, c.mission_type), (n, fence));
    for seq in 0..n {
        gcs.send(MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
            seq,
            target_system: 1,
            target_component: 1,
            mission_type: fence,
        }))
        .await;
        let it = expect_msg!(gcs, MISSION_ITEM_INT).await;
        let sent = &items[usize::from(seq)];
        assert_eq!(
            (it.command, it.param1, it.x, it.y),
            (sent.command, sent.param1, sent.x, sent.y)
        );
    }
    // The mission list still holds only home.
    assert_eq!(
        list_count(&mut gcs, MavMissionType::MAV_MISSION_TYPE_MISSION)
            .await
            .count,
        1
    );
    // FENCE_ENABLE is 0 by default, as on ArduPilot; a PARAM_SET is answered with the new value.
    let read = |name: &str| {
        MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
            param_index: -1,
            target_system: 1,
            target_component: 1,
            param_id: name.into(),
        })
    };
    gcs.send(read("FENCE_ENABLE")).await;
    let v = expect_msg!(gcs, PARAM_VALUE).await;
    assert_eq!(
        (v.param_id.to_str(), v.param_value),
        (Ok("FENCE_ENABLE"), 0.0)
    );
    gcs.send(MavMessage::PARAM_SET(PARAM_SET_DATA {
        param_value: 1.0,
        target_system: 1,
        target_component: 1,
        param_id: "FENCE_ENABLE".into(),
        param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
    }))
    .await;
    assert_eq!(expect_msg!(gcs, PARAM_VALUE).await.param_value, 1.0);
    gcs.send(read("FENCE_RADIUS")).await;
    assert_eq!(expect_msg!(gcs, PARAM_VALUE).await.param_value, 300.0);
}

#[tokio::test]
async fn a_scenario_fence_is_held_from_boot() {
    let (_sim, mut gcs) = start(
        "[fence]\nenable = 1\nradius_m = 120\n[[fence.polygons]]\ninclusion = false\ncorners_m = [[0, 0], [0, 10], [10, 0]]\n",
    )
    .await;
    assert_eq!(
        list_count(&mut gcs, MavMissionType::MAV_MISSION_TYPE_FENCE)
            .await
            .count,
        3
    );
    gcs.send(MavMessage::PARAM_REQUEST_LIST(PARAM_REQUEST_LIST_DATA {
        target_system: 1,
        target_component: 1,
    }))
    .await;
    let mut seen = Vec::new();
    for _ in 0..3 {
        let v = expect_msg!(gcs, PARAM_VALUE).await;
        seen.push((v.param_id.to_str().map(str::to_string), v.param_value));
    }
    assert!(seen.contains(&(Ok("FENCE_ENABLE".into()), 1.0)), "{seen:?}");
    assert!(
        seen.contains(&(Ok("FENCE_RADIUS".into()), 120.0)),
        "{seen:?}"
    );
}
