//! The MAVLink vehicle: tokio tasks pumping bytes between a transport and the protocol core ([`Driver`], and
//! the [`GoalIntake`] for ground stations), with `.tlog` recording, signing, link-loss reporting and
//! reconnection. The executive talks to it through the [`Vehicle`] trait, never waiting on I/O.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{mpsc as std_mpsc, Arc, Mutex};
use std::time::{Duration, Instant};

use mavlink::dialects::ardupilotmega::MavMessage;

use tokio::sync::Notify;

use super::api::VehicleEvent;
use super::api::{Vehicle, VehicleError};
use super::config::VehicleConfig;
use super::driver::{companion_heartbeat, Driver, COMPANION_COMPONENT};
use super::endpoint::{Address, Transport};
use super::frame::{parse_key, Encoder, Signer};
use super::goal_answers::{answer_uploads, Awaiting, FollowUp};
use super::goals::{GoalBatch, GoalCancel, GoalDecider, KnownLocations, SyntacticDecider};
use super::intake::{GoalIntake, PendingDecision};
use super::peers::Peers;
use super::readiness::ReadyReport;
use super::safe_stop::{OnShutdown, SafeStop, SafeStopOutcome, SafeStopReport};
use super::status::{link_state, StatusProbe, VehicleStatus};
use super::tlog::TlogWriter;
use super::types::{ActionStart, VehicleActionId};

#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    #[error("bad address: {0}")]
    Address(#[from] super::endpoint::AddressError),
    #[error("{what}: {source}")]
    Io {
        what: String,
        source: std::io::Error,
    },
    #[error("signing key: {0}")]
    Key(String),
}

/// Counters of one link, readable while it runs.
#[derive(Debug, Default)]
pub struct LinkStats {
    pub frames_in: AtomicU64,
    pub frames_out: AtomicU64,
    /// Frames dropped because signing is on and they were unsigned or badly signed.
    pub rejected_unsigned: AtomicU64,
    pub crc_errors: AtomicU64,
    /// Uploaded goal batches handed to the executive (in its event channel).
    pub goal_batches: AtomicU64,
}

/// Frames to and from the autopilot's transport (see [`MavlinkVehicle::link_counts`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LinkCounts {
    /// Frames produced for the autopilot, sent or about to be.
    pub sent: u64,
    /// Frames received from the autopilot and fully handled (events out, replies counted in `sent`).
    pub received: u64,
    /// Goal batches uploaded by ground stations and handed to the executive so far.
    pub goal_batches: u64,
}

/// Who decides on uploaded goals.
pub enum Decider {
    /// Decided here (e.g. [`SyntacticDecider`]): no executive involved.
    Local(Box<dyn GoalDecider>),
    /// Handed to the executive as [`VehicleEvent::Goals`]; after `timeout` without an answer the syntactic
    /// verdicts are sent so the ground station is not left hanging.
    Executive { timeout: Duration },
}

/// Options beyond the config file.
pub struct LinkOptions {
    /// Overrides `link.address`.
    pub address: Option<String>,
    /// Overrides `link.tlog`.
    pub tlog: Option<PathBuf>,
    /// A second endpoint where ground stations connect (goal intake only).
    pub gcs: Option<String>,
    pub known: Option<KnownLocations>,
    pub decider: Decider,
    pub first_goal_number: u32,
}

impl Default for LinkOptions {
    fn default() -> Self {
        Self {
            address: None,
            tlog: None,
            gcs: None,
            known: None,
            decider: Decider::Executive {
                timeout: Duration::from_secs(2),
            },
            first_goal_number: 1,
        }
    }
}

struct Shared {
    driver: Mutex<Driver>,
    notify: Notify,
    clock_ms: AtomicU64,
    /// When (`epoch` ms) `clock_ms` last moved, and when the autopilot's last HEARTBEAT came (`NEVER`: not
    /// yet): how long the vehicle has been silent, read without the driver's lock.
    clock_at_ms: AtomicU64,
    heartbeat_at_ms: AtomicU64,
    /// Frames taken for the autopilot's transport (counted under the driver's lock, see
    /// [`MavlinkVehicle::link_counts`]).
    tx_frames: AtomicU64,
    /// Frames received from the autopilot's transport whose handling is over: their events are in the
    /// channel and the replies they caused are counted in `tx_frames`.
    rx_frames: AtomicU64,
    /// The adopted system id, for the ground-station endpoint to answer as the same system.
    system_id: std::sync::atomic::AtomicU8,
    epoch: Instant,
    /// The last position (east, north metres from home, as f64 bits; NaN: none yet), stored by the pump:
    /// read without the driver's lock, which the mission loop must not contend for (a stepped simulator's
    /// exchange stays reproducible).
    east_bits: AtomicU64,
    north_bits: AtomicU64,
}

/// No HEARTBEAT or clock yet.
const NEVER: u64 = u64::MAX;

