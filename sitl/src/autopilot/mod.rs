//! The simulated autopilot: ArduPilot Rover's modes, arming, commands, mission protocol and AUTO
//! executor, telemetry, payload and the effects of faults. It consumes decoded frames and sim
//! ticks and produces frames; it never touches a socket (see `sim.rs`).

mod ap_camera;
mod auto;
mod boot;
mod command_memory;
mod commands;
mod copter;
mod mission;
mod modes;
mod params;
mod payload_ops;
mod px4;
mod telemetry;

use std::time::Duration;

use mavlink::dialects::ardupilotmega::*;
use mavlink::Message;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

pub use modes::Mode;

use crate::battery::Battery;
use crate::config::{MissionRequestKind, SimConfig, VehicleKind};
use crate::faults::{FaultEngine, LinkFaults, SimEvent};
use crate::geo::LocalFrame;
use crate::link::{Inbound, PeerId};
use crate::payload::{Camera, DownlinkRun, Sampler, Storage};
use crate::physics::{Kinematics, Target};
use crate::scenario::{Behaviour, EventKind, FailResult, Fault, VehicleParams};
use crate::snapshot::Snapshot;
use crate::time::later;
use crate::world::{Disc, World};

use auto::Exec;
use commands::Cmd;
use mission::{Item, Upload};
use telemetry::Streams;

/// Who sent a request: where its answers (COMMAND_ACK, MISSION_*) go and whom they address.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sender {
    pub peer: PeerId,
    pub sysid: u8,
    pub compid: u8,
}

/// Where an outgoing frame goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dest {
    All,
    Peer(PeerId),
}

pub struct Autopilot {
    // configuration
    system_id: u8,
    vehicle: VehicleKind,
    tick_ms: u64,
    mission_request: MissionRequestKind,
    mission_rerequest: Duration,
    mission_timeout: Duration,
    epoch_unix_us: u64,
    frame: LocalFrame,
    params: VehicleParams,
    /// Where the sim follows ArduPilot more closely than its simple model (`[autopilot]`).
    behaviour: Behaviour,
    // state
    now_ms: u64,
    /// Sim time of the last (re)boot: time_boot_ms counts from it.
    booted_ms: u64,
    kin: Kinematics,
    mode: Mode,
    armed: bool,
    battery: Battery,
    storage: Storage,
    camera: Camera,
    downlink: Option<DownlinkRun>,
    downlink_rate_override: Option<f64>,
    /// What AP_Camera reports (camera = "ardupilot").
    ap_camera: ap_camera::ApCamera,
    sampler: Sampler,
    servos: [u16; 16],
    world: World,
    mission: Vec<Item>,
    exec: Exec,
    guided_target: Option<Target>,
    /// The copter's takeoff, landing and landed state (`copter.rs`).
    copter: copter::CopterState,
    speed_override: Option<f64>,
    rtl_reported: bool,
    upload: Option<Upload>,
    /// The fence list (mission_type FENCE) and FENCE_* parameters (src/fence.rs).
    fence: Vec<Item>,
    fence_params: crate::fence::FenceParams,
    streams: Streams,
    command_failures: Vec<(u16, MavResult, u32)>,
    /// The last command of each kind and its answer: duplicates and re-sent copies answered again.
    cmd_memory: command_memory::CommandMemory,
    nav_blocked_until_ms: u64,
    was_moving: bool,
    exhausted_reported: bool,
    distance_m: f64,
    pictures_ok: u32,
    pictures_failed: u32,
    statustexts: Vec<String>,
    /// COMMAND_LONG/INT received that command the vehicle (all but message requests), copies included;
    /// and among them ARM requests.
    control_commands: u32,
    arm_commands: u32,
    // plumbing
    faults: FaultEngine,
    pub link_faults: LinkFaults,
    out: Vec<(Dest, MavMessage)>,
    events: Vec<SimEvent>,
}

/// Keep the last few STATUSTEXTs in the snapshot for test assertions.
const KEEP_TEXTS: usize = 32;

