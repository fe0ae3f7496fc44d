//! Issue 18: the live page over a real socket (port 0). The demo serves the page, pushes snapshots that
//! change as the mission runs (server-sent events), and its goal form goes through the goal intake: a
//! goal the acceptance test passes is accepted, one whose start window is already over is rejected with
//! the test's reason. Without `--http-goals` the form is off.

use mavtempo_testkit::http;

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use mavtempo::cli::demo::{run_demo, DemoSetup};
use mavtempo::cli::http_arg::HttpSpec;
use mavtempo::exec::executive::Fate;
use mavtempo::exec::interrupt::Interrupt;
use mavtempo::report::live::GoalAnswer;

const DEADLINE: Duration = Duration::from_secs(90);

/// One request, `Connection: close`: the status code and the body.
fn http(addr: SocketAddr, method: &str, path: &str, form: &str) -> (u16, String) {
    let req = format!(
        "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\
         Content-Type: application/x-www-form-urlencoded\r\nContent-Length: {}\r\n\r\n{form}",
        form.len()
    );
    http::exchange(addr, &req, DEADLINE)
}

/// The `data-now-ms` of each snapshot the event stream delivers, until `n` different ones came.
fn snapshot_times(addr: SocketAddr, n: usize) -> Vec<u64> {
    let mut s = TcpStream::connect(addr).expect("connect");
    s.set_read_timeout(Some(Duration::from_millis(500)))
        .expect("timeout");
    let req = format!("GET /events HTTP/1.1\r\nHost: {addr}\r\nAccept: text/event-stream\r\n\r\n");
    s.write_all(req.as_bytes()).expect("send");
    let deadline = Instant::now() + DEADLINE;
    let mut text = String::new();
    let mut buf = [0u8; 65536];
    loop {
        let times: Vec<u64> = text
            .split("data-now-ms=\"")
            .skip(1)
            .filter_map(|t| t.split('"').next()?.parse().ok())
            .collect();
        let mut distinct = times.clone();
        distinct.dedup();
        if distinct.len() >= n || Instant::now() >= deadline {
            return distinct;
        }
        if let Ok(k) = s.read(&mut buf) {
            text.push_str(&String::from_utf8_lossy(&buf[..k]));
        }
    }
}

/// The goals of a demo run, with their fates.
type DemoGoals =
    std::thread::JoinHandle<Result<Vec<(String, Fate)>, mavtempo::cli::error::CliError>>;

/// The demo at 20x with its live page; the address it printed.
fn start(goals: bool) -> (SocketAddr, Interrupt, DemoGoals) {
    let interrupt = Interrupt::default();
    let setup = DemoSetup {
        speedup: Some(20.0),
        upload: false,
        interrupt: interrupt.clone(),
        http: Some(HttpSpec {
            addr: "127.0.0.1:0".parse().expect("addr"),
            goals,
        }),
        ..DemoSetup::default()
    };
    let (tx, rx) = mpsc::channel();
    let demo = std::thread::spawn(move || {
        let run = run_demo(
            &setup,
            &mut |line| {
                if let Some(a) = line.strip_prefix("http listening on http://") {
                    let _ = tx.send(a.trim_end_matches('/').to_string());
                }
            },
            &mut |_| {},
        )?;
        Ok(run
            .report
            .goals
            .into_iter()
            .map(|g| (g.name, g.fate))
            .collect())
    });
    let addr = rx
        .recv_timeout(DEADLINE)
        .unwrap_or_else(|e| panic!("no address printed: {e}"));
    (addr.parse().expect("printed address"), interrupt, demo)
}

/// POSTs the goal form's fields: the status and the answer.
fn post_goal(addr: SocketAddr, fields: &str) -> (u16, GoalAnswer) {
    let (status, body) = http(addr, "POST", "/goal", fields);
    let a = serde_json::from_str(&body).unwrap_or_else(|e| panic!("{e}: {body}"));
    (status, a)
}