impl Shared {
    /// Wall time since the `epoch` ms stored in `at`, unless it is [`NEVER`].
    fn age(&self, at: &AtomicU64) -> Option<Duration> {
        let at = at.load(Ordering::Relaxed);
        (at != NEVER).then(|| Duration::from_millis(self.clock_now().saturating_sub(at)))
    }

    fn position(&self) -> Option<(f64, f64)> {
        let east = f64::from_bits(self.east_bits.load(Ordering::Relaxed));
        let north = f64::from_bits(self.north_bits.load(Ordering::Relaxed));
        (east.is_finite() && north.is_finite()).then_some((east, north))
    }
}

/// Ground stations connected at once to a `tcpin:` ground-station port.
pub const MAX_GCS_CONNECTIONS: u64 = 16;
/// A ground station on a `tcpin:` port that sends nothing (not even a HEARTBEAT) for this long is dropped.
pub const GCS_IDLE: Duration = Duration::from_secs(30);

/// The goal intake shared by the pumps that serve it, and who decides.
type IntakeRole = (Arc<Mutex<GoalIntake>>, Arc<Mutex<Decider>>);

/// What one pump task serves.
struct Pump {
    transport: Transport,
    shared: Option<Arc<Shared>>,
    /// The vehicle whose system id a ground-station endpoint answers with.
    follow: Option<Arc<Shared>>,
    intake: Option<IntakeRole>,
    own_system: u8,
    signer_key: Option<([u8; 32], u8)>,
    tlog: Option<Arc<Mutex<TlogWriter>>>,
    events: std_mpsc::Sender<VehicleEvent>,
    stats: Arc<LinkStats>,
    reconnect: Duration,
    epoch: Instant,
}

impl Pump {
    fn now(&self) -> u64 {
        self.epoch.elapsed().as_millis() as u64
    }

    fn record(&self, bytes: &[u8]) {
        if let Some(t) = &self.tlog {
            if let Ok(mut t) = t.lock() {
                if let Err(e) = t.record(bytes) {
                    tracing::warn!("tlog: {e}");
                }
            }
        }
    }

    /// A copy serving one accepted ground-station connection.
    fn for_connection(&self, stream: tokio::net::TcpStream) -> Pump {
        Pump {
            transport: Transport::accepted(self.transport.address().clone(), stream),
            shared: self.shared.clone(),
            follow: self.follow.clone(),
            intake: self.intake.clone(),
            own_system: self.own_system,
            signer_key: self.signer_key,
            tlog: self.tlog.clone(),
            events: self.events.clone(),
            stats: self.stats.clone(),
            reconnect: self.reconnect,
            epoch: self.epoch,
        }
    }

    /// A ground-station `tcpin:` port: every station is served on its own connection (one idle client
    /// never holds the port), at most [`MAX_GCS_CONNECTIONS`] at once; an idle one is dropped after
    /// [`GCS_IDLE`].
    async fn serve_stations(mut self) {
        let open = Arc::new(AtomicU64::new(0));
        loop {
            let stream = match self.transport.accept().await {
                Ok(s) => s,
                Err(e) => {
                    tracing::debug!("gcs accept failed: {e}");
                    tokio::time::sleep(self.reconnect).await;
                    continue;
                }
            };
            if open.load(Ordering::Acquire) >= MAX_GCS_CONNECTIONS {
                tracing::warn!("{MAX_GCS_CONNECTIONS} ground stations connected: one more refused");
                drop(stream);
                continue;
            }
            open.fetch_add(1, Ordering::AcqRel);
            let pump = self.for_connection(stream);
            let open = open.clone();
            tokio::spawn(async move {
                pump.run_inner().await;
                open.fetch_sub(1, Ordering::AcqRel);
            });
        }
    }

    async fn run(self) {
        if self.shared.is_none() && self.transport.is_listener() {
            return self.serve_stations().await;
        }
        self.run_inner().await
    }

