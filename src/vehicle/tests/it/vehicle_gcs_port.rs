//! The executive's ground-station port (`run --gcs udpin:…`) over real UDP sockets: garbage from one sender
//! costs only that sender (one frame decoder per UDP peer, replies to the peer they answer), and goals are
//! taken only from the system ids the configuration allows (`link.goal_sysids`).

use crate::support::gcs_config;
use crate::support::reports;

use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use gcs_config::config;
use mavtempo_vehicle::goal_client::{send_goals_as, GoalSendReport};
use mavtempo_vehicle::goals::SyntacticDecider;
use mavtempo_vehicle::items::MissionItem;
use mavtempo_vehicle::link::{Decider, LinkOptions, MavlinkVehicle};
use rand::{Rng, SeedableRng};

/// A companion whose ground-station port is a UDP socket on a free port, deciding goals syntactically.
fn companion(extra_link: &str) -> (MavlinkVehicle, SocketAddr) {
    let opts = LinkOptions {
        gcs: Some("udpin:127.0.0.1:0".into()),
        decider: Decider::Local(Box::new(SyntacticDecider)),
        ..LinkOptions::default()
    };
    let v = MavlinkVehicle::connect_blocking(config(extra_link), opts).expect("link");
    let gcs = v.gcs_addr().expect("gcs bound");
    (v, gcs)
}

/// Ten waypoint goals around the config's home.
fn items() -> Vec<MissionItem> {
    (0..10)
        .map(|i| MissionItem::waypoint(43.5615 + 1e-5 * f64::from(i), 1.4778, 0.0))
        .collect()
}

/// Uploads as system `sysid` in a runtime of its own; the report and the wall time it took.
fn upload(sysid: u8, gcs: SocketAddr) -> (GoalSendReport, Duration) {
    let rt = tokio::runtime::Runtime::new().expect("rt");
    let start = Instant::now();
    let report = rt
        .block_on(send_goals_as(
            sysid,
            &format!("udpout:{gcs}"),
            items(),
            Duration::from_secs(30),
        ))
        .expect("upload ran");
    (report, start.elapsed())
}

/// 1,400 random bytes that end in the start of a MAVLink 2 frame announcing a 255-byte payload: a decoder
/// that takes it for a frame waits for ~280 more bytes from whoever shares it.
fn garbage(rng: &mut rand_chacha::ChaCha8Rng) -> Vec<u8> {
    let mut d = vec![0u8; 1400];
    rng.fill(&mut d[..]);
    d[1390] = 0xFD;
    d[1391] = 0xFF;
    d
}

/// A sender that blasts garbage datagrams at `to` every millisecond until dropped.
struct Blaster {
    stop: Arc<AtomicBool>,
    sent: Arc<AtomicUsize>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Blaster {
    fn start(to: SocketAddr, seed: u64) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let sent = Arc::new(AtomicUsize::new(0));
        let (flag, count) = (stop.clone(), sent.clone());
        let thread = std::thread::spawn(move || {
            let socket = UdpSocket::bind("127.0.0.1:0").expect("bind");
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            while !flag.load(Ordering::Relaxed) {
                if socket.send_to(&garbage(&mut rng), to).is_ok() {
                    count.fetch_add(1, Ordering::Relaxed);
                }
                std::thread::sleep(Duration::from_millis(1));
            }
        });
        Blaster {
            stop,
            sent,
            thread: Some(thread),
        }
    }

    fn sent(&self) -> usize {
        self.sent.load(Ordering::Relaxed)
    }

    /// Waits (at most 10 s) until `n` datagrams are out.
    fn wait_sent(&self, n: usize) {
        let deadline = Instant::now() + Duration::from_secs(10);
        while self.sent() < n {
            assert!(
                Instant::now() < deadline,
                "the blaster sent {}",
                self.sent()
            );
            std::thread::sleep(Duration::from_millis(1));
        }
    }
}

impl Drop for Blaster {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// A normal upload takes milliseconds; the shared decoder made it wait 10–20 s.
const PROMPT: Duration = Duration::from_secs(3);

fn assert_accepted(report: &GoalSendReport, took: Duration, what: &str) {
    eprintln!("{what}: upload took {took:?}");
    assert_eq!(report.failure, None, "{what}: {report:?}");
    assert_eq!(report.texts.len(), 10, "{what}: {report:?}");
    assert!(took < PROMPT, "{what}: the upload took {took:?}");
}

#[test]
fn one_garbage_datagram_does_not_stall_another_station() {
    let (_v, gcs) = companion("");
    let rogue = UdpSocket::bind("127.0.0.1:0").expect("bind");
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(15);
    rogue.send_to(&garbage(&mut rng), gcs).expect("send");
    let (report, took) = upload(255, gcs);
    assert_accepted(&report, took, "after one garbage datagram");
}

#[test]
fn a_station_uploads_while_another_sender_blasts_garbage() {
    let (v, gcs) = companion("");
    let blaster = Blaster::start(gcs, 7);
    // The port is already under fire when the station starts.
    blaster.wait_sent(50);
    // An upload is short: on a loaded machine the blaster's thread may not run during one. Upload again
    // (at most 10 times) until one had garbage arriving while it ran; every upload must be accepted.
    let mut overlapped = false;
    for attempt in 0..10 {
        let before = blaster.sent();
        let (report, took) = upload(255, gcs);
        let during = blaster.sent() - before;
        assert_accepted(
            &report,
            took,
            &format!("upload {attempt}: {before} garbage datagrams before, {during} during"),
        );
        if during > 0 {
            overlapped = true;
            break;
        }
    }
    assert!(overlapped, "the blaster never sent during an upload");
    assert!(v.stats().crc_errors.load(Ordering::Relaxed) > 0);
}

#[test]
fn goals_are_taken_only_from_the_configured_system_ids() {
    let (_v, gcs) = companion("goal_sysids = [255, 250]");
    let (report, took) = upload(42, gcs);
    reports::assert_upload_refused(&report, "MAV_MISSION_DENIED", &["system 42", "goal_sysids"]);
    assert!(took < PROMPT, "refused in {took:?}");
    let (report, took) = upload(250, gcs);
    assert_accepted(&report, took, "from an allowed system");
}

#[test]
fn without_goal_sysids_any_system_may_upload() {
    let (_v, gcs) = companion("");
    let (report, took) = upload(42, gcs);
    assert_accepted(&report, took, "from system 42, no list");
}

/// On a `tcpin:` ground-station port every station has its own connection: one that connected first and
/// says nothing never holds the port for the others (it used to: the port served one connection at a time).
#[test]
fn an_idle_tcp_client_does_not_block_another_station() {
    let opts = LinkOptions {
        gcs: Some("tcpin:127.0.0.1:0".into()),
        decider: Decider::Local(Box::new(SyntacticDecider)),
        ..LinkOptions::default()
    };
    let v = MavlinkVehicle::connect_blocking(config(""), opts).expect("link");
    let gcs = v.gcs_addr().expect("gcs bound");
    let _idle = std::net::TcpStream::connect(gcs).expect("idle client connects");
    let rt = tokio::runtime::Runtime::new().expect("rt");
    let start = Instant::now();
    let report = rt
        .block_on(send_goals_as(
            255,
            &format!("tcpout:{gcs}"),
            items(),
            Duration::from_secs(30),
        ))
        .expect("upload ran");
    assert_accepted(&report, start.elapsed(), "beside an idle TCP client");
}
