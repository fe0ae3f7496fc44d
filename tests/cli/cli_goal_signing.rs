//! Issue 31: a companion that requires MAVLink2 signing (a `[link] signing_key`) over real sockets: an
//! unsigned `mavtempo goal send` is ignored and told why it got no answer; the same upload signed with the
//! key of the configuration given with `--config` is accepted; the live page's goal form signs too.

use mavtempo_testkit::http;

use std::net::SocketAddr;
use std::process::Command;
use std::sync::atomic::Ordering;
use std::time::Duration;

use mavtempo::cli::http_arg::goal_form;
use mavtempo::report::live::GoalAnswer;
use mavtempo::vehicle::geo::Home;
use mavtempo::vehicle::goals::{KnownLocations, SyntacticDecider};
use mavtempo::vehicle::link::{Decider, GoalServer};

const KEY: &str = "00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff";
const HOME: Home = Home {
    lat: 43.5615,
    lon: 1.4778,
    alt: 0.0,
};

const PLAN: &str = r#"{"fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
 "mission": {"version": 2, "firmwareType": 3, "vehicleType": 10, "cruiseSpeed": 2, "hoverSpeed": 5,
  "plannedHomePosition": [43.5615, 1.4778, 0],
  "items": [
   {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, null, 43.5620, 1.4780, 0], "autoContinue": true, "doJumpId": 1}
  ]},
 "geoFence": {"circles": [], "polygons": [], "version": 2}, "rallyPoints": {"points": [], "version": 2}}"#;

/// A shipped configuration with the signing key set (as a TOML key: a config without `[link]` fails here).
fn signed_config(dir: &tempfile::TempDir) -> std::path::PathBuf {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/config/demo-rover.toml"
    ))
    .expect("config");
    let mut doc: toml_edit::DocumentMut = text.parse().expect("TOML");
    doc["link"]["signing_key"] = toml_edit::value(KEY);
    let p = dir.path().join("signed.toml");
    std::fs::write(&p, doc.to_string()).expect("write");
    p
}

/// A goal intake that takes only frames signed with KEY, on a free UDP port.
fn signed_server(rt: &tokio::runtime::Runtime) -> GoalServer {
    let key = mavtempo::vehicle::frame::parse_key(KEY).expect("key");
    rt.block_on(GoalServer::start_signed(
        "udpin:127.0.0.1:0",
        1,
        KnownLocations::new(HOME),
        Decider::Local(Box::new(SyntacticDecider)),
        None,
        Some((key, 0)),
    ))
    .expect("server")
}

fn goal_send(
    plan: &std::path::Path,
    addr: SocketAddr,
    config: Option<&std::path::Path>,
) -> (bool, String, String) {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mavtempo"));
    cmd.args(["goal", "send"]).arg(plan).args([
        "--to",
        &format!("udpout:{addr}"),
        "--timeout",
        "2",
    ]);
    if let Some(c) = config {
        cmd.arg("--config").arg(c);
    }
    let out = cmd.output().expect("run mavtempo");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn an_unsigned_goal_send_is_refused_and_a_signed_one_accepted() {
    let rt = tokio::runtime::Runtime::new().expect("rt");
    let server = signed_server(&rt);
    let addr = server.local_addr.expect("bound");
    let dir = tempfile::TempDir::new().expect("temp dir");
    let plan = dir.path().join("goal.plan");
    std::fs::write(&plan, PLAN).expect("write");

    let (ok, stdout, stderr) = goal_send(&plan, addr, None);
    assert!(!ok, "stdout {stdout} stderr {stderr}");
    assert!(!stdout.contains("accepted"), "{stdout}");
    assert!(
        stderr.contains("signing") && stderr.contains("--config"),
        "{stderr}"
    );
    let dropped = server.stats.rejected_unsigned.load(Ordering::Relaxed);
    assert!(dropped > 0, "the intake saw no unsigned frame");

    let config = signed_config(&dir);
    let (ok, stdout, stderr) = goal_send(&plan, addr, Some(&config));
    assert!(ok, "stdout {stdout} stderr {stderr}");
    assert_eq!(
        stdout.lines().collect::<Vec<_>>(),
        vec!["g1 accepted: at(g1_loc)", "upload accepted"],
        "{stderr}"
    );
}

#[test]
fn the_goal_form_signs_with_the_companions_key() {
    let rt = tokio::runtime::Runtime::new().expect("rt");
    let server = signed_server(&rt);
    let gcs = format!("udpout:{}", server.local_addr.expect("bound"));
    let key = mavtempo::vehicle::frame::parse_key(KEY).expect("key");
    let form = goal_form(HOME, gcs, None, Some((key, 0)), None);
    let page = mavtempo::report::live::start(
        rt.handle(),
        SocketAddr::from(([127, 0, 0, 1], 0)),
        Some(form),
    )
    .expect("live page");
    let fields = "east=30&north=2&window_end_s=1800&d_achiev_s=60";
    let req = format!(
        "POST /goal HTTP/1.1\r\nHost: {}\r\nConnection: close\r\n\
         Content-Type: application/x-www-form-urlencoded\r\nContent-Length: {}\r\n\r\n{fields}",
        page.addr,
        fields.len()
    );
    let (status, body) = http::exchange(page.addr, &req, Duration::from_secs(60));
    let a: GoalAnswer = serde_json::from_str(&body).unwrap_or_else(|e| panic!("{e}: {body}"));
    assert_eq!(status, 200, "{a:?}");
    assert!(a.accepted && a.verdict.contains(" accepted: "), "{a:?}");
    assert_eq!(server.stats.rejected_unsigned.load(Ordering::Relaxed), 0);
}
