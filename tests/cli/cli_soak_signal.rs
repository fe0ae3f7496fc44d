//! SIGTERM to `mavtempo soak`: the mission under way stops, the summary of the missions done before it is
//! printed (not lost), and the exit code is 143.

use crate::support::child;

use std::process::Command;
use std::time::{Duration, Instant};

use child::{lines, spawn_piped};

#[test]
fn sigterm_prints_the_summary_of_the_missions_done() {
    let (mut soak, stdout) = spawn_piped(Command::new(env!("CARGO_BIN_EXE_mavtempo")).args([
        "soak",
        "--missions",
        "50",
        "--seed",
        "9000",
        "--trace",
    ]));
    let rx = lines(stdout);
    let deadline = Instant::now() + Duration::from_secs(180);
    let mut seen = Vec::new();
    // The first mission's summary (`--trace` prints it): a mission is done.
    while !seen.iter().any(|l: &String| l.starts_with("mission ended")) {
        assert!(Instant::now() < deadline, "no mission ended: {seen:?}");
        if let Ok(l) = rx.recv_timeout(Duration::from_millis(50)) {
            seen.push(l);
        }
    }
    let pid = libc::pid_t::try_from(soak.0.id()).expect("pid fits");
    // SAFETY: kill(2) with the pid of a child we own and have not reaped yet.
    assert_eq!(unsafe { libc::kill(pid, libc::SIGTERM) }, 0);
    let status = loop {
        if let Some(s) = soak.0.try_wait().expect("try_wait") {
            break s;
        }
        assert!(Instant::now() < deadline, "soak did not stop");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert_eq!(status.code(), Some(143), "{status:?}");
    let rest: Vec<String> = rx.try_iter().collect();
    let text = rest.join("\n");
    assert!(
        text.contains("soak interrupted by SIGTERM"),
        "{}",
        &text[text.len().saturating_sub(2000)..]
    );
    let line = rest
        .iter()
        .find(|l| l.starts_with("soak: "))
        .unwrap_or_else(|| panic!("no summary line"));
    let done: u64 = line
        .split_whitespace()
        .nth(1)
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!((1..50).contains(&done), "{line}");
}
