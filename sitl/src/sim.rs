//! The run loop and the in-process API: `spawn(config)` opens the sockets and runs the vehicle
//! on a tokio task; the returned [`SimHandle`] gives the bound address, the sim clock, snapshots,
//! manual stepping, fault injection and stop.

use std::net::SocketAddr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use mavaddr::Address;
use tokio::sync::{mpsc, oneshot, watch};
use tokio::time::Instant;

use crate::autopilot::{Autopilot, Dest};
use crate::config::{ClockMode, SimConfig};
use crate::error::SimError;
use crate::faults::Delivery;
use crate::link::{Inbound, Link, Peers};
use crate::scenario::Fault;
use crate::snapshot::Snapshot;

/// Most ticks run between two looks at the sockets, so that commands are answered promptly even
/// when the sim catches up after a stall.
const MAX_TICKS_PER_BATCH: u64 = 256;

enum Control {
    Step(u64, oneshot::Sender<u64>),
    Inject(Fault),
    Stop,
}

/// The sim clock, readable from any thread: milliseconds since boot.
#[derive(Debug, Clone, Default)]
pub struct SimClock(Arc<AtomicU64>);

impl SimClock {
    pub fn now_ms(&self) -> u64 {
        self.0.load(Ordering::Acquire)
    }
    fn set(&self, ms: u64) {
        self.0.store(ms, Ordering::Release);
    }
}

/// Frames through the simulator's link, counted once handled: a stepping client compares them with its
/// own counts to know that nothing is in flight (the stepped clock is then exactly reproducible).
#[derive(Debug, Default)]
struct FrameCounts {
    /// Frames queued to peers (after link faults: a dropped frame is not counted, a duplicate twice).
    sent: AtomicU64,
    /// Frames received and handled, the replies they caused already counted in `sent`.
    received: AtomicU64,
}

/// A running simulator. Dropping it stops the simulator.
pub struct SimHandle {
    local_addr: SocketAddr,
    client_address: String,
    clock: SimClock,
    frames: Arc<FrameCounts>,
    peers: Peers,
    snapshot: watch::Receiver<Snapshot>,
    ctrl: mpsc::UnboundedSender<Control>,
    task: Option<tokio::task::JoinHandle<()>>,
}

impl SimHandle {
    /// The socket actually bound (port 0 resolved).
    pub fn local_addr(&self) -> SocketAddr {
        self.local_addr
    }

    /// The address a client uses to reach this sim: `tcpout:IP:PORT` for `tcpin`, `udpout:IP:PORT`
    /// for `udpin`.
    pub fn client_address(&self) -> &str {
        &self.client_address
    }

    pub fn clock(&self) -> SimClock {
        self.clock.clone()
    }

    pub fn now_ms(&self) -> u64 {
        self.clock.now_ms()
    }

    /// Frames sent to peers so far (all peers).
    pub fn frames_sent(&self) -> u64 {
        self.frames.sent.load(Ordering::Acquire)
    }

    /// Frames received from peers and handled so far (all peers); the replies they caused are already in
    /// [`SimHandle::frames_sent`].
    pub fn frames_received(&self) -> u64 {
        self.frames.received.load(Ordering::Acquire)
    }

    /// Peers connected now.
    pub fn peer_count(&self) -> usize {
        self.peers.ids().len()
    }

    pub fn snapshot(&self) -> Snapshot {
        self.snapshot.borrow().clone()
    }

    /// Waits (wall time at most `timeout`) until `pred` holds on a snapshot; returns it.
    pub async fn wait_for(
        &self,
        timeout: Duration,
        mut pred: impl FnMut(&Snapshot) -> bool,
    ) -> Option<Snapshot> {
        let mut rx = self.snapshot.clone();
        let fut = async {
            loop {
                {
                    let s = rx.borrow_and_update();
                    if pred(&s) {
                        return Some(s.clone());
                    }
                }
                if rx.changed().await.is_err() {
                    return None;
                }
            }
        };
        tokio::time::timeout(timeout, fut).await.ok().flatten()
    }

