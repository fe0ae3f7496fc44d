//! A closed standard output (`mavtempo plan … | head`, a `tee` that died) never panics: a command that only
//! prints stops quietly with success, a live mission goes on to its end. The child's stdout is a pipe whose
//! reading end is closed before it starts, so every write it makes fails (no race with the reader).

use std::process::{Command, Stdio};

/// Runs `mavtempo ARGS` with a stdout that has no reader left (every write fails with a broken pipe);
/// checks that it neither panicked nor failed, and returns its stderr.
fn run_with_closed_stdout(args: &[&str]) -> String {
    let (reader, writer) = std::io::pipe().expect("pipe");
    drop(reader);
    let out = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .args(args)
        .stdout(Stdio::from(writer))
        .stderr(Stdio::piped())
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(out.status.success(), "{:?}: {stderr}", out.status);
    stderr
}

#[test]
fn a_printing_command_stops_quietly() {
    run_with_closed_stdout(&[
        "plan",
        "domains/rover/rover.ixt",
        "domains/rover/problems/fig2.ixt",
        "--json",
    ]);
}

#[test]
fn a_live_mission_goes_on_to_its_end() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let report_path = dir.path().join("report.json");
    let report_arg = report_path.to_str().expect("UTF-8 temp path");
    let stderr = run_with_closed_stdout(&[
        "demo",
        "--no-upload",
        "--problem",
        "tests/fixtures/exec/rover_two.ixt",
        "--scenario",
        "sitl/scenarios/fig2.toml",
        "--report",
        report_arg,
    ]);
    assert!(stderr.contains("going on without printing"), "{stderr}");
    let text = std::fs::read_to_string(&report_path).expect("report written");
    let report: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    assert_eq!(report["end"], "finished", "{}", report["end"]);
    let goals = report["goals"].as_array().expect("goals");
    assert!(goals.iter().all(|g| g["fate"] == "achieved"), "{goals:?}");
}