    async fn run_inner(mut self) {
        let one_shot = self.transport.is_one_shot();
        let mut encoder = Encoder::new(
            self.own_system,
            COMPANION_COMPONENT,
            self.signer_key.map(|(k, l)| Signer::new(k, l)),
        );
        let verifier = self.signer_key.map(|(k, l)| Signer::new(k, l));
        let mut awaiting: Vec<Awaiting> = Vec::new();
        let mut following: Vec<FollowUp> = Vec::new();
        let mut last_own_heartbeat: Option<u64> = None;
        loop {
            let mut endpoint = match self.transport.open().await {
                Ok(e) => e,
                Err(e) => {
                    tracing::debug!("link open failed: {e}; retrying");
                    tokio::time::sleep(self.reconnect).await;
                    continue;
                }
            };
            // One decoder per UDP sender: garbage from one never holds back another's frames.
            let mut peers = Peers::new(endpoint.fixed_peer());
            let datagram = self.transport.is_datagram();
            let mut buf = vec![0u8; 65536];
            let mut ticker = tokio::time::interval(Duration::from_millis(10));
            ticker.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
            let mut out = Vec::new();
            let mut rx_handled: u64 = 0;
            let mut last_rx = self.now();
            let closed = loop {
                let notified = async {
                    match &self.shared {
                        Some(s) => s.notify.notified().await,
                        None => std::future::pending().await,
                    }
                };
                tokio::select! {
                    r = endpoint.recv_from(&mut buf) => match r {
                        Ok((0, _)) | Err(_) => break true,
                        Ok((n, from)) => {
                            let (frames, corrupted) = peers.decode(from, &buf[..n]);
                            let now = self.now();
                            last_rx = now;
                            for frame in frames {
                                rx_handled += 1;
                                self.record(&frame.bytes);
                                if let Some(v) = &verifier {
                                    if !v.accepts(&frame) {
                                        self.stats.rejected_unsigned.fetch_add(1, Ordering::Relaxed);
                                        tracing::debug!(msgid = frame.message_id, "unsigned or badly signed frame rejected");
                                        continue;
                                    }
                                }
                                self.stats.frames_in.fetch_add(1, Ordering::Relaxed);
                                peers.heard(from, &frame);
                                let Some(msg) = frame.parse() else {
                                    // A goal item the dialect cannot read is refused at once, not dropped
                                    // (the autopilot's items belong to our mission client).
                                    let from_autopilot = self.shared.as_ref().is_some_and(|s| {
                                        s.driver.lock().is_ok_and(|d| d.target() == Some((frame.system_id, frame.component_id)))
                                    });
                                    if let (Some((intake, decider)), false) = (&self.intake, from_autopilot) {
                                        let done = intake.lock().ok().and_then(|mut i| i.unparsable_item(frame.header(), frame.message_id, frame.payload(), encoder.system_id, now, &mut out));
                                        if let Some(p) = done {
                                            self.decide(p, decider, intake, &mut awaiting, &mut out);
                                        }
                                    }
                                    continue;
                                };
                                let header = frame.header();
                                let mut msg = msg;
                                if self.shared.is_none() {
                                    // Only goals come to this port: a mission message to component 0 is
                                    // ours (MAVProxy's defaults, see docs/goal-items.md).
                                    to_companion(&mut msg);
                                }
                                if self.shared.is_none()
                                    && matches!(msg, MavMessage::HEARTBEAT(_))
                                    && last_own_heartbeat.is_none_or(|t| now.saturating_sub(t) >= 1000)
                                {
                                    // A new ground station hears ours at once (it waits for it to find
                                    // component 191), but never more than once a second however many
                                    // heartbeats come in: no amplification.
                                    out.push(companion_heartbeat());
                                    last_own_heartbeat = Some(now);
                                }
                                let mut from_autopilot = false;
                                if let Some(s) = &self.shared {
                                    if let Ok(mut d) = s.driver.lock() {
                                        d.handle(header, &msg, now);
                                        encoder.system_id = d.system_id;
                                        s.system_id.store(d.system_id, Ordering::Relaxed);
                                        from_autopilot = d.target() == Some((frame.system_id, frame.component_id));
                                        if from_autopilot && matches!(msg, MavMessage::HEARTBEAT(_)) {
                                            s.heartbeat_at_ms.store(now, Ordering::Relaxed);
                                        }
                                        if let Some(t) = d.telemetry().time_boot_ms {
                                            if s.clock_ms.swap(t, Ordering::Relaxed) != t {
                                                s.clock_at_ms.store(now, Ordering::Relaxed);
                                            }
                                        }
                                        if let Some(p) = d.telemetry().position {
                                            s.east_bits.store(p.east.to_bits(), Ordering::Relaxed);
                                            s.north_bits.store(p.north.to_bits(), Ordering::Relaxed);
                                        }
                                    }
                                }
                                if let Some(f) = &self.follow {
                                    encoder.system_id = f.system_id.load(Ordering::Relaxed);
                                    // A ground station's pause / continue to 191 reaches the driver; what
                                    // the driver then sends goes out on the vehicle's link.
                                    if let Ok(mut d) = f.driver.lock() {
                                        if let Some(ack) = d.operator_command(header, &msg, now) {
                                            out.push(ack);
                                            for e in d.take_events() {
                                                let _ = self.events.send(e);
                                            }
                                            f.notify.notify_one();
                                        }
                                    }
                                }
                                // The autopilot's mission messages to 191 belong to our mission client, never
                                // to the goal intake.
                                if let (Some((intake, decider)), false) = (&self.intake, from_autopilot) {
                                    let done = intake.lock().ok().and_then(|mut i| i.handle(header, &msg, from, encoder.system_id, now, &mut out));
                                    if let Some(p) = done {
                                        self.decide(p, decider, intake, &mut awaiting, &mut out);
                                    }
                                }
                            }
                            // A corrupted frame was sent too: it counts as received.
                            rx_handled += corrupted;
                            self.stats.crc_errors.fetch_add(corrupted, Ordering::Relaxed);
                        }
                    },
                    _ = ticker.tick() => {
                        let now = self.now();
                        if one_shot && now.saturating_sub(last_rx) > GCS_IDLE.as_millis() as u64 {
                            tracing::info!("ground station silent for {GCS_IDLE:?}: connection dropped");
                            break true;
                        }
                        match &self.shared {
                            Some(s) => if let Ok(mut d) = s.driver.lock() { d.tick(now) },
                            None => if last_own_heartbeat.is_none_or(|t| now.saturating_sub(t) >= 1000) {
                                last_own_heartbeat = Some(now);
                                out.push(companion_heartbeat());
                            },
                        }
                        if let Some((intake, _)) = &self.intake {
                            if let Ok(mut i) = intake.lock() {
                                i.tick(now, &mut out);
                                answer_uploads(&mut i, &mut awaiting, &mut following, Instant::now(), &mut out);
                            }
                        }
                    },
                    _ = notified => {},
                }
                if let Some(s) = &self.shared {
                    if let Ok(mut d) = s.driver.lock() {
                        out.extend(d.take_outgoing());
                        // Under the lock, with what the driver still holds: `link_counts` sees each frame once.
                        s.tx_frames.fetch_add(out.len() as u64, Ordering::AcqRel);
                        for e in d.take_events() {
                            let _ = self.events.send(e);
                        }
                    }
                }
                let mut failed = false;
                'out: for msg in out.drain(..) {
                    // Encoded once per MAVLink version its receivers speak.
                    let mut encoded: [Option<Vec<u8>>; 2] = [None, None];
                    for (to, v1) in peers.destinations(&msg, datagram) {
                        let slot = &mut encoded[usize::from(v1)];
                        if slot.is_none() {
                            let bytes = encoder.encode(&msg, v1);
                            self.record(&bytes);
                            *slot = Some(bytes);
                        }
                        let Some(bytes) = slot.as_deref() else {
                            continue;
                        };
                        match endpoint.send_to(bytes, to).await {
                            Ok(()) => {
                                self.stats.frames_out.fetch_add(1, Ordering::Relaxed);
                            }
                            // One UDP peer gone costs only that peer.
                            Err(e) if datagram => tracing::debug!(?to, "udp send: {e}"),
                            Err(_) => {
                                failed = true;
                                break 'out;
                            }
                        }
                    }
                }
                if let Some(s) = &self.shared {
                    // After the replies went out: what was received is handled.
                    s.rx_frames
                        .fetch_add(std::mem::take(&mut rx_handled), Ordering::AcqRel);
                }
                if failed {
                    break true;
                }
            };
            if closed && one_shot {
                return;
            }
            if closed {
                if let Some(s) = &self.shared {
                    if let Ok(mut d) = s.driver.lock() {
                        d.transport_lost();
                        for e in d.take_events() {
                            let _ = self.events.send(e);
                        }
                    }
                }
                if self.transport.is_datagram() {
                    // A UDP socket error is transient: keep the socket.
                    tokio::time::sleep(Duration::from_millis(10)).await;
                } else {
                    tokio::time::sleep(self.reconnect).await;
                }
            }
        }
    }

    fn decide(
        &self,
        pending: PendingDecision,
        decider: &Arc<Mutex<Decider>>,
        intake: &Arc<Mutex<GoalIntake>>,
        awaiting: &mut Vec<Awaiting>,
        out: &mut Vec<MavMessage>,
    ) {
        let Ok(mut d) = decider.lock() else { return };
        match &mut *d {
            Decider::Local(local) => {
                // Nothing executes the goals here: cancelling is forgetting them.
                let verdicts = local.decide(&pending.goals);
                let cancelled = Some(pending.cancel.clone());
                if let Ok(mut i) = intake.lock() {
                    i.decided(pending, &verdicts, cancelled, out);
                }
            }
            Decider::Executive { timeout } => {
                let cancel_rx = (!pending.cancel.is_empty()).then(|| {
                    let (cancel, rx) =
                        GoalCancel::new(pending.cancel.clone(), pending.cancel_reason.clone());
                    let _ = self.events.send(VehicleEvent::Cancel(cancel));
                    rx
                });
                let (rx, later) = if pending.goals.is_empty() {
                    (None, None)
                } else {
                    let (batch, rx, later) = GoalBatch::with_later(pending.goals.clone());
                    let _ = self.events.send(VehicleEvent::Goals(batch));
                    self.stats.goal_batches.fetch_add(1, Ordering::AcqRel);
                    (Some(rx), Some(later))
                };
                awaiting.push(Awaiting {
                    pending,
                    rx,
                    cancel_rx,
                    later,
                    deadline: Instant::now() + *timeout,
                });
            }
        }
    }
}