    /// Manual clock: advances the sim by `d` (rounded up to ticks); returns the new sim time (ms).
    /// Frames already received are handled first. In paced mode this adds ticks on top.
    pub async fn step(&self, d: Duration) -> Result<u64, SimError> {
        let (tx, rx) = oneshot::channel();
        self.ctrl
            .send(Control::Step(d.as_millis() as u64, tx))
            .map_err(|_| SimError::Stopped)?;
        rx.await.map_err(|_| SimError::Stopped)
    }

    /// Applies a fault now (as a scenario fault whose trigger fired).
    pub fn inject(&self, fault: Fault) -> Result<(), SimError> {
        self.ctrl
            .send(Control::Inject(fault))
            .map_err(|_| SimError::Stopped)
    }

    /// Stops the simulator and closes its sockets.
    pub async fn stop(mut self) {
        let _ = self.ctrl.send(Control::Stop);
        if let Some(t) = self.task.take() {
            let _ = t.await;
        }
    }
}

impl Drop for SimHandle {
    fn drop(&mut self) {
        if let Some(t) = self.task.take() {
            t.abort();
        }
    }
}

/// Opens the link and starts the simulator on the current tokio runtime.
pub async fn spawn(config: SimConfig) -> Result<SimHandle, SimError> {
    config.validate()?;
    let (in_tx, in_rx) = mpsc::channel::<Inbound>(4096);
    let link = Link::open(&config.listen, in_tx).await?;
    let local_addr = link.local_addr;
    let client_address = match Address::parse(&config.listen)? {
        Address::TcpIn(_) => format!("tcpout:{local_addr}"),
        Address::UdpIn(_) => format!("udpout:{local_addr}"),
        Address::TcpOut(hp) => format!("tcpin:{hp}"),
        Address::UdpOut(hp) => format!("udpin:{hp}"),
        // Refused by `Link::open` above: the simulator listens on sockets only.
        Address::Serial { .. } => config.listen.clone(),
    };
    let ap = Autopilot::new(&config);
    let clock = SimClock::default();
    let (snap_tx, snap_rx) = watch::channel(ap.snapshot());
    let (ctrl_tx, ctrl_rx) = mpsc::unbounded_channel();
    let frames = Arc::new(FrameCounts::default());
    let peers = link.peers.clone();
    let run = Runner {
        frames: frames.clone(),
        ap,
        link,
        inbound: in_rx,
        ctrl: ctrl_rx,
        clock: clock.clone(),
        snap: snap_tx,
        mode: config.clock,
        speedup: config.speedup,
        held_inbound: None,
    };
    let task = tokio::spawn(run.run());
    tracing::info!(%local_addr, speedup = config.speedup, "sitl: running");
    Ok(SimHandle {
        local_addr,
        client_address,
        clock,
        frames,
        peers,
        snapshot: snap_rx,
        ctrl: ctrl_tx,
        task: Some(task),
    })
}

struct Runner {
    frames: Arc<FrameCounts>,
    ap: Autopilot,
    link: Link,
    inbound: mpsc::Receiver<Inbound>,
    ctrl: mpsc::UnboundedReceiver<Control>,
    clock: SimClock,
    snap: watch::Sender<Snapshot>,
    mode: ClockMode,
    speedup: f64,
    /// An inbound frame held back by the link's reordering.
    held_inbound: Option<Inbound>,
}