impl Autopilot {
    pub fn new(cfg: &SimConfig) -> Self {
        let s = &cfg.scenario;
        let frame = LocalFrame::new(cfg.home_point());
        // Independent streams so that link noise never shifts picture sizes.
        let camera_rng = ChaCha8Rng::seed_from_u64(cfg.seed ^ 0xC0FF_EE00_CAFE_0001);
        let link_rng = ChaCha8Rng::seed_from_u64(cfg.seed ^ 0x5EED_0000_11AA_0002);
        let mut ap = Self {
            system_id: cfg.system_id,
            vehicle: cfg.vehicle,
            tick_ms: u64::from(cfg.tick_ms.max(1)),
            mission_request: cfg.mission_request,
            mission_rerequest: cfg.mission_rerequest,
            mission_timeout: cfg.mission_timeout,
            epoch_unix_us: cfg.epoch_unix_us,
            frame,
            params: s.vehicle.clone(),
            behaviour: s.autopilot.behaviour(),
            now_ms: 0,
            booted_ms: 0,
            kin: Kinematics {
                flies: cfg.vehicle == VehicleKind::Copter,
                ..Kinematics::default()
            },
            mode: Mode::Manual,
            armed: false,
            battery: Battery::new(&s.battery),
            storage: Storage::empty(&s.camera),
            camera: Camera::new(&s.camera, camera_rng),
            downlink: None,
            downlink_rate_override: None,
            ap_camera: ap_camera::ApCamera::default(),
            sampler: Sampler::new(&s.sampler),
            servos: [1500; 16],
            world: World::new(s, &frame),
            mission: Vec::new(),
            exec: Exec::default(),
            guided_target: None,
            copter: Default::default(),
            speed_override: None,
            rtl_reported: false,
            upload: None,
            fence: Vec::new(),
            fence_params: s.fence.clone(),
            streams: Streams::default(),
            command_failures: Vec::new(),
            cmd_memory: Default::default(),
            nav_blocked_until_ms: 0,
            was_moving: false,
            exhausted_reported: false,
            distance_m: 0.0,
            pictures_ok: 0,
            pictures_failed: 0,
            statustexts: Vec::new(),
            control_commands: 0,
            arm_commands: 0,
            faults: FaultEngine::new(&s.faults),
            link_faults: LinkFaults::new(link_rng),
            out: Vec::new(),
            events: Vec::new(),
        };
        ap.streams = ap.default_streams();
        ap.mission = ap.empty_mission();
        ap.fence = ap.fence_items(&s.fence);
        ap.mode = ap.boot_mode();
        ap
    }

    pub fn system_id(&self) -> u8 {
        self.system_id
    }

    pub fn now_ms(&self) -> u64 {
        self.now_ms
    }

    pub fn tick_ms(&self) -> u64 {
        self.tick_ms
    }

    /// Frames produced since the last call.
    pub fn take_output(&mut self) -> Vec<(Dest, MavMessage)> {
        std::mem::take(&mut self.out)
    }

    pub(crate) fn send(&mut self, dest: Dest, msg: MavMessage) {
        self.out.push((dest, msg));
    }

    pub(crate) fn send_to(&mut self, peer: PeerId, msg: MavMessage) {
        self.send(Dest::Peer(peer), msg);
    }

    /// STATUSTEXT to everyone (chunked beyond 50 characters).
    pub(crate) fn text(&mut self, severity: MavSeverity, text: &str) {
        tracing::debug!(t_ms = self.now_ms, "sitl: {text}");
        self.statustexts.push(text.to_string());
        if self.statustexts.len() > KEEP_TEXTS {
            self.statustexts.remove(0);
        }
        let bytes = text.as_bytes();
        let chunks: Vec<&[u8]> = bytes.chunks(50).collect();
        let id = if chunks.len() > 1 {
            (self.now_ms % 65_535) as u16 + 1
        } else {
            0
        };
        for (i, chunk) in chunks.iter().enumerate() {
            let mut buf = [0u8; 50];
            buf[..chunk.len()].copy_from_slice(chunk);
            self.send(
                Dest::All,
                MavMessage::STATUSTEXT(STATUSTEXT_DATA {
                    severity,
                    text: buf.into(),
                    id,
                    chunk_seq: i as u8,
                }),
            );
        }
    }

