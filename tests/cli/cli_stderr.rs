//! The command line's stderr: as safe as stdout (a closed stderr loses messages, never the command: no
//! panic, no exit 101), one line per warning (not once from the log and once from the command), no colour
//! codes and no progress bar when it is not a terminal.

use std::fs::File;
use std::process::{Command, Stdio};

fn mavtempo() -> Command {
    Command::new(env!("CARGO_BIN_EXE_mavtempo"))
}

/// stderr a pipe whose reader is gone before the command starts: every write to it fails (EPIPE).
fn closed_stderr() -> Stdio {
    let (reader, writer) = std::io::pipe().expect("pipe");
    drop(reader);
    Stdio::from(writer)
}

/// stderr into a file, as `2> log` does; its text after the run.
fn stderr_of(cmd: &mut Command) -> (std::process::ExitStatus, String) {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let path = dir.path().join("stderr.txt");
    let status = cmd
        .stdout(Stdio::null())
        .stderr(File::create(&path).expect("file"))
        .status()
        .expect("runs");
    (status, std::fs::read_to_string(&path).unwrap_or_default())
}

/// The first-mission template with a home 961 m from the configuration's (a warning at start), in `dir`.
fn far_home_problem(dir: &std::path::Path) -> std::path::PathBuf {
    let far = dir.join("far.ixt");
    let text = std::fs::read_to_string("domains/vehicle/problems/first.ixt").expect("template");
    std::fs::write(
        &far,
        text.replace("horizon 15min;", "horizon 15min;\nhome lat 43.57 lon 1.48;"),
    )
    .expect("write");
    far
}

/// `demo` of `problem` on the generic vehicle, stdout dropped.
fn demo(problem: &std::path::Path) -> Command {
    let mut cmd = mavtempo();
    cmd.args(["demo", "--quiet", "--domain", "domains/vehicle/vehicle.ixt"])
        .args(["--config", "config/sitl-vehicle.toml", "--problem"])
        .arg(problem)
        .stdout(Stdio::null());
    cmd
}

#[test]
fn a_closed_stderr_does_not_panic() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let bad = dir.path().join("bad.ixt");
    std::fs::write(&bad, "problem p;\ndomain vehicle;\nobject x: nowhere;\n").expect("write");
    // An error said on stderr: the command fails as it should (1), not with a panic (101).
    let status = mavtempo()
        .arg("check")
        .arg("domains/vehicle/vehicle.ixt")
        .arg(&bad)
        .stdout(Stdio::null())
        .stderr(closed_stderr())
        .status()
        .expect("runs");
    assert_eq!(status.code(), Some(1));
    // Warnings on stderr while a mission runs: the mission ends normally.
    let status = demo(&far_home_problem(dir.path()))
        .stderr(closed_stderr())
        .status()
        .expect("runs");
    assert_eq!(status.code(), Some(0));
}

/// The configuration's home 961 m from the problem's: one warning line, plain text.
#[test]
fn a_warning_is_one_plain_line() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let (status, err) = stderr_of(&mut demo(&far_home_problem(dir.path())));
    assert!(status.success(), "{err}");
    let home: Vec<&str> = err.lines().filter(|l| l.contains("home:")).collect();
    assert_eq!(home.len(), 1, "{err}");
    assert!(home[0].starts_with("config/sitl-vehicle.toml:"), "{err}");
    assert!(!err.contains('\u{1b}'), "colour codes in a file: {err:?}");
}

/// Redirected, `soak` and `experiment` draw no progress bar.
#[test]
fn no_progress_bar_off_a_terminal() {
    let (status, err) = stderr_of(mavtempo().args(["soak", "--missions", "1", "--seed", "9000"]));
    assert!(status.success(), "{err}");
    assert!(!err.contains('\r') && !err.contains("missions,"), "{err:?}");
    let (status, err) = stderr_of(mavtempo().args([
        "experiment",
        "dispatch",
        "--seeds",
        "1",
        "--scenario",
        "auv",
        "--policy",
        "earliest",
    ]));
    assert!(status.success(), "{err}");
    assert!(!err.contains('\r') && !err.contains("] 1/"), "{err:?}");
}
