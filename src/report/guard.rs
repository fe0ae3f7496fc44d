//! The live page's connections kept within bounds (issue 31): a request's head must arrive within the header
//! timeout, a connection with no traffic either way for the idle timeout is closed, and at most
//! [`PageLimits::max_connections`] are open at once, far below the process's descriptor limit, so that slow
//! or idle clients can neither hold the page nor take the descriptors the mission's link, `.tlog` and report
//! need. When every slot is taken, a newcomer evicts the connection still waiting for a request head (the
//! oldest first; else the one quiet the longest): a normal client is served while slow ones come and go.

use std::future::Future;
use std::io;
use std::pin::Pin;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll, Waker};
use std::time::Duration;

use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};
use tokio::net::{TcpListener, TcpStream};
use tokio::time::{Instant, Sleep};

/// The page's bounds on its connections.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PageLimits {
    /// Connections open at once (further capped by the descriptor limit, [`connection_cap`]).
    pub max_connections: usize,
    /// From a connection's first byte of a request (or its opening) to the end of the request's head.
    pub header_timeout: Duration,
    /// No byte read or written for this long: the connection is closed.
    pub idle_timeout: Duration,
}

impl Default for PageLimits {
    fn default() -> Self {
        Self {
            max_connections: 64,
            header_timeout: Duration::from_secs(10),
            idle_timeout: Duration::from_secs(60),
        }
    }
}

/// The soft limit on open descriptors (`ulimit -n`), when the system says (Linux: `/proc/self/limits`).
pub fn fd_soft_limit() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/limits").ok()?;
    let line = text.lines().find(|l| l.starts_with("Max open files"))?;
    line["Max open files".len()..]
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// At most an eighth of the descriptor limit goes to the page: the rest is the mission's.
pub fn connection_cap(wanted: usize, fd_soft_limit: Option<u64>) -> usize {
    let share = fd_soft_limit.map_or(usize::MAX, |n| usize::try_from(n / 8).unwrap_or(usize::MAX));
    wanted.min(share).max(1)
}

/// One open connection as the slots see it.
struct ConnState {
    /// Waiting for (or receiving) a request's head: the first to go when the slots are full.
    in_head: AtomicBool,
    /// Its request is whole and its answer not begun (a goal upload may take a while): not idle, and not
    /// evicted for being quiet.
    answering: AtomicBool,
    evicted: AtomicBool,
    /// When it last read or wrote, ms since the slots' epoch.
    active_ms: AtomicU64,
    opened_ms: u64,
    waker: Mutex<Option<Waker>>,
}

impl ConnState {
    fn evict(&self) {
        self.evicted.store(true, Ordering::Release);
        if let Some(w) = self.waker.lock().ok().and_then(|mut w| w.take()) {
            w.wake();
        }
    }
}

/// The open connections, in the order they came.
pub struct Slots {
    open: Mutex<Vec<Arc<ConnState>>>,
    cap: usize,
    epoch: Instant,
    refused: AtomicU64,
    evictions: AtomicU64,
}

impl Slots {
    fn now_ms(&self) -> u64 {
        self.epoch.elapsed().as_millis() as u64
    }

    /// Connections open now (evicted ones that have not closed yet included).
    pub fn open(&self) -> usize {
        self.open.lock().map_or(0, |o| o.len())
    }

    /// The cap in force.
    pub fn cap(&self) -> usize {
        self.cap
    }

    /// Connections closed at once because every slot was busy with a request.
    pub fn refused(&self) -> u64 {
        self.refused.load(Ordering::Relaxed)
    }

    /// Connections closed to make room for a newcomer.
    pub fn evictions(&self) -> u64 {
        self.evictions.load(Ordering::Relaxed)
    }

    /// A slot for a new connection, evicting one if all are taken; `None`: refuse it.
    fn admit(&self) -> Option<Arc<ConnState>> {
        let mut open = self.open.lock().ok()?;
        let live = open
            .iter()
            .filter(|c| !c.evicted.load(Ordering::Acquire))
            .count();
        if live >= self.cap {
            let candidates = || open.iter().filter(|c| !c.evicted.load(Ordering::Acquire));
            let victim = candidates()
                .filter(|c| c.in_head.load(Ordering::Acquire))
                .min_by_key(|c| c.opened_ms)
                .or_else(|| {
                    candidates()
                        .filter(|c| !c.answering.load(Ordering::Acquire))
                        .min_by_key(|c| c.active_ms.load(Ordering::Relaxed))
                })
                .cloned();
            match victim {
                Some(v) => {
                    v.evict();
                    self.evictions.fetch_add(1, Ordering::Relaxed);
                }
                None => {
                    self.refused.fetch_add(1, Ordering::Relaxed);
                    return None;
                }
            }
        }
        let now = self.now_ms();
        let c = Arc::new(ConnState {
            in_head: AtomicBool::new(true),
            answering: AtomicBool::new(false),
            evicted: AtomicBool::new(false),
            active_ms: AtomicU64::new(now),
            opened_ms: now,
            waker: Mutex::new(None),
        });
        open.push(c.clone());
        Some(c)
    }