/// A mission-protocol message to any component (0) addressed to the companion's (191): on the ground-station
/// port nothing else could answer it. MAVProxy sends to `target_component` 0 until told otherwise (it
/// takes its target from an autopilot's HEARTBEAT, and the companion's is not one).
// The legacy MISSION_ITEM / MISSION_REQUEST must still be accepted (MAVProxy, ArduPilot's GCSs send them).
#[allow(deprecated)]
fn to_companion(msg: &mut MavMessage) {
    let tc = match msg {
        MavMessage::MISSION_COUNT(m) => &mut m.target_component,
        MavMessage::MISSION_ITEM_INT(m) => &mut m.target_component,
        MavMessage::MISSION_ITEM(m) => &mut m.target_component,
        MavMessage::MISSION_REQUEST_LIST(m) => &mut m.target_component,
        MavMessage::MISSION_REQUEST_INT(m) => &mut m.target_component,
        MavMessage::MISSION_REQUEST(m) => &mut m.target_component,
        MavMessage::MISSION_ACK(m) => &mut m.target_component,
        MavMessage::MISSION_CLEAR_ALL(m) => &mut m.target_component,
        _ => return,
    };
    if *tc == 0 {
        *tc = COMPANION_COMPONENT;
    }
}

/// The MAVLink2 signing key and link id of `cfg`'s link, when it has a key.
pub fn signing_key(cfg: &VehicleConfig) -> Result<Option<([u8; 32], u8)>, LinkError> {
    cfg.link
        .signing_key
        .as_deref()
        .map(|k| {
            parse_key(k)
                .map(|key| (key, cfg.link.signing_link_id))
                .map_err(LinkError::Key)
        })
        .transpose()
}

