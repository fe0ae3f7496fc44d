//! Child processes of the CLI tests: killed even when an assertion fails.

use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Kills the child process even when an assertion fails.
pub struct Reap(pub Child);

impl Drop for Reap {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Spawns `cmd` with its stdout piped and its stderr dropped: the child, reaped on drop, and its stdout.
pub fn spawn_piped(cmd: &mut Command) -> (Reap, ChildStdout) {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap_or_else(|e| panic!("spawn {cmd:?}: {e}"));
    let stdout = child.stdout.take().expect("stdout");
    (Reap(child), stdout)
}

/// The lines of a child's pipe, as they come.
pub fn lines(pipe: impl std::io::Read + Send + 'static) -> std::sync::mpsc::Receiver<String> {
    use std::io::BufRead;
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in std::io::BufReader::new(pipe).lines() {
            let Ok(line) = line else { break };
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    rx
}

/// Waits (at most `within`) for a line containing `needle`; everything read on the way is kept in `seen`.
pub fn wait_line(
    rx: &mpsc::Receiver<String>,
    needle: &str,
    within: Duration,
    seen: &mut Vec<String>,
) {
    wait_line_once(rx, needle, &mut || true, within, seen);
}

/// Waits (at most `within`) for a line containing `needle` that comes once `ready` holds.
pub fn wait_line_once(
    rx: &mpsc::Receiver<String>,
    needle: &str,
    ready: &mut dyn FnMut() -> bool,
    within: Duration,
    seen: &mut Vec<String>,
) {
    let deadline = Instant::now() + within;
    let mut is_ready = ready();
    loop {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            panic!(
                "no line with {needle:?} within {within:?}:\n{}",
                seen.join("\n")
            );
        }
        match rx.recv_timeout(left.min(Duration::from_millis(20))) {
            Ok(line) => {
                let found = is_ready && line.contains(needle);
                seen.push(line);
                if found {
                    return;
                }
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                panic!("the process ended:\n{}", seen.join("\n"))
            }
        }
        is_ready = is_ready || ready();
    }
}

/// `mavtempo sim` with Fig. 2's scenario paced at `speedup` on a free port: the process and its port.
pub fn fig2_sim(speedup: &str) -> (Reap, u16) {
    let (reap, stdout) = spawn_piped(
        Command::new(env!("CARGO_BIN_EXE_mavtempo"))
            .args(["sim", "--listen", "tcpin:127.0.0.1:0", "--speedup", speedup])
            .args(["--scenario", "sitl/scenarios/fig2.toml"]),
    );
    let mut first = Vec::new();
    let rx = lines(stdout);
    wait_line(
        &rx,
        "sitl listening on",
        Duration::from_secs(30),
        &mut first,
    );
    let port = first
        .last()
        .and_then(|l| l.split_whitespace().nth(3))
        .and_then(|a| a.rsplit(':').next())
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("no port in {first:?}"));
    (reap, port)
}

/// `mavtempo run` with the built-in SITL rover's configuration, paced at `speedup`, against the simulator on
/// `port` (callers add the rest: goals, timeouts, report, domain and problem).
pub fn run_on_sim(port: u16, speedup: &str) -> Command {
    let mut run = Command::new(env!("CARGO_BIN_EXE_mavtempo"));
    run.args([
        "run",
        "--config",
        "config/sitl-rover.toml",
        "--speedup",
        speedup,
    ])
    .args(["--vehicle", &format!("tcpout:127.0.0.1:{port}")]);
    run
}
