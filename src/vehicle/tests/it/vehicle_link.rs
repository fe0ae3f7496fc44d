//! The MAVLink vehicle over real sockets (loopback, port 0) against a tiny scripted peer built in the test:
//! link up / loss / recovery, MAVLink 1 peers, signing accepted and rejected, `.tlog` recording, an action
//! report over the wire, and goal uploads to component 191 decided locally or by the executive.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use mavlink::dialects::ardupilotmega::*;
use mavlink::MavlinkVersion;
use mavtempo_vehicle::config::VehicleConfig;
use mavtempo_vehicle::frame::{Encoder, FrameDecoder, RawFrame, Signer};
use mavtempo_vehicle::geo::Home;
use mavtempo_vehicle::goal_client::{send_goals, GoalSendReport};
use mavtempo_vehicle::items::MissionItem;
use mavtempo_vehicle::link::{Decider, GoalServer, LinkOptions, MavlinkVehicle};
use mavtempo_vehicle::tlog::read_tlog;
use mavtempo_vehicle::{ActionStart, GoalVerdict, LinkStatus, ReportStatus, Vehicle, VehicleEvent};

const KEY_HEX: &str = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f";

/// The link's heartbeat timeout: short where a test waits for a loss, else long enough that a loaded machine
/// does not lose the link in the middle of an exchange.
const SHORT_HEARTBEAT_MS: i64 = 400;
const HEARTBEAT_MS: i64 = 3_000;

/// The fixture with its link bound to port 0, the given heartbeat timeout and an optional signing key: set as
/// TOML keys, so a fixture that no longer has them fails here instead of silently keeping its own.
fn config(signing_key: Option<&str>, heartbeat_ms: i64) -> VehicleConfig {
    let text =
        std::fs::read_to_string(repo!("tests/fixtures/vehicle/bindings.toml")).expect("config");
    let mut doc: toml_edit::DocumentMut = text.parse().expect("the fixture is TOML");
    let link = doc["link"].as_table_mut().expect("the fixture has [link]");
    assert!(link.contains_key("address") && link.contains_key("heartbeat_timeout_ms"));
    link["address"] = toml_edit::value("tcpin:127.0.0.1:0");
    link["heartbeat_timeout_ms"] = toml_edit::value(heartbeat_ms);
    if let Some(key) = signing_key {
        link["signing_key"] = toml_edit::value(key);
    }
    VehicleConfig::parse(&doc.to_string(), "test").expect("parses")
}

fn vehicle(
    signing_key: Option<&str>,
    heartbeat_ms: i64,
    opts: LinkOptions,
) -> (MavlinkVehicle, std::net::SocketAddr) {
    let v =
        MavlinkVehicle::connect_blocking(config(signing_key, heartbeat_ms), opts).expect("link");
    let addr = v.local_addr().expect("bound");
    (v, addr)
}

/// A scripted autopilot at the other end of the TCP link.
struct Peer {
    s: TcpStream,
    enc: Encoder,
    dec: FrameDecoder,
}

impl Peer {
    fn connect(addr: std::net::SocketAddr, system: u8, signer: Option<Signer>) -> Self {
        let s = TcpStream::connect(addr).expect("connect");
        s.set_read_timeout(Some(Duration::from_millis(50)))
            .expect("timeout");
        Self {
            s,
            enc: Encoder::new(system, 1, signer),
            dec: FrameDecoder::default(),
        }
    }

    /// An unsigned autopilot of `system` connected to `addr` that has sent one heartbeat (MAVLink 1 if `v1`).
    fn after_heartbeat(addr: std::net::SocketAddr, system: u8, v1: bool) -> Self {
        let mut p = Self::connect(addr, system, None);
        p.send(&heartbeat(0), v1);
        p
    }

    fn send(&mut self, msg: &MavMessage, v1: bool) -> Vec<u8> {
        let bytes = self.enc.encode(msg, v1);
        self.s.write_all(&bytes).expect("write");
        bytes
    }

