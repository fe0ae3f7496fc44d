//! `mavtempo goal send` and `goal check` as a user runs them: a .plan file to a goal intake, answers printed;
//! a malformed file refused with its place.

use std::process::Command;

use mavtempo::vehicle::geo::Home;
use mavtempo::vehicle::link::GoalServer;

const PLAN: &str = r#"{"fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
 "mission": {"version": 2, "firmwareType": 3, "vehicleType": 10, "cruiseSpeed": 2, "hoverSpeed": 5,
  "plannedHomePosition": [43.5615, 1.4778, 0],
  "items": [
   {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, null, 43.5620, 1.4780, 0], "autoContinue": true, "doJumpId": 1},
   {"type": "SimpleItem", "command": 31011, "frame": 2, "params": [1, 0, 10, 0, 60, 0, 0], "autoContinue": true, "doJumpId": 2},
   {"type": "SimpleItem", "command": 2000, "frame": 3, "params": [0, 0, 1, 0, 43.5625, 1.4785, 0], "autoContinue": true, "doJumpId": 3}
  ]},
 "geoFence": {"circles": [], "polygons": [], "version": 2}, "rallyPoints": {"points": [], "version": 2}}"#;

/// `text` written to `name` in `dir` (removed with it when the test ends, passed or failed).
fn temp_file(dir: &tempfile::TempDir, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).expect("write");
    p
}

/// `mavtempo goal send PLAN --to udpout:ADDR`.
fn goal_send(plan: &std::path::Path, addr: std::net::SocketAddr) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .args(["goal", "send"])
        .arg(plan)
        .args(["--to", &format!("udpout:{addr}")])
        .output()
        .expect("run mavtempo")
}

/// A goal server on a free UDP port that answers with the syntactic acceptance test.
fn syntactic_server(rt: &tokio::runtime::Runtime) -> GoalServer {
    rt.block_on(GoalServer::syntactic(
        "udpin:127.0.0.1:0",
        Home {
            lat: 43.5615,
            lon: 1.4778,
            alt: 0.0,
        },
    ))
    .expect("server")
}

#[test]
fn goal_send_uploads_a_plan_and_prints_the_verdicts() {
    let rt = tokio::runtime::Runtime::new().expect("rt");
    let server = syntactic_server(&rt);
    let addr = server.local_addr.expect("bound");
    let dir = tempfile::TempDir::new().expect("temp dir");
    let plan = temp_file(&dir, "goals.plan", PLAN);
    let out = goal_send(&plan, addr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "stdout {stdout} stderr {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        stdout.lines().collect::<Vec<_>>(),
        vec![
            "g1 accepted: at(g1_loc)",
            "g2 rejected: window ends before reachable",
            "upload accepted"
        ]
    );
}

#[test]
fn goal_check_refuses_a_malformed_waypoints_file_with_its_place() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let wp = temp_file(
        &dir,
        "bad.waypoints",
        "QGC WPL 110\n1\t0\t3\t16\t0\t0\t0\t0\tnorth\t1.4\t0\t1\n",
    );
    let out = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .args(["goal", "check"])
        .arg(&wp)
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains(&format!(
            "{}:2:18: LAT: `north` is not a number",
            wp.display()
        )),
        "{stderr}"
    );
    let plan = temp_file(&dir, "good.plan", PLAN);
    let out = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .args(["goal", "check"])
        .arg(&plan)
        .output()
        .expect("run");
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout)
        .contains("g2: picture_of(g2_loc) priority 1 window [0, 10] s"));
}

/// MISSION_COUNT counts in 16 bits: 70,000 items are refused with the reason, not wrapped to 4,464 and
/// reported as accepted.
#[test]
fn goal_send_refuses_more_items_than_mavlink_can_count() {
    let rt = tokio::runtime::Runtime::new().expect("rt");
    let server = syntactic_server(&rt);
    let addr = server.local_addr.expect("bound");
    let item = r#"{"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, 0, 43.5620, 1.4850, 0], "autoContinue": true}"#;
    let items = vec![item; 70_000].join(",\n");
    let plan = format!(
        r#"{{"fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
 "mission": {{"version": 2, "firmwareType": 3, "vehicleType": 10, "cruiseSpeed": 2, "hoverSpeed": 5,
  "plannedHomePosition": [43.5615, 1.4778, 0], "items": [{items}]}},
 "geoFence": {{"circles": [], "polygons": [], "version": 2}}, "rallyPoints": {{"points": [], "version": 2}}}}"#
    );
    let dir = tempfile::TempDir::new().expect("temp dir");
    let plan = temp_file(&dir, "many.plan", &plan);
    let out = goal_send(&plan, addr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "stdout {stdout}");
    assert!(!stdout.contains("upload accepted"), "{stdout}");
    assert!(
        stderr.contains("70000 items") && stderr.contains("at most 65535"),
        "{stderr}"
    );
}