/// Polls `done` until it holds, at most DEADLINE.
fn poll_until(what: &str, mut done: impl FnMut() -> bool) {
    let deadline = Instant::now() + DEADLINE;
    while !done() {
        assert!(Instant::now() < deadline, "{what}: not within {DEADLINE:?}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn the_live_page_updates_and_its_form_goes_through_the_intake() {
    let (addr, interrupt, demo) = start(true);
    // Issue 31: a hundred clients that never finish a request (more than the page's connections) block
    // neither the page nor the mission: everything below still happens.
    let _slow: Vec<TcpStream> = (0..100)
        .map(|_| {
            let mut s = TcpStream::connect(addr).expect("connect");
            s.write_all(b"GET / HTTP/1.1\r\nX-Slow: ").expect("send");
            s
        })
        .collect();
    let (status, page) = http(addr, "GET", "/", "");
    assert_eq!(status, 200);
    assert!(page.contains("id=\"goal-form\"") && page.contains("EventSource"));
    // The goals show from the first snapshot on.
    poll_until("goals on the page", || {
        http(addr, "GET", "/", "").1.contains("data-goal=\"g1\"")
    });

    // The snapshots move on with the mission.
    let times = snapshot_times(addr, 3);
    assert!(
        times.len() >= 3 && times.windows(2).all(|w| w[0] < w[1]),
        "{times:?}"
    );

    // The track (the vehicle's reported positions) and the places on the map.
    poll_until("a track on the map", || {
        let (_, snap) = http(addr, "GET", "/snapshot.json", "");
        snap.contains("\"track\":[{") && snap.contains("\"name\":\"p1\"")
    });

    let (status, ok) = post_goal(addr, "east=30&north=2&window_end_s=1800&d_achiev_s=60");
    assert_eq!(status, 200);
    assert!(ok.accepted, "{ok:?}");
    let name = ok.verdict.split(' ').next().unwrap_or("").to_string();
    assert!(
        ok.verdict.starts_with(&format!("{name} accepted: ")),
        "{ok:?}"
    );

    // Its start window is over: the acceptance test of seed 1 §3.3 rejects it, with its reason.
    let (_, no) = post_goal(addr, "east=30&north=2&window_end_s=1&d_achiev_s=60");
    assert!(!no.accepted);
    assert!(
        no.verdict.contains(" rejected: ") && no.verdict.contains("start window"),
        "{no:?}"
    );
    let (status, bad) = post_goal(addr, "east=far&north=2&window_end_s=1&d_achiev_s=60");
    assert_eq!(status, 400);
    assert!(bad.verdict.contains("east: not a number"), "{bad:?}");

    // Issue 30: the accepted goal is on the page as the operator reads it — accepted (not "pending"),
    // what, where, its window, the station that uploaded it, and a cancel button.
    poll_until(&format!("{name} accepted on the page"), || {
        goal_row(addr, &name).is_some_and(|g| g["state"] == "accepted" && g["cancellable"] == true)
    });
    let row = goal_row(addr, &name).expect("the row");
    assert_eq!(row["source"], "ground station 255/190", "{row}");
    assert!(
        row["what"]
            .as_str()
            .is_some_and(|w| w.starts_with("PICTURE(")),
        "{row}"
    );
    assert!(
        row["where"]
            .as_str()
            .is_some_and(|w| w.contains("30 m E, 2 m N")),
        "{row}"
    );
    assert!(
        row["window"]
            .as_str()
            .is_some_and(|w| w.ends_with("1800s]")),
        "{row}"
    );
    let problem_goal = goal_row(addr, "g1").expect("g1");
    assert_eq!(problem_goal["source"], "problem", "{problem_goal}");
    assert!(problem_goal.get("cancellable").is_none(), "{problem_goal}");
    // The vehicle: its mode, arming, battery and link.
    let snap: serde_json::Value =
        serde_json::from_str(&http(addr, "GET", "/snapshot.json", "").1).expect("JSON");
    let v = &snap["vehicle"];
    assert_eq!(v["mode"], "GUIDED", "{v}");
    assert_eq!(v["armed"], true, "{v}");
    assert!(
        v["battery_percent"].as_f64().is_some_and(|b| b > 0.0),
        "{v}"
    );
    assert_eq!(v["link"], "up", "{v}");

    // Cancel: a problem goal is held by no station; the uploaded one is withdrawn by its station's list.
    let (status, no) = post_cancel(addr, "g1");
    assert_eq!(status, 409, "{no:?}");
    assert!(!no.accepted && no.verdict.contains("not held"), "{no:?}");
    let (status, done) = post_cancel(addr, &name);
    assert_eq!(status, 200, "{done:?}");
    assert!(
        done.accepted && done.verdict.contains(&format!("{name} cancelled: ")),
        "{done:?}"
    );
    poll_until(&format!("{name} cancelled on the page"), || {
        goal_row(addr, &name)
            .is_some_and(|g| g["state"] == "cancelled" && g.get("cancellable").is_none())
    });
    interrupt.request(15);
    let goals = demo.join().expect("demo thread").expect("demo");
    assert!(
        goals.contains(&(name.clone(), Fate::Cancelled)),
        "{goals:?}"
    );
}

/// Goal `name`'s row in the page's snapshot.
fn goal_row(addr: SocketAddr, name: &str) -> Option<serde_json::Value> {
    let (_, snap) = http(addr, "GET", "/snapshot.json", "");
    let snap: serde_json::Value = serde_json::from_str(&snap).ok()?;
    snap["goals"]
        .as_array()?
        .iter()
        .find(|g| g["name"] == name)
        .cloned()
}

/// POSTs the page's cancel of goal `name`: the status and the answer.
fn post_cancel(addr: SocketAddr, name: &str) -> (u16, GoalAnswer) {
    let (status, body) = http(addr, "POST", "/cancel", &format!("goal={name}"));
    let a = serde_json::from_str(&body).unwrap_or_else(|e| panic!("{e}: {body}"));
    (status, a)
}

#[test]
fn the_goal_form_is_off_by_default() {
    let (addr, interrupt, demo) = start(false);
    let (status, page) = http(addr, "GET", "/", "");
    assert_eq!(status, 200);
    assert!(!page.contains("id=\"goal-form\""));
    let (status, a) = post_goal(addr, "east=30&north=2&window_end_s=1800&d_achiev_s=60");
    assert_eq!(status, 403);
    assert!(!a.accepted && a.verdict.contains("--http-goals"), "{a:?}");
    interrupt.request(15);
    let goals = demo.join().expect("demo thread").expect("demo");
    // Nothing was uploaded: only the problem's goals.
    assert_eq!(goals.len(), 5, "{goals:?}");
}
