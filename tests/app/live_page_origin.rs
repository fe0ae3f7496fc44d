//! The live page refuses a POST from another site (a cross-origin `Origin`) and one whose `Host` is not the
//! page itself (DNS rebinding), over a real socket; the page's own POST gets through the check.

use mavtempo_testkit::http;

use std::net::SocketAddr;
use std::time::Duration;

/// POSTs the goal form to `addr` with these `Host` and `Origin` headers: the status and the body.
fn post(addr: SocketAddr, host: &str, origin: Option<&str>) -> (u16, String) {
    let form = "east=3&north=2&window_end_s=1800&d_achiev_s=60";
    let origin = origin.map_or(String::new(), |o| format!("Origin: {o}\r\n"));
    let req = format!(
        "POST /goal HTTP/1.1\r\nHost: {host}\r\n{origin}Connection: close\r\n\
         Content-Type: application/x-www-form-urlencoded\r\nContent-Length: {}\r\n\r\n{form}",
        form.len()
    );
    http::exchange(addr, &req, Duration::from_secs(30))
}

#[test]
fn cross_origin_and_rebound_posts_are_refused() {
    let rt = tokio::runtime::Runtime::new().expect("runtime");
    let server =
        mavtempo::report::live::start(rt.handle(), SocketAddr::from(([127, 0, 0, 1], 0)), None)
            .expect("live page");
    let addr = server.addr;
    let own = addr.to_string();

    let (status, body) = post(addr, &own, Some("http://evil.example"));
    assert_eq!(status, 403, "{body}");
    assert!(body.contains("cross-origin"), "{body}");

    let (status, body) = post(addr, "evil.example", None);
    assert_eq!(status, 403, "{body}");
    assert!(body.contains("is not this page"), "{body}");

    // The page's own POST passes the check; the form itself is off here.
    let (status, body) = post(addr, &own, Some(&format!("http://{own}")));
    assert_eq!(status, 403, "{body}");
    assert!(body.contains("--http-goals"), "{body}");
    let (status, body) = post(addr, &format!("localhost:{}", addr.port()), None);
    assert!(body.contains("--http-goals"), "{status} {body}");
}
