//! SIGTERM / SIGINT to `mavtempo run` (against a `mavtempo sim` process) and to `mavtempo demo`, as an
//! operator or a supervisor sends them mid-mission: the vehicle is put in HOLD and seen in it, the report is
//! written with the end `interrupted`, the `.tlog` ends on a frame boundary, the exit code is 128 + the
//! signal's number; a second signal exits at once.

use crate::support::child;

use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage};
use mavtempo::vehicle::frame::FrameDecoder;
use mavtempo::vehicle::tlog::read_tlog;

use child::{fig2_sim, lines, spawn_piped, wait_line, wait_line_once, Reap};

/// ArduPilot Rover's custom modes (config/sitl-rover.toml).
const HOLD: u32 = 4;
const GUIDED: u32 = 15;

fn send_signal(child: &Child, signal: i32) {
    let pid = libc::pid_t::try_from(child.id()).expect("pid fits");
    // SAFETY: kill(2) with the pid of a child we own and have not reaped yet.
    let r = unsafe { libc::kill(pid, signal) };
    assert_eq!(r, 0, "kill({pid}, {signal})");
}

/// Polls the child until it exits, at most `within`.
fn wait_exit(child: &mut Child, within: Duration) -> ExitStatus {
    let deadline = Instant::now() + within;
    loop {
        if let Some(status) = child.try_wait().expect("try_wait") {
            return status;
        }
        assert!(Instant::now() < deadline, "still running after {within:?}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The `.tlog` has passed its writer's 8 KiB buffer on disk (where the issue found it cut mid-frame).
fn past_8_kib(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| m.len() >= 8192)
}

/// `mavtempo run` of the two-goal rover problem against the SITL at `port`, with a `.tlog` and a report
/// in `dir`: the process and its stdout and stderr lines.
fn run(
    port: u16,
    speedup: &str,
    dir: &Path,
) -> (Reap, mpsc::Receiver<String>, mpsc::Receiver<String>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_mavtempo"))
        .args([
            "run",
            "--config",
            "config/sitl-rover.toml",
            "--speedup",
            speedup,
        ])
        .args(["--vehicle", &format!("tcpout:127.0.0.1:{port}")])
        .arg("--tlog")
        .arg(dir.join("run.tlog"))
        .arg("--report")
        .arg(dir.join("run.json"))
        .args([
            "domains/rover/rover.ixt",
            "tests/fixtures/exec/rover_two.ixt",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn mavtempo run");
    let out = lines(child.stdout.take().expect("stdout"));
    let err = lines(child.stderr.take().expect("stderr"));
    (Reap(child), out, err)
}

/// The `.tlog`'s frames, each read whole: the file must end on a frame boundary.
fn tlog_messages(path: &Path) -> Vec<(u8, u8, MavMessage)> {
    let bytes = std::fs::read(path).expect("tlog written");
    let records = read_tlog(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(!records.is_empty());
    records
        .iter()
        .filter_map(|(_, frame)| {
            let mut d = FrameDecoder::default();
            d.push(frame);
            let f = d.next_frame()?;
            Some((f.system_id, f.component_id, f.parse()?))
        })
        .collect()
}

/// The custom modes of the autopilot's HEARTBEATs, in order.
fn autopilot_modes(messages: &[(u8, u8, MavMessage)]) -> Vec<u32> {
    messages
        .iter()
        .filter_map(|(s, c, m)| match m {
            MavMessage::HEARTBEAT(h) if (*s, *c) == (1, 1) => Some(h.custom_mode),
            _ => None,
        })
        .collect()
}

fn report(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).expect("report written");
    serde_json::from_str(&text).expect("report is JSON")
}

/// The report of a run stopped by `signal` while the rover moved: the end, the safe stop, the goals.
fn assert_interrupted_report(r: &serde_json::Value, signal: &str) {
    assert_eq!(r["end"]["interrupted"], signal, "{}", r["end"]);
    let s = &r["shutdown"];
    assert_eq!(s["action"], "hold", "{s}");
    assert_eq!(s["outcome"], "confirmed", "{s}");
    assert_eq!(s["mode"], HOLD, "{s}");
    assert_eq!(s["last_mode"], HOLD, "{s}");
    assert!(
        s["stopped"]
            .as_array()
            .is_some_and(|a| a.iter().any(|t| t == "move")),
        "{s}"
    );
    let goals = r["goals"].as_array().expect("goals");
    assert!(!goals.is_empty());
    for g in goals.iter().filter(|g| g["fate"] == "pending") {
        assert!(
            g["reason"]
                .as_str()
                .is_some_and(|t| t.contains(&format!("interrupted ({signal})"))),
            "{g}"
        );
    }
    assert!(r["cycles"].as_array().is_some_and(|c| !c.is_empty()));
}

/// `run` against `sim` (both at 5×), with its report and `.tlog` in `dir`, once a move has started after the
/// `.tlog` passed 8 KiB: the rover is moving (GUIDED) when a signal comes.
struct Moving {
    sim: Reap,
    run: Reap,
    /// Kept open: the child's stdout is read until the test ends.
    _out: mpsc::Receiver<String>,
    err: mpsc::Receiver<String>,
    seen: Vec<String>,
}

fn moving(dir: &Path) -> Moving {
    let (sim, port) = fig2_sim("5");
    let (run, out, err) = run(port, "5", dir);
    let mut seen = Vec::new();
    let tlog = dir.join("run.tlog");
    wait_line_once(
        &out,
        "START move(",
        &mut || past_8_kib(&tlog),
        Duration::from_secs(120),
        &mut seen,
    );
    Moving {
        sim,
        run,
        _out: out,
        err,
        seen,
    }
}

#[test]
fn sigterm_during_run_holds_the_rover_writes_the_report_and_a_whole_tlog() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    // Every pipe stays read until the end: a closed one would fail the child's next print.
    let Moving {
        sim: _sim,
        mut run,
        _out,
        err: _err,
        ..
    } = moving(dir.path());
    send_signal(&run.0, libc::SIGTERM);
    let status = wait_exit(&mut run.0, Duration::from_secs(30));
    assert_eq!(status.code(), Some(143), "{status:?}");

    let r = report(&dir.path().join("run.json"));
    assert_interrupted_report(&r, "SIGTERM");

    let messages = tlog_messages(&dir.path().join("run.tlog"));
    let hold_sent = messages.iter().any(|(_, c, m)| {
        *c == 191
            && matches!(m, MavMessage::COMMAND_LONG(l)
                if l.command == MavCmd::MAV_CMD_DO_SET_MODE && l.param2 == HOLD as f32)
    });
    assert!(
        hold_sent,
        "no DO_SET_MODE(HOLD) from the companion in the tlog"
    );
    let modes = autopilot_modes(&messages);
    assert!(modes.contains(&GUIDED), "never moving: {modes:?}");
    assert_eq!(modes.last(), Some(&HOLD), "{modes:?}");
}

#[test]
fn a_second_signal_exits_at_once_with_whole_frames_in_the_tlog() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let Moving {
        sim,
        mut run,
        _out,
        err,
        mut seen,
    } = moving(dir.path());
    // A vehicle that no longer answers: the orderly stop would wait for its HOLD for seconds.
    send_signal(&sim.0, libc::SIGSTOP);
    send_signal(&run.0, libc::SIGINT);
    wait_line(&err, "SIGINT received", Duration::from_secs(10), &mut seen);
    let second = Instant::now();
    send_signal(&run.0, libc::SIGINT);
    let status = wait_exit(&mut run.0, Duration::from_secs(10));
    let took = second.elapsed();
    send_signal(&sim.0, libc::SIGCONT);
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert!(took < Duration::from_secs(2), "exit took {took:?}");
    assert!(
        !dir.path().join("run.json").exists(),
        "the orderly stop did not finish: no report"
    );
    // Whatever reached the disk is whole frames, and the buffer was flushed on the way out.
    let messages = tlog_messages(&dir.path().join("run.tlog"));
    let on_disk = std::fs::metadata(dir.path().join("run.tlog")).map_or(0, |m| m.len());
    assert!(on_disk > 8192 && messages.len() > 100, "{on_disk} bytes");
}

#[test]
fn sigint_during_demo_holds_the_rover_and_writes_the_report() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let report_path = dir.path().join("demo.json");
    let (mut demo, stdout) = spawn_piped(
        Command::new(env!("CARGO_BIN_EXE_mavtempo"))
            .args(["demo", "--no-upload", "--speedup", "10"])
            .args(["--problem", "tests/fixtures/exec/rover_two.ixt"])
            .args(["--scenario", "sitl/scenarios/fig2.toml"])
            .arg("--report")
            .arg(&report_path),
    );
    let out = lines(stdout);
    let mut seen = Vec::new();
    wait_line(&out, "START move(", Duration::from_secs(120), &mut seen);
    send_signal(&demo.0, libc::SIGINT);
    let status = wait_exit(&mut demo.0, Duration::from_secs(30));
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert_interrupted_report(&report(&report_path), "SIGINT");
}
