//! A closed standard output (`mavtempo plan … | head`, a `tee` that died) never panics: a command that only
//! prints stops quietly with success, a live mission goes on to its end. The child's stdout is a pipe whose
//! reading end is closed before it starts, so every write it makes fails (no race with the reader).

use std::process::{Command, Stdio};

/// A pipe with no reader left: writing to it fails with a broken pipe.
fn closed_stdout() -> Stdio {
    let (reader, writer) = std::io::pipe().expect("pipe");
    drop(reader);
    Stdio::from(writer)
}

#[test]
fn a_printing_command_stops_quietly() {
    let out = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .args([
            "plan",
            "domains/rover/rover.ixt",
            "domains/rover/problems/fig2.ixt",
            "--json",
        ])
        .stdout(closed_stdout())
        .stderr(Stdio::piped())
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.status.success(), "{:?}: {stderr}", out.status);
}

#[test]
fn a_live_mission_goes_on_to_its_end() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let report_path = dir.path().join("report.json");
    let out = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .args(["demo", "--no-upload", "--problem"])
        .arg("tests/fixtures/exec/rover_two.ixt")
        .args(["--scenario", "sitl/scenarios/fig2.toml", "--report"])
        .arg(&report_path)
        .stdout(closed_stdout())
        .stderr(Stdio::piped())
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.status.success(), "{:?}: {stderr}", out.status);
    assert!(stderr.contains("going on without printing"), "{stderr}");
    let text = std::fs::read_to_string(&report_path).expect("report written");
    let report: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    assert_eq!(report["end"], "finished", "{}", report["end"]);
    let goals = report["goals"].as_array().expect("goals");
    assert!(goals.iter().all(|g| g["fate"] == "achieved"), "{goals:?}");
}