async fn bind(addr: &str) -> Result<Transport, LinkError> {
    let a = Address::parse(addr).map_err(LinkError::Address)?;
    Transport::bind(a).await.map_err(|source| LinkError::Io {
        what: format!("bind {addr}"),
        source,
    })
}

fn open_tlog(path: &std::path::Path) -> Result<Arc<Mutex<TlogWriter>>, LinkError> {
    TlogWriter::create(path)
        .map(|t| Arc::new(Mutex::new(t)))
        .map_err(|source| LinkError::Io {
            what: format!("tlog {}", path.display()),
            source,
        })
}

/// The MAVLink implementation of [`Vehicle`].
pub struct MavlinkVehicle {
    shared: Arc<Shared>,
    events: std_mpsc::Receiver<VehicleEvent>,
    /// For the events a command causes at once (a stopped action's report): they are in the channel when
    /// `start`/`stop` return, not whenever the pump runs next.
    events_tx: std_mpsc::Sender<VehicleEvent>,
    local_addr: Option<SocketAddr>,
    gcs_addr: Option<SocketAddr>,
    stats: Arc<LinkStats>,
    tasks: Vec<tokio::task::JoinHandle<()>>,
    tlog: Option<Arc<Mutex<TlogWriter>>>,
    /// The goal intake both endpoints serve: what each ground station holds.
    intake: Arc<Mutex<GoalIntake>>,
    /// Present when the vehicle made its own runtime ([`MavlinkVehicle::connect_blocking`]).
    _runtime: Option<tokio::runtime::Runtime>,
}

impl MavlinkVehicle {
    /// Binds / connects and spawns the link tasks on the current tokio runtime.
    pub async fn connect(cfg: VehicleConfig, opts: LinkOptions) -> Result<Self, LinkError> {
        let address = opts
            .address
            .clone()
            .unwrap_or_else(|| cfg.link.address.clone());
        let key = signing_key(&cfg)?;
        let tlog_path = opts
            .tlog
            .clone()
            .or_else(|| cfg.link.tlog.as_ref().map(PathBuf::from));
        let tlog = tlog_path.as_deref().map(open_tlog).transpose()?;
        let reconnect = Duration::from_millis(cfg.link.reconnect_ms);
        let known = opts
            .known
            .clone()
            .unwrap_or_else(|| KnownLocations::new(cfg.home));
        let transport = bind(&address).await?;
        let local_addr = transport.local_addr();
        let gcs_transport = match &opts.gcs {
            Some(g) => Some(bind(g).await?),
            None => None,
        };
        let gcs_addr = gcs_transport.as_ref().and_then(|t| t.local_addr());
        let goal_sysids = cfg.link.goal_sysids.clone();
        let epoch = Instant::now();
        let shared = Arc::new(Shared {
            driver: Mutex::new(Driver::new(cfg)),
            notify: Notify::new(),
            clock_ms: AtomicU64::new(0),
            clock_at_ms: AtomicU64::new(NEVER),
            heartbeat_at_ms: AtomicU64::new(NEVER),
            east_bits: AtomicU64::new(f64::NAN.to_bits()),
            north_bits: AtomicU64::new(f64::NAN.to_bits()),
            tx_frames: AtomicU64::new(0),
            rx_frames: AtomicU64::new(0),
            system_id: std::sync::atomic::AtomicU8::new(1),
            epoch,
        });
        let (tx, rx) = std_mpsc::channel();
        let events_tx = tx.clone();
        let stats = Arc::new(LinkStats::default());
        let intake = Arc::new(Mutex::new(
            GoalIntake::new(known, opts.first_goal_number).allowing(goal_sysids),
        ));
        let decider = Arc::new(Mutex::new(opts.decider));
        let intake_view = intake.clone();
        let mut tasks = vec![tokio::spawn(
            Pump {
                transport,
                shared: Some(shared.clone()),
                follow: None,
                intake: Some((intake.clone(), decider.clone())),
                own_system: 1,
                signer_key: key,
                tlog: tlog.clone(),
                events: tx.clone(),
                stats: stats.clone(),
                reconnect,
                epoch,
            }
            .run(),
        )];
        if let Some(t) = gcs_transport {
            // The ground-station side: goal intake only; its system id follows the vehicle's.
            tasks.push(tokio::spawn(
                Pump {
                    transport: t,
                    shared: None,
                    follow: Some(shared.clone()),
                    intake: Some((intake, decider)),
                    own_system: 1,
                    signer_key: key,
                    tlog: tlog.clone(),
                    events: tx,
                    stats: stats.clone(),
                    reconnect,
                    epoch,
                }
                .run(),
            ));
        }
        Ok(Self {
            shared,
            events: rx,
            events_tx,
            local_addr,
            gcs_addr,
            stats,
            tasks,
            tlog,
            intake: intake_view,
            _runtime: None,
        })
    }