    /// Frames until `pred` holds, within 5 s.
    fn until(
        &mut self,
        mut pred: impl FnMut(&RawFrame, &MavMessage) -> bool,
    ) -> (RawFrame, MavMessage) {
        let deadline = Instant::now() + Duration::from_secs(5);
        let mut buf = [0u8; 4096];
        loop {
            while let Some(f) = self.dec.next_frame() {
                if let Some(m) = f.parse() {
                    if pred(&f, &m) {
                        return (f, m);
                    }
                }
            }
            assert!(Instant::now() < deadline, "expected frame not received");
            if let Ok(n) = self.s.read(&mut buf) {
                self.dec.push(&buf[..n]);
            }
        }
    }
}

fn heartbeat(mode: u32) -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: mode,
        mavtype: MavType::MAV_TYPE_GROUND_ROVER,
        autopilot: MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
        base_mode: MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED,
        system_status: MavState::MAV_STATE_ACTIVE,
        mavlink_version: 3,
    })
}

/// The next link event, within 5 s (other events skipped).
fn link_event(v: &mut MavlinkVehicle) -> LinkStatus {
    let deadline = Instant::now() + Duration::from_secs(5);
    while Instant::now() < deadline {
        if let Some(VehicleEvent::Link(l)) = v.wait_event(Duration::from_millis(100)) {
            return l;
        }
    }
    panic!("no link event within 5 s");
}

#[test]
fn link_up_loss_on_disconnect_and_heartbeat_timeout_then_recovery() {
    let (mut v, addr) = vehicle(None, SHORT_HEARTBEAT_MS, LinkOptions::default());
    let mut p = Peer::after_heartbeat(addr, 7, false);
    assert_eq!(link_event(&mut v), LinkStatus::Up { system_id: 7 });
    // Our heartbeat: component 191, onboard controller, the adopted system id.
    let (f, _) = p.until(|_, m| matches!(m, MavMessage::HEARTBEAT(h) if h.mavtype == MavType::MAV_TYPE_ONBOARD_CONTROLLER));
    assert_eq!((f.system_id, f.component_id), (7, 191));
    // Silence longer than the short timeout: lost, then recovered on the next heartbeat.
    assert_eq!(link_event(&mut v), LinkStatus::Lost);
    p.send(&heartbeat(0), false);
    assert_eq!(link_event(&mut v), LinkStatus::Recovered);
    // Transport closed: lost; a new connection (tcpin keeps listening) recovers.
    drop(p);
    assert_eq!(link_event(&mut v), LinkStatus::Lost);
    let _p = Peer::after_heartbeat(addr, 7, false);
    assert_eq!(link_event(&mut v), LinkStatus::Recovered);
}

#[test]
fn mavlink1_peer_is_accepted_and_answered_in_mavlink1() {
    let (mut v, addr) = vehicle(None, HEARTBEAT_MS, LinkOptions::default());
    let mut p = Peer::after_heartbeat(addr, 3, true);
    assert_eq!(link_event(&mut v), LinkStatus::Up { system_id: 3 });
    let (f, _) = p.until(|_, m| matches!(m, MavMessage::HEARTBEAT(_)));
    assert_eq!(f.version, MavlinkVersion::V1);
}

