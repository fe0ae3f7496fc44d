//! Issue 31's paced run (two processes over sockets): `mavtempo sim` with Fig. 2's scenario and `mavtempo
//! run` on Fig. 2, both paced at 10×; at ≈ 100 s of mission time a ground station uploads one picture goal
//! 22 m from home (`mavtempo goal send` to the intake's port-0 address). Every Fig. 2 goal is achieved,
//! none is lost to the plan-change bound; the new goal is settled with a reason.

use crate::support::child;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use child::{fig2_sim, lines, run_on_sim, wait_line, Reap};

const SPEEDUP: &str = "10";

/// One picture goal (MAV_CMD_IMAGE_START_CAPTURE at a position) 22 m north of the SITL's home.
const PICTURE_22M: &str = r#"{
  "fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
  "mission": { "version": 2, "firmwareType": 3, "vehicleType": 10, "cruiseSpeed": 2, "hoverSpeed": 5,
    "plannedHomePosition": [43.5615, 1.4778, 150],
    "items": [
      {"type": "SimpleItem", "command": 2000, "frame": 3, "params": [0, 0, 1, 0, 43.5617, 1.4778, 0],
       "autoContinue": true, "doJumpId": 1}
    ]},
  "geoFence": {"circles": [], "polygons": [], "version": 2}, "rallyPoints": {"points": [], "version": 2}
}"#;

/// The address at the end of the first line containing `needle`.
fn address_after(seen: &[String], needle: &str) -> String {
    seen.iter()
        .find(|l| l.contains(needle))
        .and_then(|l| l.split_whitespace().find(|w| w.starts_with("127.0.0.1:")))
        .map(str::to_string)
        .unwrap_or_else(|| panic!("no address after {needle:?} in {seen:?}"))
}

/// The mission time (s) of a cycle line `[   101.0 s] cycle …`, if it is one.
fn cycle_time(line: &str) -> Option<f64> {
    let rest = line.trim_start().strip_prefix('[')?;
    rest.split_whitespace().next()?.parse().ok()
}

#[test]
fn fig2_paced_with_a_goal_uploaded_at_100_s_keeps_every_goal() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let plan_file = dir.path().join("picture22.plan");
    std::fs::write(&plan_file, PICTURE_22M).expect("write the goal file");
    let (_sim, port) = fig2_sim(SPEEDUP);
    let report_path = dir.path().join("run.json");
    let mut run = run_on_sim(port, SPEEDUP)
        .args(["--gcs", "udpin:127.0.0.1:0"])
        .arg("--report")
        .arg(&report_path)
        .args(["domains/rover/rover.ixt", "domains/rover/problems/fig2.ixt"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map(Reap)
        .expect("spawn mavtempo run");
    let out = lines(run.0.stdout.take().expect("stdout"));
    let mut seen = Vec::new();
    wait_line(
        &out,
        "goal intake listening on",
        Duration::from_secs(60),
        &mut seen,
    );
    let gcs = address_after(&seen, "goal intake listening on");
    // The upload at ≈ 100 s of mission time (the first cycle at or after it).
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        assert!(!left.is_zero(), "no cycle at 100 s: {seen:?}");
        if let Ok(line) = out.recv_timeout(left.min(Duration::from_millis(50))) {
            let at = cycle_time(&line);
            seen.push(line);
            if at.is_some_and(|t| t >= 100.0) {
                break;
            }
        }
    }
    let send = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .args(["goal", "send", "--to", &format!("udpout:{gcs}")])
        .arg(&plan_file)
        .output()
        .expect("run mavtempo goal send");
    assert!(
        send.status.success(),
        "{}",
        String::from_utf8_lossy(&send.stdout)
    );
    // The mission to its end (Fig. 2 ends at ≈ 530 s: 53 s of wall at 10×, plus a loaded machine).
    let deadline = Instant::now() + Duration::from_secs(120);
    let status = loop {
        if let Some(status) = run.0.try_wait().expect("try_wait") {
            break status;
        }
        seen.extend(out.try_iter());
        assert!(
            Instant::now() < deadline,
            "run still going: {}",
            seen.join("\n")
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    seen.extend(out.try_iter());
    assert!(status.success(), "{status:?}\n{}", seen.join("\n"));
    let text = std::fs::read_to_string(&report_path).expect("report written");
    let r: serde_json::Value = serde_json::from_str(&text).expect("report is JSON");
    let goals = r["goals"].as_array().expect("goals");
    let fate = |name: &str| {
        goals
            .iter()
            .find(|g| g["name"] == name)
            .unwrap_or_else(|| panic!("{name} in {goals:?}"))
    };
    for g in ["g1", "g2", "g3", "g4", "g5"] {
        assert_eq!(fate(g)["fate"], "achieved", "{g}: {goals:?}");
    }
    for g in goals {
        let reason = g["reason"].as_str().unwrap_or("");
        assert!(
            !reason.contains("times within a minute"),
            "lost to the plan-change bound: {g}"
        );
    }
    let new = goals
        .iter()
        .find(|g| !["g1", "g2", "g3", "g4", "g5"].contains(&g["name"].as_str().unwrap_or("")))
        .unwrap_or_else(|| panic!("the uploaded goal in {goals:?}"));
    // 22 m north of home, with the battery Fig. 2 leaves: the new goal is achieved too (the issue's run lost
    // it with three held goals).
    assert_eq!(new["fate"], "achieved", "{new}\n{}", seen.join("\n"));
}