    /// For a synchronous executive: runs the link on a runtime of its own.
    pub fn connect_blocking(cfg: VehicleConfig, opts: LinkOptions) -> Result<Self, LinkError> {
        let rt = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .enable_all()
            .build()
            .map_err(|source| LinkError::Io {
                what: "tokio runtime".into(),
                source,
            })?;
        let mut v = rt.block_on(Self::connect(cfg, opts))?;
        v._runtime = Some(rt);
        Ok(v)
    }

    pub fn local_addr(&self) -> Option<SocketAddr> {
        self.local_addr
    }

    pub fn gcs_addr(&self) -> Option<SocketAddr> {
        self.gcs_addr
    }

    pub fn stats(&self) -> &LinkStats {
        &self.stats
    }

    /// Frames exchanged with the autopilot so far: a stepped simulator compares them with its own counts
    /// to know that nothing is in flight between them.
    pub fn link_counts(&self) -> LinkCounts {
        let (sent, pending) = match self.shared.driver.lock() {
            Ok(d) => (
                self.shared.tx_frames.load(Ordering::Acquire),
                d.outgoing_len() as u64,
            ),
            Err(_) => (self.shared.tx_frames.load(Ordering::Acquire), 0),
        };
        LinkCounts {
            sent: sent + pending,
            received: self.shared.rx_frames.load(Ordering::Acquire),
            goal_batches: self.stats.goal_batches.load(Ordering::Acquire),
        }
    }

    /// The adopted autopilot (system, component), once seen.
    pub fn target(&self) -> Option<(u8, u8)> {
        self.shared.driver.lock().ok().and_then(|d| d.target())
    }

    /// Leaves the vehicle safe as the configuration says (`modes.on_shutdown`): ends the running actions,
    /// commands HOLD (or RTL) and waits, within the command's retries and two seconds more, for a HEARTBEAT
    /// in that mode. `pass_time` runs between looks (a sleep on a live link; a step of a stepped simulator).
    pub fn safe_stop(&self, pass_time: &mut dyn FnMut(&MavlinkVehicle)) -> SafeStopReport {
        let bound = {
            // A poisoned driver (a pump panicked) can command nothing.
            let Ok(mut d) = self.shared.driver.lock() else {
                return SafeStop::settled(OnShutdown::None, SafeStopOutcome::NoVehicle).report();
            };
            d.begin_safe_stop(self.shared.clock_now());
            self.deliver(&mut d);
            Duration::from_millis(d.safe_stop_bound_ms())
        };
        self.shared.notify.notify_one();
        let deadline = Instant::now() + bound;
        loop {
            // Time passes before each look, as in `wait_ready`: the stop's answers take no time of the
            // autopilot's own, and a look racing them would make a stepped run's report depend on the machine.
            pass_time(self);
            let state = self
                .shared
                .driver
                .lock()
                .ok()
                .and_then(|d| d.safe_stop().cloned());
            let Some(state) = state else {
                return SafeStop::settled(OnShutdown::None, SafeStopOutcome::NoVehicle).report();
            };
            if state.outcome().is_some() || Instant::now() >= deadline {
                return state.report();
            }
        }
    }