impl Runner {
    async fn run(mut self) {
        let start = Instant::now();
        let tick_ms = self.ap.tick_ms();
        let wall_per_tick = Duration::from_secs_f64(tick_ms as f64 / 1000.0 / self.speedup);
        let mut paced_ticks: u64 = 0;
        loop {
            let next_tick = match self.mode {
                ClockMode::Paced => start + wall_per_tick.mul_f64((paced_ticks + 1) as f64),
                ClockMode::Manual => Instant::now() + Duration::from_secs(3600),
            };
            let wake = match self.ap.upload_deadline() {
                Some(d) => next_tick.min(Instant::from_std(d)),
                None => next_tick,
            };
            tokio::select! {
                biased;
                c = self.ctrl.recv() => match c {
                    None | Some(Control::Stop) => break,
                    Some(Control::Inject(f)) => self.ap.apply_fault(f),
                    Some(Control::Step(ms, reply)) => {
                        self.drain_inbound();
                        let n = ms.div_ceil(tick_ms);
                        for _ in 0..n {
                            self.ap.tick();
                            self.flush();
                        }
                        self.publish();
                        let _ = reply.send(self.ap.now_ms());
                    }
                },
                m = self.inbound.recv() => match m {
                    Some(frame) => self.receive(frame),
                    None => break,
                },
                _ = tokio::time::sleep_until(wake) => {}
            }
            if self.mode == ClockMode::Paced {
                let due = (start.elapsed().as_secs_f64() / wall_per_tick.as_secs_f64()) as u64;
                let n = due.saturating_sub(paced_ticks).min(MAX_TICKS_PER_BATCH);
                for _ in 0..n {
                    self.ap.tick();
                    self.flush();
                }
                paced_ticks += n;
                // Far behind (a stalled machine): drop the backlog rather than sprint.
                if due.saturating_sub(paced_ticks) > 10 * MAX_TICKS_PER_BATCH {
                    paced_ticks = due;
                }
            }
            self.ap.check_upload_timers(std::time::Instant::now());
            self.flush();
            self.publish();
        }
        tracing::info!("sitl: stopped");
    }

    fn drain_inbound(&mut self) {
        while let Ok(frame) = self.inbound.try_recv() {
            self.receive(frame);
        }
    }

    fn receive(&mut self, frame: Inbound) {
        let msg_id = mavlink::Message::message_id(&frame.msg);
        match self.ap.link_faults.inbound(self.ap.now_ms(), msg_id) {
            Delivery::Drop => {}
            Delivery::Once => self.handle_then_held(frame),
            Delivery::Twice => {
                self.ap.handle(frame.clone());
                self.handle_then_held(frame);
            }
            // Held back until the next frame that gets through, which overtakes it.
            Delivery::Reorder => match self.held_inbound.take() {
                Some(prev) => {
                    self.ap.handle(frame);
                    self.ap.handle(prev);
                }
                None => self.held_inbound = Some(frame),
            },
        }
        self.flush();
        // After the flush: a client seeing this count also sees the replies in `sent`.
        self.frames.received.fetch_add(1, Ordering::AcqRel);
    }

    /// Handles `frame`, then the frame held back for reordering, which it overtook.
    fn handle_then_held(&mut self, frame: Inbound) {
        self.ap.handle(frame);
        if let Some(prev) = self.held_inbound.take() {
            self.ap.handle(prev);
        }
    }

    fn publish(&mut self) {
        self.clock.set(self.ap.now_ms());
        self.snap.send_replace(self.ap.snapshot());
    }

    /// Sends what the autopilot produced, through the link faults.
    fn flush(&mut self) {
        let out = self.ap.take_output();
        if out.is_empty() {
            return;
        }
        let now = self.ap.now_ms();
        let sysid = self.ap.system_id();
        let peers: Peers = self.link.peers.clone();
        let all = peers.ids();
        let sent = |ok: bool| u64::from(ok);
        let mut count = 0;
        for (dest, msg) in out {
            let targets: Vec<u64> = match dest {
                Dest::All => all.clone(),
                Dest::Peer(p) => vec![p],
            };
            for peer in targets {
                let Some(bytes) = peers.encode(peer, sysid, &msg) else {
                    continue;
                };
                let lf = &mut self.ap.link_faults;
                match lf.outbound(now) {
                    Delivery::Drop => {}
                    Delivery::Once => {
                        count += sent(peers.send_bytes(peer, bytes));
                    }
                    Delivery::Twice => {
                        count += sent(peers.send_bytes(peer, bytes.clone()));
                        count += sent(peers.send_bytes(peer, bytes));
                    }
                    Delivery::Reorder => {
                        // Hold this frame back until the next one; if one is already held,
                        // this frame overtakes it instead.
                        if let Some(prev) = lf.take_held(peer) {
                            count += sent(peers.send_bytes(peer, bytes));
                            count += sent(peers.send_bytes(peer, prev));
                        } else {
                            lf.hold(peer, bytes);
                        }
                        continue;
                    }
                }
                if let Some(held) = self.ap.link_faults.take_held(peer) {
                    count += sent(peers.send_bytes(peer, held));
                }
            }
        }
        self.frames.sent.fetch_add(count, Ordering::AcqRel);
    }
}