    /// One decoded frame from a peer.
    pub fn handle(&mut self, f: Inbound) {
        let from = Sender {
            peer: f.peer,
            sysid: f.header.system_id.min(255) as u8,
            compid: f.header.component_id,
        };
        // Faults due now (e.g. at t = 0) apply before the message is handled.
        self.process_events();
        // Only what is addressed to this autopilot (system id, component 1) or broadcast: a
        // companion's component 191 must not see its goal uploads answered by the autopilot.
        let ts = f.msg.target_system_id();
        let tc = f.msg.target_component_id();
        if ts.is_some_and(|t| t != 0 && t != self.system_id) || tc.is_some_and(|c| c != 0 && c != 1)
        {
            return;
        }
        match &f.msg {
            MavMessage::COMMAND_LONG(m) => {
                self.on_command(Cmd::from_long(from, f.header.sequence, m))
            }
            MavMessage::COMMAND_INT(m) => {
                self.on_command(Cmd::from_int(from, f.header.sequence, m))
            }
            MavMessage::SET_MODE(m) => self.on_set_mode(from, m),
            MavMessage::MISSION_COUNT(m) => self.on_mission_count(from, m),
            MavMessage::MISSION_ITEM_INT(m) => self.on_item_int(from, m),
            MavMessage::MISSION_ITEM(m) => self.on_item_float(from, m),
            MavMessage::MISSION_REQUEST_LIST(m) => self.on_request_list(from, m),
            MavMessage::MISSION_REQUEST_INT(m) => {
                self.on_request_item(from, m.seq, false, m.mission_type)
            }
            MavMessage::MISSION_REQUEST(m) => {
                self.on_request_item(from, m.seq, true, m.mission_type)
            }
            MavMessage::MISSION_CLEAR_ALL(m) => self.on_clear_all(from, m),
            MavMessage::MISSION_SET_CURRENT(m) => {
                if usize::from(m.seq) < self.mission.len() {
                    self.exec.restart_at(m.seq.max(self.first_item()));
                }
                self.broadcast_mission_current();
            }
            MavMessage::SET_POSITION_TARGET_GLOBAL_INT(m) => self.on_set_position_target(m),
            MavMessage::REQUEST_DATA_STREAM(m) => self.on_request_data_stream(m),
            MavMessage::PARAM_REQUEST_READ(m) => self.on_param_request_read(from, m),
            MavMessage::PARAM_REQUEST_LIST(_) => self.on_param_request_list(from),
            MavMessage::PARAM_SET(m) => self.on_param_set(from, m),
            _ => {}
        }
        self.process_events();
    }

    /// Advances the sim by one tick.
    pub fn tick(&mut self) {
        self.now_ms += self.tick_ms;
        let dt = self.tick_ms as f64 / 1000.0;
        for fault in self.faults.due(self.now_ms) {
            self.apply_fault(fault);
        }
        self.step_auto();
        let target = self.nav_target();
        let factor = self.world.speed_factor(&self.kin.pos);
        let dist = self.kin.step(dt, target.as_ref(), &self.params, factor);
        self.distance_m += dist;
        self.step_copter(dt);
        let still = self.kin.is_still();
        if !still && !self.was_moving {
            self.emit_event(EventKind::Moving, 0);
        }
        self.was_moving = !still;
        let recharge = still && self.world.sunlit(&self.kin.pos);
        self.battery.step(dt, dist, recharge);
        let exhausted = self.battery.pct <= 0.0;
        if exhausted && !self.exhausted_reported {
            self.text(MavSeverity::MAV_SEVERITY_CRITICAL, "Battery exhausted");
        }
        self.exhausted_reported = exhausted;
        self.step_rtl();
        self.step_payload();
        self.step_telemetry();
        self.process_events();
    }

    /// Feeds this step's events to the fault triggers, then applies faults due now.
    fn process_events(&mut self) {
        for ev in std::mem::take(&mut self.events) {
            self.faults.on_event(ev, self.now_ms);
        }
        for fault in self.faults.due(self.now_ms) {
            self.apply_fault(fault);
        }
    }