#[test]
fn signing_rejects_unsigned_frames_and_signs_its_own() {
    let key = mavtempo_vehicle::frame::parse_key(KEY_HEX).expect("key");
    let (mut v, addr) = vehicle(Some(KEY_HEX), HEARTBEAT_MS, LinkOptions::default());
    let mut unsigned = Peer::connect(addr, 7, None);
    unsigned.send(&heartbeat(0), false);
    unsigned.send(&heartbeat(0), true);
    drop(unsigned);
    let mut forger = Peer::connect(addr, 9, Some(Signer::new([0x55; 32], 0)));
    forger.send(&heartbeat(0), false); // signed with the wrong key
    drop(forger);
    let mut p = Peer::connect(addr, 9, Some(Signer::new(key, 0)));
    p.send(&heartbeat(0), false);
    // Only the correctly signed autopilot (system 9) is adopted.
    assert_eq!(link_event(&mut v), LinkStatus::Up { system_id: 9 });
    assert_eq!(v.stats().rejected_unsigned.load(Ordering::Relaxed), 3);
    let verifier = Signer::new(key, 1);
    let (f, _) = p.until(|_, m| matches!(m, MavMessage::HEARTBEAT(_)));
    assert!(
        f.signed && verifier.accepts(&f),
        "our frames are signed with the key"
    );
}

#[test]
fn picture_action_over_the_wire_and_tlog_records_both_directions() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let tlog = dir.path().join("link.tlog");
    let opts = LinkOptions {
        tlog: Some(tlog.clone()),
        ..LinkOptions::default()
    };
    let (mut v, addr) = vehicle(None, HEARTBEAT_MS, opts);
    let mut p = Peer::connect(addr, 1, None);
    let hb_bytes = p.send(&heartbeat(4), false);
    assert_eq!(link_event(&mut v), LinkStatus::Up { system_id: 1 });
    v.start(ActionStart {
        id: 5,
        task: "take_picture".into(),
        args: vec![],
    })
    .expect("start");
    let (_, m) = p.until(|_, m| matches!(m, MavMessage::COMMAND_LONG(_)));
    let MavMessage::COMMAND_LONG(c) = m else {
        unreachable!()
    };
    assert_eq!(
        (c.command, c.target_system, c.target_component),
        (MavCmd::MAV_CMD_IMAGE_START_CAPTURE, 1, 1)
    );
    p.send(
        &MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
            command: c.command,
            result: MavResult::MAV_RESULT_ACCEPTED,
            ..Default::default()
        }),
        false,
    );
    p.send(
        &MavMessage::CAMERA_IMAGE_CAPTURED(CAMERA_IMAGE_CAPTURED_DATA {
            image_index: 0,
            capture_result: MavBool::MAV_BOOL_TRUE,
            ..Default::default()
        }),
        false,
    );
    let deadline = Instant::now() + Duration::from_secs(5);
    let report = loop {
        assert!(Instant::now() < deadline, "no report");
        if let Some(VehicleEvent::Report(r)) = v.wait_event(Duration::from_millis(100)) {
            break r;
        }
    };
    assert_eq!((report.id, report.status), (5, ReportStatus::Nominal));
    v.flush_tlog();
    let records =
        read_tlog(&std::fs::read(&tlog).expect("tlog written")).expect("well-formed tlog");
    assert!(
        records.iter().any(|(_, f)| *f == hb_bytes),
        "incoming heartbeat recorded byte for byte"
    );
    let mut dec = FrameDecoder::default();
    for (_, f) in &records {
        dec.push(f);
    }
    let frames: Vec<RawFrame> = std::iter::from_fn(|| dec.next_frame()).collect();
    assert!(
        frames.iter().any(
            |f| f.component_id == 191 && matches!(f.parse(), Some(MavMessage::COMMAND_LONG(_)))
        ),
        "outgoing recorded"
    );
    let now_us = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .expect("clock")
        .as_micros() as u64;
    assert!(
        records
            .iter()
            .all(|(t, _)| *t <= now_us && *t > now_us - 600_000_000),
        "timestamps are unix µs"
    );
}

/// Uploads `items` over `transport` (`udp` or `tcp`) to a syntactic goal server of `home` on port 0.
fn upload_to_syntactic_server(
    transport: &str,
    home: Home,
    items: Vec<MissionItem>,
) -> GoalSendReport {
    let rt = tokio::runtime::Runtime::new().expect("rt");
    rt.block_on(async {
        let server = GoalServer::syntactic(&format!("{transport}in:127.0.0.1:0"), home)
            .await
            .expect("server");
        let addr = server.local_addr.expect("bound");
        send_goals(
            &format!("{transport}out:{addr}"),
            items,
            Duration::from_secs(5),
        )
        .await
        .expect("upload ran")
    })
}