    /// The mission is over: the vehicle is left as `[authority] at_end` says (HOLD, then disarmed) and
    /// the companion lets go of it. The commands go out with the link's next wake-up.
    pub fn end_of_mission(&self) {
        if let Ok(mut d) = self.shared.driver.lock() {
            d.end_of_mission(self.shared.clock_now());
            self.deliver(&mut d);
        }
        self.shared.notify.notify_one();
    }

    /// Waits for the autopilot to be ready for the mission's first start: a position fix, then ARM accepted
    /// (retried with a backoff while refused). Gives up after `limit_ms` of the vehicle's time, or after
    /// `wall_limit` should its clock stop. `pass_time` runs between looks (a sleep on a live link; a step
    /// of a stepped simulator) and returns false to stop waiting (a signal).
    pub fn wait_ready(
        &self,
        limit_ms: u64,
        wall_limit: Duration,
        pass_time: &mut dyn FnMut(&MavlinkVehicle) -> bool,
    ) -> ReadyReport {
        let not_ready = || super::readiness::Readiness::new(0).report().clone();
        let started = {
            // A poisoned driver (a pump panicked) can command nothing.
            let Ok(mut d) = self.shared.driver.lock() else {
                return not_ready();
            };
            d.begin_ready(self.shared.clock_now());
            self.deliver(&mut d);
            d.telemetry().time_boot_ms.unwrap_or(0)
        };
        self.shared.notify.notify_one();
        let deadline = Instant::now() + wall_limit;
        loop {
            // Time passes before each look, the first included: the autopilot answers what `begin_ready`
            // sent in no time of its own, and a look while the answers are still in flight would make a
            // stepped simulator's start depend on the machine's speed.
            let go_on = pass_time(self);
            let state = self.shared.driver.lock().ok().and_then(|d| {
                let vnow = d.telemetry().time_boot_ms.unwrap_or(0);
                d.readiness()
                    .map(|r| (r.report().clone(), vnow, d.fence_read_done()))
            });
            let Some((report, vnow, fence_read)) = state else {
                return not_ready();
            };
            // Ready, and the autopilot's fence read (or given up on): the mission may start.
            if !go_on
                || (report.ready && fence_read)
                || vnow.saturating_sub(started) >= limit_ms
                || Instant::now() >= deadline
            {
                return report;
            }
        }
    }

    /// A flush of the `.tlog` that never waits: it skips when a record is being written (for a process
    /// about to exit at once; records reach the file whole either way).
    pub fn tlog_flusher(&self) -> Option<Box<dyn Fn() + Send>> {
        let tlog = self.tlog.clone()?;
        Some(Box::new(move || {
            if let Ok(mut t) = tlog.try_lock() {
                let _ = t.flush();
            }
        }))
    }

    /// The autopilot's fence as read at readiness (`None`: not read, or not yet).
    pub fn autopilot_fence(&self) -> Option<super::fence::AutopilotFence> {
        self.shared
            .driver
            .lock()
            .ok()
            .and_then(|d| d.autopilot_fence())
    }

    /// Writes buffered `.tlog` records to disk.
    pub fn flush_tlog(&self) {
        if let Some(t) = &self.tlog {
            if let Ok(mut t) = t.lock() {
                let _ = t.flush();
            }
        }
    }
}

impl Drop for MavlinkVehicle {
    fn drop(&mut self) {
        for t in &self.tasks {
            t.abort();
        }
        self.flush_tlog();
    }
}

impl Vehicle for MavlinkVehicle {
    fn start(&mut self, action: ActionStart) -> Result<(), VehicleError> {
        self.drive(|d, now| d.start(action, now))
    }

    fn start_still(&mut self, action: ActionStart) -> Result<(), VehicleError> {
        self.drive(|d, now| d.start_still(action, now))
    }

    fn stop(&mut self, id: VehicleActionId) -> Result<(), VehicleError> {
        self.drive(|d, now| d.stop(id, now))
    }

    fn try_event(&mut self) -> Option<VehicleEvent> {
        self.events.try_recv().ok()
    }

    fn wait_event(&mut self, timeout: Duration) -> Option<VehicleEvent> {
        self.events.recv_timeout(timeout).ok()
    }

    fn now_ms(&self) -> u64 {
        self.shared.clock_ms.load(Ordering::Relaxed)
    }

    fn position(&self) -> Option<(f64, f64)> {
        self.shared.position()
    }

    fn silence(&self) -> Option<Duration> {
        self.shared.age(&self.shared.heartbeat_at_ms)
    }

    fn clock_age(&self) -> Option<Duration> {
        self.shared.age(&self.shared.clock_at_ms)
    }
}

/// Where the vehicle is (metres east and north of home), readable from elsewhere while the mission holds
/// the vehicle (the live page's track).
pub type PositionProbe = Arc<dyn Fn() -> Option<(f64, f64)> + Send + Sync>;

impl MavlinkVehicle {
    pub fn position_probe(&self) -> PositionProbe {
        let shared = self.shared.clone();
        Arc::new(move || shared.position())
    }