    pub(crate) fn set_mode(&mut self, m: Mode) -> Result<(), &'static str> {
        if m == Mode::Auto && self.mission_items() == 0 {
            self.text(
                MavSeverity::MAV_SEVERITY_NOTICE,
                "No Mission. Can't set AUTO.",
            );
            return Err("no mission");
        }
        if m.navigates() && self.nav_blocked() {
            self.text(MavSeverity::MAV_SEVERITY_ERROR, NAV_FAIL_TEXT);
            return Err("navigation failed");
        }
        if m == self.mode {
            return Ok(());
        }
        // Without a fix ArduPilot has no position: armed, a mode that needs one cannot be entered
        // (Mode::enter), and RTL has no home even disarmed (ModeRTL::_enter).
        if !self.gps_fixed() && ((self.armed && m.navigates()) || m == Mode::Rtl) {
            let text = self.mode_refused_text(m);
            self.text(MavSeverity::MAV_SEVERITY_WARNING, &text);
            return Err("no position");
        }
        if self.behaviour.guided_submodes && m.navigates() {
            // Entering AUTO, GUIDED or RTL initialises AR_WPNav at WP_SPEED: an earlier speed
            // change is forgotten.
            self.speed_override = None;
        }
        self.mode = m;
        match m {
            Mode::Auto => {
                if self.armed {
                    self.start_mission();
                }
            }
            Mode::Guided => self.guided_target = None,
            Mode::Rtl => self.rtl_reported = false,
            Mode::Manual | Mode::Hold | Mode::Land => {}
        }
        self.emit_event(EventKind::ModeChanged, i64::from(self.mode_number(m)));
        self.send(Dest::All, self.heartbeat());
        self.broadcast_mission_current();
        Ok(())
    }

    /// Arms, or returns why not (one STATUSTEXT each).
    fn arm(&mut self, force: bool) -> Result<(), Vec<String>> {
        if self.armed {
            return Ok(());
        }
        if !force {
            let refusals = self.arm_refusals();
            if !refusals.is_empty() {
                return Err(refusals);
            }
        }
        self.armed = true;
        self.emit_event(EventKind::Armed, 0);
        if self.mode == Mode::Auto {
            self.start_mission();
        }
        self.send(Dest::All, self.heartbeat());
        Ok(())
    }

    fn disarm(&mut self) {
        if self.armed {
            self.armed = false;
            self.emit_event(EventKind::Disarmed, 0);
            self.send(Dest::All, self.heartbeat());
        }
    }

    fn nav_blocked(&self) -> bool {
        self.now_ms < self.nav_blocked_until_ms
    }

    /// What each fault does to the vehicle (link faults go to the link's state).
    pub fn apply_fault(&mut self, fault: Fault) {
        tracing::info!(t_ms = self.now_ms, ?fault, "sitl: fault");
        match fault {
            Fault::CommandFails {
                command,
                result,
                count,
            } => {
                let r = match result {
                    FailResult::Denied => MavResult::MAV_RESULT_DENIED,
                    FailResult::Failed => MavResult::MAV_RESULT_FAILED,
                    FailResult::TemporarilyRejected => MavResult::MAV_RESULT_TEMPORARILY_REJECTED,
                };
                self.command_failures.push((command, r, count));
            }
            Fault::PictureFails { count } => self.camera.fail_next += count,
            Fault::PictureHangs { count } => self.camera.hang_next += count,
            Fault::PictureDuration {
                capture_time_s,
                size_mib,
                count,
            } => {
                let n = count.min(crate::payload::MAX_PICTURES_PER_REQUEST) as usize;
                self.camera
                    .duration_next
                    .extend(std::iter::repeat_n((capture_time_s, size_mib), n));
            }
            Fault::SlowZone { zone } => self.world.slow.push(Disc::from_zone(&zone, &self.frame)),
            Fault::BatteryDrop { percent } => {
                self.battery.drop_by(percent);
                self.text(
                    MavSeverity::MAV_SEVERITY_WARNING,
                    &format!("Battery dropped by {percent:.0}%"),
                );
            }
            Fault::StorageShrink { mib } => {
                self.storage.capacity_mib = (self.storage.capacity_mib - mib).max(0.0);
                self.storage.used_mib = self.storage.used_mib.min(self.storage.capacity_mib);
                self.text(
                    MavSeverity::MAV_SEVERITY_WARNING,
                    "Storage capacity reduced",
                );
            }
            Fault::NavFails { duration_s } => {
                // + 1 ms: a zero duration still refuses navigation at this instant.
                self.nav_blocked_until_ms = later(self.now_ms, duration_s).saturating_add(1);
                self.text(MavSeverity::MAV_SEVERITY_ERROR, NAV_FAIL_TEXT);
                if self.mode.navigates() {
                    // Stop: HOLD, as a failed navigation module leaves the rover.
                    self.mode = Mode::Hold;
                    self.emit_event(
                        EventKind::ModeChanged,
                        i64::from(self.mode_number(Mode::Hold)),
                    );
                    self.send(Dest::All, self.heartbeat());
                    self.broadcast_mission_current();
                }
            }
            Fault::Arm => {
                if let Err(why) = self.arm(false) {
                    tracing::info!(?why, "arm fault: arming refused");
                }
            }
            Fault::ModeChange { mode } => match self.mode_from_number(mode) {
                Some(m) => {
                    if let Err(why) = self.set_mode(m) {
                        tracing::info!(mode, why, "mode_change fault: the mode was refused");
                    }
                }
                None => tracing::warn!(mode, "mode_change fault: no such mode on this vehicle"),
            },
            Fault::LinkBlackout { duration_s } => {
                self.link_faults.blackout(self.now_ms, duration_s)
            }
            Fault::LinkQuality {
                loss,
                duplicate,
                reorder,
                duration_s,
            } => self
                .link_faults
                .set_quality(self.now_ms, loss, duplicate, reorder, duration_s),
            Fault::DownlinkRate { mib_per_s } => self.downlink_rate_override = Some(mib_per_s),
            Fault::Reboot { silent_s } => self.reboot(silent_s),
        }
    }

    /// A restart: silent for `silent_s`, then booted afresh where the vehicle stands (see
    /// [`Fault::Reboot`]).
    fn reboot(&mut self, silent_s: f64) {
        self.link_faults.blackout(self.now_ms, silent_s);
        self.link_faults.drop_held();
        self.booted_ms = later(self.now_ms, silent_s);
        if self.armed {
            self.armed = false;
            self.emit_event(EventKind::Disarmed, 0);
        }
        self.mode = self.boot_mode();
        self.guided_target = None;
        self.speed_override = None;
        self.exec = Exec::default();
        self.downlink = None;
        self.camera.cancel();
        self.ap_camera = ap_camera::ApCamera::booted(self.camera.next_index());
        self.upload = None;
        self.streams = self.default_streams();
        self.cmd_memory.clear();
    }

    /// A read-only picture of the vehicle for tests and the demo.
    pub fn snapshot(&self) -> Snapshot {
        let geo = self.frame.to_geo(self.kin.pos);
        Snapshot {
            time_ms: self.now_ms,
            lat: geo.lat,
            lon: geo.lon,
            north_m: self.kin.pos.x,
            east_m: self.kin.pos.y,
            depth_m: self.kin.depth,
            landed_state: self.landed_state() as u8,
            speed_mps: self.kin.speed,
            heading_deg: self.kin.heading.to_degrees().rem_euclid(360.0),
            distance_m: self.distance_m,
            mode: self.mode.name(),
            custom_mode: self.reported_mode(),
            armed: self.armed,
            battery_pct: self.battery.pct,
            storage_capacity_mib: self.storage.capacity_mib,
            storage_used_mib: self.storage.used_mib,
            pictures_ok: self.pictures_ok,
            pictures_failed: self.pictures_failed,
            samples: self.sampler.samples,
            downlink_active: self.downlink.is_some(),
            mission_total: self.mission_items() as u16,
            mission_current: self.exec.current,
            mission_complete: self.exec.complete,
            link_blackout: self.link_faults.in_blackout(self.now_ms),
            frames_dropped: self.link_faults.dropped,
            statustexts: self.statustexts.clone(),
            control_commands: self.control_commands,
            arm_commands: self.arm_commands,
        }
    }
}

pub const NAV_FAIL_TEXT: &str = "Navigation failed: no map available";
