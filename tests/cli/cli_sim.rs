//! `mavtempo sim` as a process: bad arguments give clear errors; a good start prints its address
//! and serves MAVLink there.

use crate::support::child;

use std::io::{BufRead, BufReader, Read};
use std::process::Command;
use std::time::{Duration, Instant};

fn mavtempo() -> Command {
    Command::new(env!("CARGO_BIN_EXE_mavtempo"))
}

#[test]
fn bad_arguments_are_refused_with_their_reason() {
    for (args, needle) in [
        (vec!["sim", "--home", "north"], "bad home"),
        (vec!["sim", "--vehicle", "plane"], "unknown vehicle"),
        (vec!["sim", "--speedup=-3"], "bad speed-up"),
        (
            vec!["sim", "--listen", "serial:/dev/ttyS0"],
            "bad listen address",
        ),
        (
            vec!["sim", "--scenario", "/nonexistent/s.toml"],
            "/nonexistent/s.toml",
        ),
    ] {
        let out = mavtempo().args(&args).output().expect("run mavtempo");
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn sim_prints_its_port_and_sends_heartbeats() {
    let (_reap, stdout) = child::spawn_piped(mavtempo().args([
        "sim",
        "--listen",
        "tcpin:127.0.0.1:0",
        "--speedup",
        "20",
    ]));
    let mut line = String::new();
    BufReader::new(stdout)
        .read_line(&mut line)
        .expect("first line");
    let port: u16 = line
        .split_whitespace()
        .nth(3)
        .and_then(|a| a.rsplit(':').next())
        .and_then(|p| p.parse().ok())
        .unwrap_or_else(|| panic!("no port in {line:?}"));
    let mut stream = std::net::TcpStream::connect(("127.0.0.1", port)).expect("connect");
    stream
        .set_read_timeout(Some(Duration::from_secs(5)))
        .expect("timeout");
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut buf = [0u8; 512];
    let mut seen = Vec::new();
    // A MAVLink 2 HEARTBEAT frame: 0xFD, len 9, ..., msgid 0.
    while Instant::now() < deadline {
        let n = stream.read(&mut buf).expect("read");
        seen.extend_from_slice(&buf[..n]);
        if seen
            .windows(10)
            .any(|w| w[0] == 0xFD && w[1] == 9 && w[7..10] == [0, 0, 0])
        {
            break;
        }
    }
    assert!(
        seen.windows(10)
            .any(|w| w[0] == 0xFD && w[1] == 9 && w[7..10] == [0, 0, 0]),
        "no heartbeat frame"
    );
}
