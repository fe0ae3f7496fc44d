//! Child processes of the CLI tests: killed even when an assertion fails.
#![allow(dead_code)]

use std::process::{Child, ChildStdout, Command, Stdio};

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