    /// Mode, arming, battery and link state for the live page. It never waits for the driver's lock (the
    /// mission loop must not contend for it): while the pump holds it, the last status is given again.
    pub fn status_probe(&self) -> StatusProbe {
        let shared = self.shared.clone();
        let timeout = self
            .shared
            .driver
            .lock()
            .map_or(Duration::from_secs(3), |d| {
                Duration::from_millis(d.config().link.heartbeat_timeout_ms)
            });
        let last = Arc::new(Mutex::new(VehicleStatus::default()));
        Arc::new(move || {
            let Ok(mut last) = last.lock() else {
                return VehicleStatus::default();
            };
            if let Ok(d) = shared.driver.try_lock() {
                let t = d.telemetry();
                last.mode = t
                    .custom_mode
                    .map(|m| super::mode_names::mode_name(m, t.vehicle_type));
                last.armed = t.armed;
                last.battery_percent = t.battery_percent;
            }
            last.link = link_state(shared.age(&shared.heartbeat_at_ms), timeout);
            last.clone()
        })
    }

    /// The goal intake of both endpoints (the goals each ground station holds).
    pub fn goal_intake(&self) -> Arc<Mutex<GoalIntake>> {
        self.intake.clone()
    }
}

impl MavlinkVehicle {
    /// Hands the driver's events to the channel, under its lock as the pump does (their order is kept).
    /// `START` / `END` on the driver at the link clock's now; what it reports is delivered and the link
    /// task woken to send what it queued.
    fn drive(
        &mut self,
        f: impl FnOnce(&mut Driver, u64) -> Result<(), VehicleError>,
    ) -> Result<(), VehicleError> {
        let now = self.shared.clock_now();
        {
            let mut d = self
                .shared
                .driver
                .lock()
                .map_err(|_| VehicleError::Closed)?;
            f(&mut d, now)?;
            self.deliver(&mut d);
        }
        self.shared.notify.notify_one();
        Ok(())
    }

    fn deliver(&self, d: &mut Driver) {
        for e in d.take_events() {
            let _ = self.events_tx.send(e);
        }
    }
}

impl Shared {
    /// The driver's timeouts run on the pump's monotonic clock; start/stop stamp with it too.
    fn clock_now(&self) -> u64 {
        self.epoch.elapsed().as_millis() as u64
    }
}

/// A standalone goal intake (`mavtempo goal serve`): answers uploads to component 191 at `addr`.
pub struct GoalServer {
    pub local_addr: Option<SocketAddr>,
    pub events: std_mpsc::Receiver<VehicleEvent>,
    pub stats: Arc<LinkStats>,
    task: tokio::task::JoinHandle<()>,
}

impl GoalServer {
    pub async fn start(
        addr: &str,
        system_id: u8,
        known: KnownLocations,
        decider: Decider,
        tlog: Option<PathBuf>,
    ) -> Result<Self, LinkError> {
        Self::start_signed(addr, system_id, known, decider, tlog, None).await
    }

    /// [`GoalServer::start`] that signs its frames and takes only frames signed with `signing` (key, link
    /// id), as a companion whose config has a `link.signing_key` does.
    pub async fn start_signed(
        addr: &str,
        system_id: u8,
        known: KnownLocations,
        decider: Decider,
        tlog: Option<PathBuf>,
        signing: Option<([u8; 32], u8)>,
    ) -> Result<Self, LinkError> {
        let transport = bind(addr).await?;
        let local_addr = transport.local_addr();
        let tlog = tlog.as_deref().map(open_tlog).transpose()?;
        let (tx, rx) = std_mpsc::channel();
        let stats = Arc::new(LinkStats::default());
        let task = tokio::spawn(
            Pump {
                transport,
                shared: None,
                follow: None,
                intake: Some((
                    Arc::new(Mutex::new(GoalIntake::new(known, 1))),
                    Arc::new(Mutex::new(decider)),
                )),
                own_system: system_id,
                signer_key: signing,
                tlog,
                events: tx,
                stats: stats.clone(),
                reconnect: Duration::from_millis(200),
                epoch: Instant::now(),
            }
            .run(),
        );
        Ok(Self {
            local_addr,
            events: rx,
            stats,
            task,
        })
    }

    /// A goal intake deciding with [`SyntacticDecider`], no `.tlog`: for tools, tests and benchmarks.
    pub async fn syntactic(addr: &str, home: super::geo::Home) -> Result<Self, LinkError> {
        Self::start(
            addr,
            1,
            KnownLocations::new(home),
            Decider::Local(Box::new(SyntacticDecider)),
            None,
        )
        .await
    }

    /// Runs until the task ends (it does not on its own).
    pub async fn join(mut self) {
        let task = std::mem::replace(&mut self.task, tokio::spawn(async {}));
        let _ = task.await;
    }
}

impl Drop for GoalServer {
    fn drop(&mut self) {
        self.task.abort();
    }
}
