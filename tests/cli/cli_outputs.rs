//! The mission's outputs: a `--report` that cannot be written is refused before the mission (nothing
//! planned or sent, a clear error, a non-zero exit); a report is written whole (through a temporary file
//! renamed over it), leaving no temporary file behind.

use std::process::Command;

fn mavtempo() -> Command {
    Command::new(env!("CARGO_BIN_EXE_mavtempo"))
}

#[test]
fn a_report_into_a_missing_directory_fails_before_the_mission() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let report = dir.path().join("no-such-dir").join("run.json");
    // No vehicle listens there: reaching the link would wait for its heartbeat; the check comes first.
    let out = mavtempo()
        .args(["run", "--config", "config/sitl-rover.toml"])
        .args(["--vehicle", "tcpout:127.0.0.1:9", "--link-timeout", "30"])
        .arg("--report")
        .arg(&report)
        .args([
            "domains/rover/rover.ixt",
            "tests/fixtures/exec/rover_two.ixt",
        ])
        .output()
        .expect("run mavtempo run");
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("cannot write") && err.contains("no-such-dir"),
        "{err}"
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        !stdout.contains("planning"),
        "planned before failing: {stdout}"
    );
}

#[test]
fn demo_writes_its_report_whole_and_leaves_no_temporary_file() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let report = dir.path().join("demo.json");
    std::fs::write(&report, "an older report").expect("write");
    let out = mavtempo()
        .args(["demo", "--quiet", "--no-upload"])
        .args(["--problem", "tests/fixtures/exec/rover_two.ixt"])
        .args(["--scenario", "sitl/scenarios/fig2.toml"])
        .arg("--report")
        .arg(&report)
        .output()
        .expect("run mavtempo demo");
    assert!(out.status.success(), "{out:?}");
    let text = std::fs::read_to_string(&report).expect("report");
    let r: serde_json::Value = serde_json::from_str(&text).expect("whole JSON");
    assert!(r["goals"].as_array().is_some_and(|g| !g.is_empty()));
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["demo.json".to_string()]);
}