    fn release(&self, c: &Arc<ConnState>) {
        if let Ok(mut open) = self.open.lock() {
            open.retain(|o| !Arc::ptr_eq(o, c));
        }
    }
}

/// A TCP listener that hands out [`Guarded`] connections within [`PageLimits`].
pub struct GuardedListener {
    inner: TcpListener,
    slots: Arc<Slots>,
    limits: PageLimits,
}

impl GuardedListener {
    /// `limits.max_connections` capped by the descriptor limit (told in the log when it lowers it).
    pub fn new(inner: TcpListener, limits: PageLimits) -> Self {
        let soft = fd_soft_limit();
        let cap = connection_cap(limits.max_connections, soft);
        if cap < limits.max_connections {
            tracing::warn!(
                "live page: at most {cap} connections (the descriptor limit is {}; the mission keeps the rest)",
                soft.unwrap_or(0)
            );
        }
        Self {
            inner,
            slots: Arc::new(Slots {
                open: Mutex::new(Vec::new()),
                cap,
                epoch: Instant::now(),
                refused: AtomicU64::new(0),
                evictions: AtomicU64::new(0),
            }),
            limits,
        }
    }

    pub fn slots(&self) -> Arc<Slots> {
        self.slots.clone()
    }
}

/// A failed accept (out of descriptors, most often) is retried after this pause, not in a busy loop.
const ACCEPT_BACKOFF: Duration = Duration::from_millis(100);

impl axum::serve::Listener for GuardedListener {
    type Io = Guarded;
    type Addr = std::net::SocketAddr;

    async fn accept(&mut self) -> (Self::Io, Self::Addr) {
        loop {
            match self.inner.accept().await {
                Ok((stream, addr)) => {
                    let Some(state) = self.slots.admit() else {
                        tracing::debug!("live page: {addr} refused, every connection is busy");
                        continue;
                    };
                    let io = Guarded {
                        stream,
                        state,
                        slots: self.slots.clone(),
                        deadline: Box::pin(tokio::time::sleep(self.limits.header_timeout)),
                        limits: self.limits,
                        phase: Phase::Head(Vec::new()),
                    };
                    return (io, addr);
                }
                Err(e) => {
                    tracing::debug!("live page: accept failed: {e}");
                    tokio::time::sleep(ACCEPT_BACKOFF).await;
                }
            }
        }
    }

    fn local_addr(&self) -> io::Result<Self::Addr> {
        self.inner.local_addr()
    }
}

/// A connection that closes itself past its header or idle timeout, or when evicted.
pub struct Guarded {
    stream: TcpStream,
    state: Arc<ConnState>,
    slots: Arc<Slots>,
    deadline: Pin<Box<Sleep>>,
    limits: PageLimits,
    phase: Phase,
}

/// Where a connection is in its request / answer exchange.
enum Phase {
    /// Reading a request's head (the bytes so far, up to [`MAX_HEAD`]).
    Head(Vec<u8>),
    /// Reading its body: bytes left (`Content-Length`).
    Body(u64),
    /// The request is whole; the answer has not begun.
    Answering,
    /// Answered (or answering a stream): the next byte read starts a new request.
    Idle,
}

/// Head bytes kept to find its end and its `Content-Length`; a longer head is left to time out.
const MAX_HEAD: usize = 64 * 1024;

/// The `Content-Length` of a request head (0 without one).
fn content_length(head: &[u8]) -> u64 {
    String::from_utf8_lossy(head)
        .lines()
        .filter_map(|l| l.split_once(':'))
        .find(|(k, _)| k.trim().eq_ignore_ascii_case("content-length"))
        .and_then(|(_, v)| v.trim().parse().ok())
        .unwrap_or(0)
}

impl Guarded {
    fn closed(&self) -> Option<io::Error> {
        self.state.evicted.load(Ordering::Acquire).then(|| {
            io::Error::new(
                io::ErrorKind::ConnectionAborted,
                "evicted: the page is full",
            )
        })
    }

    fn touch(&self) {
        self.state
            .active_ms
            .store(self.slots.now_ms(), Ordering::Relaxed);
    }

    fn rearm(&mut self, d: Duration) {
        self.deadline.as_mut().reset(Instant::now() + d);
    }

