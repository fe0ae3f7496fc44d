//! The vehicle vanishes mid-mission (`kill -9` of `mavtempo sim`, over a socket): `mavtempo run` ends within
//! its link timeout and a margin with the verdict "vehicle lost", the pending goals settled with it, the
//! report written, and a non-zero exit; mission time went on on the companion's clock meanwhile.

use crate::support::child;

use std::process::Stdio;
use std::time::{Duration, Instant};

use child::{fig2_sim, lines, run_on_sim, wait_line, Reap};

#[test]
fn run_ends_with_a_verdict_when_the_vehicle_vanishes() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let (mut sim, port) = fig2_sim("10");
    let report_path = dir.path().join("run.json");
    let mut run = run_on_sim(port, "10")
        .args(["--link-timeout", "4"])
        .arg("--report")
        .arg(&report_path)
        .args([
            "domains/rover/rover.ixt",
            "tests/fixtures/exec/rover_two.ixt",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map(Reap)
        .expect("spawn mavtempo run");
    let out = lines(run.0.stdout.take().expect("stdout"));
    let err = lines(run.0.stderr.take().expect("stderr"));
    let mut seen = Vec::new();
    wait_line(&out, "START move(", Duration::from_secs(120), &mut seen);
    let started_at = seen
        .iter()
        .rev()
        .find_map(|l| l.trim().strip_prefix('['))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|t| t.parse::<f64>().ok())
        .unwrap_or_else(|| panic!("no cycle time before the move: {seen:?}"));
    // Issue 30: the trace tells the vehicle's mode, arming, battery and link.
    assert!(
        seen.iter().any(|l| l.contains("] vehicle: mode ")
            && l.contains(", battery ")
            && l.ends_with("link up")),
        "{seen:?}"
    );
    sim.0.kill().expect("kill -9 the simulator");
    let killed = Instant::now();
    let status = loop {
        if let Some(status) = run.0.try_wait().expect("try_wait") {
            break status;
        }
        // The link timeout (4 s) and a margin for a replanning (its wall budget) and a loaded machine.
        if killed.elapsed() > Duration::from_secs(60) {
            let later: Vec<String> = out.try_iter().chain(err.try_iter()).collect();
            panic!(
                "run still going {:?} after the vehicle vanished:\n{}",
                killed.elapsed(),
                later.join("\n")
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    assert_eq!(status.code(), Some(1), "{status:?}");
    // The link's loss is in the trace before the verdict (the link timeout of the config, 3 s, is
    // shorter than --link-timeout).
    let mut later = Vec::new();
    wait_line(
        &out,
        "link lost: no heartbeat for",
        Duration::from_secs(5),
        &mut later,
    );
    let mut errs = Vec::new();
    wait_line(
        &err,
        "vehicle lost: no heartbeat for 4 s",
        Duration::from_secs(5),
        &mut errs,
    );
    let text = std::fs::read_to_string(&report_path).expect("report written");
    let r: serde_json::Value = serde_json::from_str(&text).expect("report is JSON");
    assert_eq!(r["end"]["vehicle_lost"]["silent_s"], 4, "{}", r["end"]);
    let goals = r["goals"].as_array().expect("goals");
    let pending: Vec<&serde_json::Value> =
        goals.iter().filter(|g| g["fate"] == "pending").collect();
    assert!(!pending.is_empty(), "{goals:?}");
    for g in pending {
        assert_eq!(g["reason"], "vehicle lost: no heartbeat for 4 s", "{g}");
    }
    // Mission time went on while the vehicle was silent: 4 s of wall at 10x is 40 s of mission.
    let end_s = r["duration_ms"].as_f64().expect("duration") / 1000.0;
    assert!(
        end_s >= started_at + 30.0,
        "{end_s} s, move at {started_at} s"
    );
}
