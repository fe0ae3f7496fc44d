//! `mavtempo demo ARGS --report FILE` as a user runs it: its stdout and the report, read back.

use std::process::Command;

/// Runs `demo` with `args` and `--report` into a temporary file; panics with its output when it fails.
pub fn demo_with_report(args: &[&str]) -> (String, serde_json::Value) {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let report = dir.path().join("report.json");
    let out = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .arg("demo")
        .args(args)
        .arg("--report")
        .arg(&report)
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&report).expect("report written");
    (stdout, serde_json::from_str(&text).expect("JSON"))
}

/// Every event of the report's cycles, in order.
pub fn events(report: &serde_json::Value) -> Vec<serde_json::Value> {
    report["cycles"]
        .as_array()
        .expect("cycles")
        .iter()
        .flat_map(|c| c["events"].as_array().cloned().unwrap_or_default())
        .collect()
}