    /// Pending I/O: an error once the deadline has passed.
    fn timed_out(&mut self, cx: &mut Context<'_>) -> Poll<io::Error> {
        if let Ok(mut w) = self.state.waker.lock() {
            *w = Some(cx.waker().clone());
        }
        if let Some(e) = self.closed() {
            return Poll::Ready(e);
        }
        // The request is whole: the page is working on its answer (bounded by the handler's own timeouts).
        if matches!(self.phase, Phase::Answering) {
            return Poll::Pending;
        }
        match self.deadline.as_mut().poll(cx) {
            Poll::Ready(()) => {
                let what = if self.state.in_head.load(Ordering::Acquire) {
                    "no complete request head within the header timeout"
                } else {
                    "idle past the idle timeout"
                };
                Poll::Ready(io::Error::new(io::ErrorKind::TimedOut, what))
            }
            Poll::Pending => Poll::Pending,
        }
    }

    fn set_phase(&mut self, phase: Phase) {
        let (head, answering) = match &phase {
            Phase::Head(_) => (true, false),
            Phase::Answering => (false, true),
            Phase::Body(_) | Phase::Idle => (false, false),
        };
        self.state.in_head.store(head, Ordering::Release);
        self.state.answering.store(answering, Ordering::Release);
        self.phase = phase;
    }

    /// Bytes read: a new request's head starts, goes on, or ends (`\r\n\r\n`); its body is counted.
    fn on_read(&mut self, bytes: &[u8]) {
        self.touch();
        if matches!(self.phase, Phase::Idle) {
            self.set_phase(Phase::Head(Vec::new()));
            self.rearm(self.limits.header_timeout);
        }
        let next = match &mut self.phase {
            Phase::Head(head) => {
                let from = head.len().saturating_sub(3);
                if head.len() < MAX_HEAD {
                    head.extend_from_slice(bytes);
                }
                let Some(end) = head[from..]
                    .windows(4)
                    .position(|w| w == b"\r\n\r\n")
                    .map(|p| from + p + 4)
                else {
                    return;
                };
                let read_of_body = (head.len() - end) as u64;
                match content_length(&head[..end]).saturating_sub(read_of_body) {
                    0 => Some(Phase::Answering),
                    left => Some(Phase::Body(left)),
                }
            }
            Phase::Body(left) => {
                *left = left.saturating_sub(bytes.len() as u64);
                (*left == 0).then_some(Phase::Answering)
            }
            Phase::Answering | Phase::Idle => None,
        };
        if let Some(p) = next {
            self.set_phase(p);
        }
        self.rearm(self.limits.idle_timeout);
    }
}

impl Drop for Guarded {
    fn drop(&mut self) {
        self.slots.release(&self.state);
    }
}

impl AsyncRead for Guarded {
    fn poll_read(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        if let Some(e) = self.closed() {
            return Poll::Ready(Err(e));
        }
        let before = buf.filled().len();
        match Pin::new(&mut self.stream).poll_read(cx, buf) {
            Poll::Ready(Ok(())) => {
                let got = buf.filled()[before..].to_vec();
                if !got.is_empty() {
                    self.on_read(&got);
                }
                Poll::Ready(Ok(()))
            }
            Poll::Ready(Err(e)) => Poll::Ready(Err(e)),
            Poll::Pending => self.timed_out(cx).map(Err),
        }
    }
}

impl AsyncWrite for Guarded {
    fn poll_write(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        data: &[u8],
    ) -> Poll<io::Result<usize>> {
        if let Some(e) = self.closed() {
            return Poll::Ready(Err(e));
        }
        match Pin::new(&mut self.stream).poll_write(cx, data) {
            Poll::Ready(Ok(n)) => {
                self.touch();
                if !matches!(self.phase, Phase::Head(_)) {
                    self.set_phase(Phase::Idle);
                    let idle = self.limits.idle_timeout;
                    self.rearm(idle);
                    // The server may have polled its read while answering (no timer then) and not poll
                    // it again before the client speaks: the idle timer must wake this task itself.
                    let _ = self.deadline.as_mut().poll(cx);
                }
                Poll::Ready(Ok(n))
            }
            Poll::Ready(Err(e)) => Poll::Ready(Err(e)),
            // A reader that never reads (its window full) is idle too.
            Poll::Pending => self.timed_out(cx).map(Err),
        }
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.stream).poll_flush(cx)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.stream).poll_shutdown(cx)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_page_takes_at_most_an_eighth_of_the_descriptors() {
        assert_eq!(connection_cap(64, Some(20_000)), 64);
        assert_eq!(connection_cap(64, Some(256)), 32);
        assert_eq!(connection_cap(64, Some(4)), 1);
        assert_eq!(connection_cap(64, None), 64);
    }
}
