//! Issue 31: the live page's connections are bounded, over real sockets. Clients that open a connection and
//! send nothing, or trickle a request head that never ends, are dropped after the (short, configured)
//! header timeout; a client idle after its answer is dropped after the idle timeout; hundreds of slow
//! clients hold at most the cap of the page's descriptors and never keep a normal client from its page.

use mavtempo_testkit::http;

use std::io::{ErrorKind, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::Arc;
use std::time::{Duration, Instant};

use mavtempo::report::guard::PageLimits;
use mavtempo::report::live::{start_with, GoalForm, LiveServer, PictureGoal};
use mavtempo::vehicle::goal_client::GoalSendReport;

const DEADLINE: Duration = Duration::from_secs(30);

fn serve(rt: &tokio::runtime::Runtime, limits: PageLimits) -> LiveServer {
    start_with(
        rt.handle(),
        SocketAddr::from(([127, 0, 0, 1], 0)),
        None,
        limits,
    )
    .expect("live page")
}

/// Polls `s` until the server closes it (end of stream or reset), at most DEADLINE: when it did.
fn closed_at(s: &mut TcpStream) -> Instant {
    s.set_read_timeout(Some(Duration::from_millis(50)))
        .expect("timeout");
    let deadline = Instant::now() + DEADLINE;
    let mut buf = [0u8; 4096];
    loop {
        match s.read(&mut buf) {
            Ok(0) => return Instant::now(),
            Ok(_) => {}
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
            Err(_) => return Instant::now(),
        }
        assert!(Instant::now() < deadline, "still open after {DEADLINE:?}");
    }
}

/// A normal client's page: the status.
fn get_page(addr: SocketAddr) -> u16 {
    let req = format!("GET / HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n");
    http::exchange(addr, &req, DEADLINE).0
}

#[test]
fn silent_slow_and_idle_clients_are_dropped_after_their_timeouts() {
    let rt = tokio::runtime::Runtime::new().expect("runtime");
    let limits = PageLimits {
        max_connections: 32,
        header_timeout: Duration::from_millis(400),
        idle_timeout: Duration::from_millis(700),
    };
    let server = serve(&rt, limits);
    let addr = server.addr;

    let opened = Instant::now();
    let mut silent = TcpStream::connect(addr).expect("connect");
    let mut slow = TcpStream::connect(addr).expect("connect");
    slow.write_all(b"GET / HTTP/1.1\r\nHost: ").expect("send");
    let mut slow_body = TcpStream::connect(addr).expect("connect");
    slow_body
        .write_all(
            format!("POST /goal HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/x-www-form-urlencoded\r\nContent-Length: 50\r\n\r\neast=")
                .as_bytes(),
        )
        .expect("send");
    let mut idle = TcpStream::connect(addr).expect("connect");
    idle.write_all(format!("GET /favicon.ico HTTP/1.1\r\nHost: {addr}\r\n\r\n").as_bytes())
        .expect("send");

    // Never before their timeout: the server cannot have closed them earlier than that.
    let t = closed_at(&mut silent);
    assert!(t - opened >= limits.header_timeout, "{:?}", t - opened);
    let t = closed_at(&mut slow);
    assert!(t - opened >= limits.header_timeout, "{:?}", t - opened);
    // A body that stops coming is idle.
    let t = closed_at(&mut slow_body);
    assert!(t - opened >= limits.idle_timeout, "{:?}", t - opened);
    // Answered (204), then kept alive until the idle timeout.
    let t = closed_at(&mut idle);
    assert!(t - opened >= limits.idle_timeout, "{:?}", t - opened);
    assert_eq!(get_page(addr), 200);
}

#[test]
fn hundreds_of_slow_clients_hold_at_most_the_cap_and_a_normal_client_is_served() {
    let rt = tokio::runtime::Runtime::new().expect("runtime");
    let limits = PageLimits {
        max_connections: 8,
        // Long: here they must go by eviction, not by timing out.
        header_timeout: Duration::from_secs(120),
        idle_timeout: Duration::from_secs(120),
    };
    let server = serve(&rt, limits);
    let addr = server.addr;
    let mut slow: Vec<TcpStream> = (0..200)
        .map(|i| {
            let mut s = TcpStream::connect(addr).expect("connect");
            if i % 2 == 0 {
                s.write_all(b"GET / HTTP/1.1\r\nX-Slow: ").expect("send");
            }
            s
        })
        .collect();
    // Wait until the server has seen them all (each one taken in, evicting an older one).
    let deadline = Instant::now() + DEADLINE;
    while server.slots.evictions() + server.slots.refused() < 192 {
        assert!(
            Instant::now() < deadline,
            "the server did not take the clients in"
        );
        std::thread::sleep(Duration::from_millis(20));
        assert!(server.slots.open() <= limits.max_connections + 1);
    }
    assert!(server.slots.open() <= limits.max_connections);
    // A normal client gets its page at once, three times over, while the slow ones keep coming.
    for _ in 0..3 {
        assert_eq!(get_page(addr), 200);
        slow.push(TcpStream::connect(addr).expect("connect"));
    }
    assert!(server.slots.open() <= limits.max_connections);
    // The slow clients beyond the cap were closed by the server: their descriptors are free again.
    let first = slow.first_mut().expect("a client");
    closed_at(first);
}

/// A request whose answer takes longer than the idle timeout (a goal upload waits for the executive's
/// verdict) is answered, not cut as idle.
#[test]
fn a_slow_answer_is_not_idle() {
    let rt = tokio::runtime::Runtime::new().expect("runtime");
    let limits = PageLimits {
        max_connections: 8,
        header_timeout: Duration::from_millis(300),
        idle_timeout: Duration::from_millis(300),
    };
    let answer_after = limits.idle_timeout * 3;
    let form = GoalForm {
        items: Arc::new(|_: &PictureGoal| Vec::new()),
        submit: Arc::new(move |_| {
            Box::pin(async move {
                // The intake's verdict comes late.
                tokio::time::sleep(answer_after).await;
                Ok(GoalSendReport {
                    failure: None,
                    texts: vec!["g9 accepted: picture_of(g9_loc)".into()],
                })
            })
        }),
        cancel: None,
    };
    let server = start_with(
        rt.handle(),
        SocketAddr::from(([127, 0, 0, 1], 0)),
        Some(form),
        limits,
    )
    .expect("live page");
    let addr = server.addr;
    let fields = "east=30&north=2&window_end_s=1800&d_achiev_s=60";
    let req = format!(
        "POST /goal HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\
         Content-Type: application/x-www-form-urlencoded\r\nContent-Length: {}\r\n\r\n{fields}",
        fields.len()
    );
    let (status, body) = http::exchange(addr, &req, DEADLINE);
    assert_eq!(status, 200, "{body}");
    assert!(body.contains("g9 accepted"), "{body}");
}