fn goal_items() -> Vec<MissionItem> {
    let mut attrs = MissionItem::new(MavCmd::MAV_CMD_USER_2, MavFrame::MAV_FRAME_MISSION);
    attrs.params = [2.0, 0.0, 30.0, 0.0];
    attrs.x = 60.0; // d_achiev 60 s > window end 30 s: rejected
    let mut pic = MissionItem::new(
        MavCmd::MAV_CMD_IMAGE_START_CAPTURE,
        MavFrame::MAV_FRAME_GLOBAL,
    );
    pic.x = 43.5620;
    pic.y = 1.4850;
    vec![MissionItem::waypoint(43.5617, 1.4848, 0.0), attrs, pic]
}

#[test]
fn goal_upload_to_component_191_gets_ack_and_one_statustext_per_goal() {
    let home = Home {
        lat: 43.5616,
        lon: 1.4847,
        alt: 0.0,
    };
    let report = upload_to_syntactic_server("udp", home, goal_items());
    assert_eq!(report.failure, None);
    assert_eq!(
        report.texts,
        vec![
            "g1 accepted: at(g1_loc)".to_string(),
            "g2 rejected: window ends before reachable".to_string()
        ]
    );
}

#[test]
fn goal_upload_is_decided_by_the_executive_through_the_vehicle() {
    let opts = LinkOptions {
        gcs: Some("udpin:127.0.0.1:0".into()),
        decider: Decider::Executive {
            timeout: Duration::from_secs(10),
        },
        first_goal_number: 6,
        ..LinkOptions::default()
    };
    let (mut v, _) = vehicle(None, HEARTBEAT_MS, opts);
    let gcs = v.gcs_addr().expect("gcs bound");
    let client = std::thread::spawn(move || {
        let rt = tokio::runtime::Runtime::new().expect("rt");
        rt.block_on(send_goals(
            &format!("udpout:{gcs}"),
            goal_items(),
            Duration::from_secs(5),
        ))
    });
    let deadline = Instant::now() + Duration::from_secs(10);
    let batch = loop {
        assert!(Instant::now() < deadline, "no goal batch");
        if let Some(VehicleEvent::Goals(b)) = v.wait_event(Duration::from_millis(100)) {
            break b;
        }
    };
    assert_eq!(
        batch
            .goals
            .iter()
            .map(|g| g.name.as_str())
            .collect::<Vec<_>>(),
        vec!["g6", "g7"]
    );
    batch.answer(vec![
        GoalVerdict::Rejected("conflicts with g3".into()),
        GoalVerdict::Accepted,
    ]);
    let report = client.join().expect("client thread").expect("upload");
    assert_eq!(report.failure, None);
    assert_eq!(
        report.texts,
        vec![
            "g6 rejected: conflicts with g3".to_string(),
            "g7 accepted: picture_of(g7_loc)".to_string()
        ]
    );
}

#[test]
fn goal_upload_with_an_item_that_is_no_goal_skips_it_with_the_reason() {
    let home = Home {
        lat: 0.0,
        lon: 0.0,
        alt: 0.0,
    };
    let items = vec![
        MissionItem::new(MavCmd::MAV_CMD_DO_SET_SERVO, MavFrame::MAV_FRAME_MISSION),
        MissionItem::waypoint(0.0001, 0.0001, 0.0),
    ];
    let report = upload_to_syntactic_server("tcp", home, items);
    assert_eq!(report.failure, None, "{report:?}");
    assert_eq!(
        report.texts,
        [
            "item 0: command 183 is not a goal: skipped",
            "g1 accepted: at(g1_loc)"
        ]
    );
}
