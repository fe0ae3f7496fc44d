//! Action bindings at run time: one state machine per running action instance, realising its task in MAVLink
//! and recognising its end (nominal / interrupted / failed, seed 1 §2.1). Pure: messages in, messages out.

use mavlink::dialects::ardupilotmega::{MavCmd, MavMessage, MavResult, COMMAND_INT_DATA};

use super::authority::Arming;
use super::capture_evidence::{CaptureEvidence, CaptureStatus, Verdict};
use super::commands::{Command, CommandClient, CommandOutcome};
use super::config::{Autopilot, Binding, Mode, VehicleConfig};
use super::flight::{Flight, FlightEnd};
use super::items::MissionItem;
use super::mission_client::{MissionClient, MissionOutcome};
use super::telemetry::Telemetry;
use super::types::{ActionStart, Enu, ReportStatus, StateValue, VehicleActionId};
use geodesy::deg_to_e7;

/// What an action run needs from the driver.
pub struct Ctx<'a> {
    /// Wall-clock ms: protocol timeouts (ACKs, mission transfer) are about the link.
    pub now: u64,
    /// Vehicle ms (time_boot_ms): the action's own durations (holds, capture timeout, polling) follow the
    /// vehicle's clock, so a simulator at 200x speed-up keeps them right.
    pub vnow: u64,
    pub cfg: &'a VehicleConfig,
    pub tel: &'a Telemetry,
    pub cmds: &'a mut CommandClient,
    pub mission: &'a mut MissionClient,
    pub out: &'a mut Vec<MavMessage>,
    pub target: (u8, u8),
}

impl Ctx<'_> {
    pub(crate) fn command(&mut self, id: VehicleActionId, cmd: Command) {
        self.cmds.send(id, cmd, self.now, self.out);
    }

    pub(crate) fn set_mode(&mut self, id: VehicleActionId, mode: Mode) {
        let (p2, p3) = mode.set_mode_params();
        // p1 = MAV_MODE_FLAG_CUSTOM_MODE_ENABLED.
        let cmd = Command::long(
            MavCmd::MAV_CMD_DO_SET_MODE,
            self.target,
            [1.0, p2, p3, 0.0, 0.0, 0.0, 0.0],
        );
        self.command(id, cmd);
    }

    pub(crate) fn arm(&mut self, id: VehicleActionId) {
        let cmd = Command::long(
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            self.target,
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        );
        self.command(id, cmd);
    }

    fn request_storage(&mut self) {
        self.request_message(261); // STORAGE_INFORMATION
    }

    fn request_capture_status(&mut self) {
        self.request_message(262); // CAMERA_CAPTURE_STATUS
    }

    /// MAV_CMD_REQUEST_MESSAGE; fire and forget (no owner waits on it).
    fn request_message(&mut self, msg_id: u16) {
        let cmd = Command::long(
            MavCmd::MAV_CMD_REQUEST_MESSAGE,
            self.target,
            [f32::from(msg_id), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        );
        self.cmds.send(u64::MAX, cmd, self.now, self.out);
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub struct End {
    pub status: ReportStatus,
    pub reason: Option<String>,
    pub state: Vec<(String, StateValue)>,
}

impl End {
    fn nominal() -> Self {
        End {
            status: ReportStatus::Nominal,
            reason: None,
            state: Vec::new(),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    Arming,
    /// Waiting for the ACK of the command that starts the action.
    Starting,
    Uploading,
    SettingCurrent,
    Running,
    /// Sampler: hold of step i until the given time.
    Holding(usize, u64),
    /// Sampler: waiting for the ACK of step i.
    Servo(usize),
    /// Picture: captured (or not) at the given time; waiting for the storage level it left, so that the
    /// report carries it.
    Stored(u64),
}

/// One running action instance.
#[derive(Debug)]
pub struct Run {
    pub id: VehicleActionId,
    pub task: String,
    binding: Binding,
    phase: Phase,
    started_ms: u64,
    /// Destination (move), last survey item, picture index, recharge level.
    goal: Option<Enu>,
    last_seq: u16,
    target_level: f64,
    /// Mode the action expects the vehicle to stay in, once reached (foreign mode change = failure).
    expect_mode: Option<u32>,
    mode_seen: bool,
    last_poll: u64,
    /// The end of a capture waiting for its storage level.
    pending: Option<End>,
    /// A picture's end from the camera's status, should its CAMERA_IMAGE_CAPTURED be lost.
    capture: Option<CaptureEvidence>,
    /// A failed motion waiting (until the vehicle ms given) for the vehicle to be still before its report.
    settling: Option<(u64, End)>,
    /// Its settling is over (a report taken from it is not held again).
    settled: bool,
    /// Times the run was commanded again after an autopilot restart.
    resumes: u32,
    /// When (vehicle ms) a heartbeat showed the vehicle disarmed under this run.
    disarmed_since: Option<u64>,
    /// A picture: the index of the camera's last CAMERA_FEEDBACK before the capture was commanded.
    feedback_before: Option<u16>,
    /// A motion the next action needs still: it ends within its radius once the vehicle is still
    /// (`[state] still_below_m_s`), not as it enters the radius.
    pub end_still: bool,
    /// A flight action (src/vehicle/src/flight.rs) runs instead of the bindings above.
    flight: Option<Flight>,
}

/// How long (vehicle ms) a run disarmed under it waits for the restart that explains it before failing.
const DISARM_GRACE_MS: u64 = 1_500;

/// An action is commanded again after at most this many autopilot restarts; the next one fails it.
pub const MAX_RESUMES: u32 = 3;

/// What a survey mission starts with. ArduPilot replaces item 0 with home (AP_Mission): a placeholder keeps
/// the survey's numbering. PX4 stores and flies every item from 0 (src/modules/mavlink/mavlink_mission.cpp
/// has no home item; the navigator starts at `current_seq` 0): a placeholder there would be a waypoint at
/// home, flown first.
fn survey_head(autopilot: Autopilot, home: &super::geo::Home) -> Vec<MissionItem> {
    match autopilot {
        Autopilot::Ardupilot => vec![MissionItem::waypoint(home.lat, home.lon, 0.0)],
        Autopilot::Px4 => Vec::new(),
    }
}
/// How long (vehicle ms) a picture's report waits for STORAGE_INFORMATION.
const STORAGE_WAIT_MS: u64 = 2_000;

fn lawnmower(center: Enu, width: f64, height: f64, spacing: f64) -> Vec<Enu> {
    let rows = (height / spacing).floor() as usize + 1;
    let (x0, x1) = (center.east - width / 2.0, center.east + width / 2.0);
    let y0 = center.north - height / 2.0;
    let mut pts = Vec::with_capacity(rows * 2);
    for r in 0..rows {
        let y = y0 + r as f64 * spacing;
        let (a, b) = if r % 2 == 0 { (x0, x1) } else { (x1, x0) };
        pts.push(Enu::new(a, y, center.up));
        pts.push(Enu::new(b, y, center.up));
    }
    pts
}

/// Why an action cannot start: its arguments or the vehicle's state refuse it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum StartError {
    #[error("needs a location argument `{0}`")]
    NoLocation(String),
    #[error("another mission transfer is running")]
    TransferBusy,
    #[error("command {0} unknown to the dialect")]
    UnknownCommand(u16),
    #[error(
        "the vehicle is disarmed and arming is the operator's ([authority] arm = \"operator\")"
    )]
    NotArmed,
    #[error("the vehicle is on the ground: it must take off first")]
    OnGround,
    #[error("no landing mode: [modes] land")]
    NoLandMode,
}

fn location_arg(start: &ActionStart, name: &str) -> Result<Enu, StartError> {
    start
        .arg(name)
        .and_then(|a| a.as_enu())
        .ok_or_else(|| StartError::NoLocation(name.to_string()))
}

impl Run {
    /// Checks the arguments and issues the first messages.
    pub fn begin(
        start: &ActionStart,
        binding: &Binding,
        ctx: &mut Ctx,
    ) -> Result<Self, StartError> {
        let mut run = Run {
            id: start.id,
            task: start.task.clone(),
            binding: binding.clone(),
            phase: Phase::Starting,
            started_ms: ctx.vnow,
            goal: None,
            last_seq: 0,
            target_level: 0.0,
            expect_mode: None,
            mode_seen: false,
            last_poll: ctx.vnow,
            pending: None,
            capture: None,
            resumes: 0,
            disarmed_since: None,
            feedback_before: None,
            settling: None,
            settled: false,
            end_still: false,
            flight: None,
        };
        let id = start.id;
        match binding {
            Binding::Move { to, .. } => {
                run.goal = Some(location_arg(start, to)?);
                run.expect_mode = Some(ctx.cfg.modes.guided.custom_mode());
                run.arm_or(ctx, Self::start_motion)?;
            }
            Binding::Survey {
                area,
                width_m,
                height_m,
                spacing_m,
                ..
            } => {
                let center = location_arg(start, area)?;
                let pts = lawnmower(center, *width_m, *height_m, *spacing_m);
                let home = ctx.cfg.home;
                let mut items = survey_head(ctx.cfg.autopilot, &home);
                items.extend(pts.iter().map(|p| {
                    let (lat, lon, _) = home.to_global(*p);
                    MissionItem::waypoint(lat, lon, p.up as f32)
                }));
                run.last_seq = (items.len() - 1) as u16;
                run.goal = pts.last().copied();
                run.expect_mode = Some(ctx.cfg.modes.auto.custom_mode());
                if !ctx.mission.upload(id, items, ctx.now, ctx.out) {
                    return Err(StartError::TransferBusy);
                }
                run.phase = Phase::Uploading;
            }
            Binding::TakePicture { camera_id, .. } => run.start_capture(ctx, *camera_id),
            Binding::Sample { steps } => {
                run.servo(ctx, 0, steps[0].servo, steps[0].pwm);
            }
            Binding::ReturnHome { .. } => {
                run.goal = Some(Enu::default());
                run.expect_mode = Some(ctx.cfg.modes.rtl.custom_mode());
                run.arm_or(ctx, |r, c| {
                    let rtl = c.cfg.modes.rtl;
                    c.set_mode(r.id, rtl);
                })?;
            }
            Binding::Recharge {
                until_percent,
                level_arg,
            } => {
                run.target_level = level_arg
                    .as_deref()
                    .and_then(|n| start.arg(n))
                    .and_then(|a| a.as_number())
                    .unwrap_or(*until_percent);
                run.expect_mode = Some(ctx.cfg.modes.hold.custom_mode());
                let hold = ctx.cfg.modes.hold;
                ctx.set_mode(id, hold);
            }
            Binding::Timed { .. } => run.phase = Phase::Running,
            Binding::Download { command, .. } => start_download(ctx, id, *command)?,
            Binding::Flight(f) => {
                run.phase = Phase::Running;
                run.flight = Some(Flight::begin(start, f, ctx)?);
            }
        }
        Ok(run)
    }

    /// IMAGE_START_CAPTURE of one image, and the camera's status asked for (the count before it).
    fn start_capture(&mut self, ctx: &mut Ctx, camera_id: u8) {
        // p3 = 1 image, p4 = 0: no sequence number.
        let cmd = Command::long(
            MavCmd::MAV_CMD_IMAGE_START_CAPTURE,
            ctx.target,
            [f32::from(camera_id), 0.0, 1.0, 0.0, 0.0, 0.0, 0.0],
        );
        ctx.command(self.id, cmd);
        // The camera's messages carry the autopilot's clock: while it is unknown (no time_boot_ms seen yet)
        // `vnow` is the companion's, and comparing the two would drop this picture's confirmation.
        self.capture = Some(CaptureEvidence::new(ctx.tel.time_boot_ms.unwrap_or(0)));
        self.feedback_before = ctx.tel.camera_feedback_index;
        ctx.request_capture_status();
    }

    fn arm_or(&mut self, ctx: &mut Ctx, then: fn(&mut Run, &mut Ctx)) -> Result<(), StartError> {
        if ctx.tel.armed {
            then(self, ctx);
            self.phase = Phase::Starting;
        } else if ctx.cfg.authority.arm == Arming::Operator {
            return Err(StartError::NotArmed);
        } else {
            ctx.arm(self.id);
            self.phase = Phase::Arming;
        }
        Ok(())
    }

    fn start_motion(&mut self, ctx: &mut Ctx) {
        let (Binding::Move { speed_m_s, .. }, Some(goal)) = (&self.binding, self.goal) else {
            return;
        };
        let (lat, lon, alt) = ctx.cfg.home.to_global(goal);
        // ArduPilot enters GUIDED in its Stop submode, where a speed cannot be set: DO_REPOSITION with a
        // speed then fails. It goes without one, and DO_CHANGE_SPEED follows its ACK (`speed_after_ack`).
        let speed = match ctx.cfg.autopilot {
            Autopilot::Ardupilot => -1.0,
            Autopilot::Px4 => *speed_m_s as f32,
        };
        // DO_REPOSITION over COMMAND_INT; param2 = MAV_DO_REPOSITION_FLAGS_CHANGE_MODE (switch to GUIDED).
        let cmd = Command::Int(COMMAND_INT_DATA {
            param1: speed,
            param2: 1.0,
            param3: 0.0,
            param4: f32::NAN,
            x: deg_to_e7(lat),
            y: deg_to_e7(lon),
            z: alt as f32,
            command: MavCmd::MAV_CMD_DO_REPOSITION,
            target_system: ctx.target.0,
            target_component: ctx.target.1,
            // PX4 answers any frame but GLOBAL_INT with UNSUPPORTED_MAV_FRAME (9): see px4.rs.
            frame: super::px4::command_int_frame(ctx.cfg.autopilot),
            current: 0,
            autocontinue: 0,
        });
        ctx.command(self.id, cmd);
    }

    /// ArduPilot: the move's speed, once DO_REPOSITION put the rover in GUIDED's waypoint submode
    /// (DO_CHANGE_SPEED, ground speed; the speed holds until GUIDED is entered again).
    fn speed_after_ack(&self, ctx: &mut Ctx) {
        let Binding::Move { speed_m_s, .. } = self.binding else {
            return;
        };
        change_speed(ctx, self.id, speed_m_s);
    }

    fn servo(&mut self, ctx: &mut Ctx, step: usize, servo: u8, pwm: u16) {
        let cmd = Command::long(
            MavCmd::MAV_CMD_DO_SET_SERVO,
            ctx.target,
            [f32::from(servo), f32::from(pwm), 0.0, 0.0, 0.0, 0.0, 0.0],
        );
        ctx.command(self.id, cmd);
        self.phase = Phase::Servo(step);
    }

    fn failed(&self, ctx: &Ctx, reason: String) -> End {
        End {
            status: ReportStatus::Failed,
            reason: Some(reason),
            state: self.state_values(ctx, true),
        }
    }

    /// The action's state variables for a non-nominal report: a motion's reached position and what
    /// telemetry says of the vehicle (`[state]`); `with_moving`: its moving/still value too.
    fn state_values(&self, ctx: &Ctx, with_moving: bool) -> Vec<(String, StateValue)> {
        let pos_var = match &self.binding {
            Binding::Move {
                position_variable, ..
            }
            | Binding::Survey {
                position_variable, ..
            }
            | Binding::ReturnHome {
                position_variable, ..
            } => Some(position_variable.as_str()),
            Binding::Flight(f) => f.position_variable(),
            _ => None,
        };
        let mut v = Vec::new();
        if let (Some(var), Some(p)) = (pos_var, ctx.tel.position) {
            v.push((var.to_string(), StateValue::Position(p)));
        }
        if pos_var.is_some() {
            v.extend(ctx.cfg.state.values(ctx.tel, &ctx.cfg.modes, with_moving));
        }
        v
    }

    /// A failed motion is reported once the vehicle is still (within `state.settle_ms`), so that its
    /// report tells the state the vehicle is in, not the one it passes through while braking.
    pub fn settle(&mut self, ctx: &mut Ctx, end: End) -> Option<End> {
        let waits = !self.settled
            && end.status == ReportStatus::Failed
            && self.is_vehicle_motion()
            && ctx.cfg.state.moving.is_some()
            && ctx.cfg.state.is_moving(ctx.tel) == Some(true);
        if !waits {
            return Some(end);
        }
        ctx.cmds.cancel(self.id);
        self.settling = Some((ctx.vnow.saturating_add(ctx.cfg.state.settle_ms), end));
        None
    }

    /// The settled report of a failed motion, with the state as it is now.
    fn settled(&mut self, ctx: &Ctx) -> Option<End> {
        let (_, mut end) = self.settling.take()?;
        self.settled = true;
        end.state = self.state_values(ctx, true);
        Some(end)
    }

    fn is_vehicle_motion(&self) -> bool {
        matches!(
            self.binding,
            Binding::Move { .. }
                | Binding::Survey { .. }
                | Binding::ReturnHome { .. }
                | Binding::Flight(_)
        )
    }

    /// A flight action's end as a report (with the vehicle's state when it failed).
    fn flight_end(&self, ctx: &Ctx, end: Option<FlightEnd>) -> Option<End> {
        Some(match end? {
            FlightEnd::Nominal => End::nominal(),
            FlightEnd::Failed(why) => self.failed(ctx, why),
        })
    }

    pub fn on_command(
        &mut self,
        ctx: &mut Ctx,
        cmd: MavCmd,
        outcome: CommandOutcome,
    ) -> Option<End> {
        if self.settling.is_some() {
            return None;
        }
        if let Some(f) = self.flight.as_mut() {
            let end = f.on_command(ctx, self.id, cmd, outcome);
            return self.flight_end(ctx, end);
        }
        let what = format!("{cmd:?}");
        if cmd == MavCmd::MAV_CMD_DO_CHANGE_SPEED {
            // The move goes on at the autopilot's own speed: its report will say it came early or late.
            if let CommandOutcome::Rejected(_) | CommandOutcome::TimedOut { .. } = outcome {
                tracing::warn!(
                    id = self.id,
                    ?outcome,
                    "the move's speed was not taken: the autopilot's own speed"
                );
            }
            return None;
        }
        match outcome {
            CommandOutcome::Rejected(r) => {
                return Some(self.failed(ctx, format!("{what} refused: {}", result_name(r))))
            }
            CommandOutcome::TimedOut { tries } if !self.command_took_effect(ctx, cmd) => {
                return Some(self.failed(
                    ctx,
                    format!("no COMMAND_ACK for {what} after {tries} tries"),
                ))
            }
            // Its ACKs were lost, but telemetry shows it done: go on as if acknowledged.
            CommandOutcome::TimedOut { .. } | CommandOutcome::Accepted => {}
        }
        match self.phase {
            Phase::Arming => {
                self.phase = Phase::Starting;
                match self.binding {
                    Binding::Move { .. } => self.start_motion(ctx),
                    Binding::ReturnHome { .. } => {
                        let rtl = ctx.cfg.modes.rtl;
                        ctx.set_mode(self.id, rtl);
                    }
                    Binding::Survey { .. } => self.start_auto(ctx),
                    _ => {}
                }
                None
            }
            Phase::SettingCurrent => {
                let auto = ctx.cfg.modes.auto;
                ctx.set_mode(self.id, auto);
                self.phase = Phase::Starting;
                None
            }
            Phase::Starting => {
                self.phase = Phase::Running;
                self.speed_after_ack(ctx);
                if let Binding::Download { .. } = self.binding {
                    ctx.request_storage();
                    self.last_poll = ctx.vnow;
                }
                None
            }
            Phase::Servo(i) => {
                if let Binding::Sample { steps } = &self.binding {
                    self.phase = Phase::Holding(i, ctx.vnow + steps[i].hold_ms);
                }
                None
            }
            _ => None,
        }
    }

    /// The autopilot restarted under this run: the run is commanded again from the start of its protocol
    /// (the vehicle kept its position, so a move goes on from where it stopped).
    pub fn resume(&mut self, ctx: &mut Ctx) -> Option<End> {
        if let Some(f) = self.flight.as_mut() {
            let end = f.resume();
            return self.flight_end(ctx, Some(end));
        }
        self.resumes += 1;
        if self.resumes > MAX_RESUMES {
            return Some(self.failed(
                ctx,
                format!("the autopilot restarted {} times under it", self.resumes),
            ));
        }
        ctx.cmds.cancel(self.id);
        self.mode_seen = false;
        self.disarmed_since = None;
        let id = self.id;
        match &self.binding {
            Binding::Move { .. } | Binding::ReturnHome { .. } | Binding::Survey { .. } => {
                // Disarmed at boot: arming first; its ACK re-sends the move, RTL or AUTO start.
                ctx.arm(id);
                self.phase = Phase::Arming;
            }
            Binding::TakePicture { camera_id, .. } => {
                let camera = *camera_id;
                self.started_ms = ctx.vnow;
                self.pending = None;
                self.phase = Phase::Starting;
                self.start_capture(ctx, camera);
            }
            Binding::Sample { steps } => {
                let first = steps[0];
                self.servo(ctx, 0, first.servo, first.pwm);
            }
            Binding::Recharge { .. } => {
                let hold = ctx.cfg.modes.hold;
                ctx.set_mode(id, hold);
                self.phase = Phase::Starting;
            }
            Binding::Download { command, .. } => {
                if start_download(ctx, id, *command).is_ok() {
                    self.phase = Phase::Starting;
                }
            }
            Binding::Timed { .. } | Binding::Flight(_) => {}
        }
        None
    }

    /// Telemetry shows what an unacknowledged command asked for: armed, or in the mode this run expects.
    fn command_took_effect(&self, ctx: &Ctx, cmd: MavCmd) -> bool {
        match cmd {
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM => ctx.tel.armed,
            MavCmd::MAV_CMD_DO_SET_MODE | MavCmd::MAV_CMD_DO_REPOSITION => {
                self.expect_mode.is_some() && ctx.tel.custom_mode == self.expect_mode
            }
            _ => false,
        }
    }

    fn start_auto(&mut self, ctx: &mut Ctx) {
        // Start from the first real item (0 is home), then AUTO.
        let cmd = Command::long(
            MavCmd::MAV_CMD_DO_SET_MISSION_CURRENT,
            ctx.target,
            [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        );
        ctx.command(self.id, cmd);
        self.phase = Phase::SettingCurrent;
    }

    pub fn on_mission(&mut self, ctx: &mut Ctx, outcome: MissionOutcome) -> Option<End> {
        if self.settling.is_some() {
            return None;
        }
        match outcome {
            MissionOutcome::Uploaded if self.phase == Phase::Uploading => {
                if ctx.tel.armed {
                    self.start_auto(ctx);
                } else if ctx.cfg.authority.arm == Arming::Operator {
                    return Some(self.failed(ctx, StartError::NotArmed.to_string()));
                } else {
                    ctx.arm(self.id);
                    self.phase = Phase::Arming;
                }
                None
            }
            MissionOutcome::Failed(r) => Some(self.failed(ctx, r)),
            _ => None,
        }
    }

    /// A message from the autopilot while the run is active.
    pub fn on_message(&mut self, ctx: &mut Ctx, msg: &MavMessage) -> Option<End> {
        if self.settling.is_some() {
            return None;
        }
        if let Some(f) = self.flight.as_mut() {
            let end = f.on_message(ctx, msg);
            return self.flight_end(ctx, end);
        }
        match msg {
            MavMessage::HEARTBEAT(h) => {
                let armed = h.base_mode.contains(
                    mavlink::dialects::ardupilotmega::MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED,
                );
                let needs_arming = matches!(
                    self.binding,
                    Binding::Move { .. } | Binding::ReturnHome { .. } | Binding::Survey { .. }
                );
                if !armed && needs_arming && self.mode_seen {
                    // Disarmed under a move: a restart (its clock, in the messages that follow, says so and
                    // the run is resumed) or someone else's doing (the run fails after a grace period).
                    self.disarmed_since.get_or_insert(ctx.vnow);
                    return None;
                }
                if let Some(m) = self.expect_mode {
                    if h.custom_mode == m {
                        self.mode_seen = true;
                    } else if self.mode_seen {
                        return Some(self.failed(
                            ctx,
                            format!(
                                "foreign mode change to {}",
                                super::mode_names::mode_name(h.custom_mode, Some(h.mavtype))
                            ),
                        ));
                    }
                }
                None
            }
            // An autopilot error (e.g. "no map available") ends motion; payload failures have their own
            // signals (capture_result, COMMAND_ACK) and must not fail a concurrent move.
            MavMessage::STATUSTEXT(s) if (s.severity as u8) <= 3 && self.is_motion() => {
                let text = s
                    .text
                    .to_str()
                    .unwrap_or("")
                    .trim_end_matches('\0')
                    .to_string();
                Some(self.failed(ctx, format!("autopilot error: {text}")))
            }
            MavMessage::CAMERA_IMAGE_CAPTURED(c)
                if matches!(self.binding, Binding::TakePicture { .. })
                    && !matches!(self.phase, Phase::Stored(_))
                    && self
                        .capture
                        .as_ref()
                        .is_none_or(|e| e.is_current(ctx.tel.vehicle_time(c.time_boot_ms))) =>
            {
                let end = if c.capture_result.bits() == 1 {
                    End::nominal()
                } else {
                    self.failed(
                        ctx,
                        format!("image {} not captured (capture_result 0)", c.image_index),
                    )
                };
                self.stored(ctx, end)
            }
            // ArduPilot's camera library confirms a picture with CAMERA_FEEDBACK only (no
            // CAMERA_IMAGE_CAPTURED): an image index past the one before the command is this picture. It
            // reports no storage (STORAGE_INFORMATION is refused): the picture ends here, not 2 s later.
            MavMessage::CAMERA_FEEDBACK(f)
                if matches!(self.binding, Binding::TakePicture { .. })
                    && !matches!(self.phase, Phase::Stored(_))
                    && self.feedback_before.is_none_or(|b| f.img_idx != b) =>
            {
                Some(End::nominal())
            }
            MavMessage::CAMERA_CAPTURE_STATUS(c) if !matches!(self.phase, Phase::Stored(_)) => {
                let status = CaptureStatus {
                    time_ms: ctx.tel.vehicle_time(c.time_boot_ms),
                    capturing: c.image_status & 1 == 1,
                    count: c.image_count,
                };
                let end = match self.capture.as_mut()?.observe(status)? {
                    Verdict::Captured => End::nominal(),
                    Verdict::NoImage => self.failed(
                        ctx,
                        "the camera is idle again with no new image (CAMERA_CAPTURE_STATUS)".into(),
                    ),
                };
                self.stored(ctx, end)
            }
            MavMessage::STORAGE_INFORMATION(_) if matches!(self.phase, Phase::Stored(_)) => {
                self.pending.take()
            }
            MavMessage::MISSION_ITEM_REACHED(r)
                if matches!(self.binding, Binding::Survey { .. }) =>
            {
                (self.phase == Phase::Running && r.seq >= self.last_seq).then(End::nominal)
            }
            _ => None,
        }
    }

    /// A capture ended: its report waits (at most [`STORAGE_WAIT_MS`]) for the storage level it left.
    fn stored(&mut self, ctx: &mut Ctx, end: End) -> Option<End> {
        ctx.request_storage();
        self.pending = Some(end);
        self.phase = Phase::Stored(ctx.vnow);
        None
    }

    /// Time passed / telemetry changed: recognise ends that are states (position, battery, storage).
    pub fn on_tick(&mut self, ctx: &mut Ctx) -> Option<End> {
        if let Some((until, _)) = &self.settling {
            let still = ctx.cfg.state.is_moving(ctx.tel) != Some(true);
            return if still || ctx.vnow >= *until {
                self.settled(ctx)
            } else {
                None
            };
        }
        if self
            .disarmed_since
            .is_some_and(|t| ctx.vnow.saturating_sub(t) >= DISARM_GRACE_MS)
        {
            let mode = ctx.tel.custom_mode.unwrap_or(0);
            return Some(self.failed(ctx, format!("the vehicle disarmed (mode {mode})")));
        }
        if let Some(f) = self.flight.as_mut() {
            let end = f.on_tick(ctx);
            return self.flight_end(ctx, end);
        }
        match (&self.binding, self.phase) {
            (
                Binding::Move {
                    acceptance_radius_m,
                    vertical_acceptance_m,
                    ..
                },
                Phase::Running,
            ) => {
                let (p, g) = (ctx.tel.position?, self.goal?);
                let vertical_ok = vertical_acceptance_m.is_none_or(|v| (p.up - g.up).abs() <= v);
                let still = !self.end_still || ctx.cfg.state.is_moving(ctx.tel) != Some(true);
                (p.horizontal_distance(&g) <= *acceptance_radius_m && vertical_ok && still)
                    .then(End::nominal)
            }
            (
                Binding::ReturnHome {
                    acceptance_radius_m,
                    ..
                },
                Phase::Running,
            ) => {
                let (p, g) = (ctx.tel.position?, self.goal?);
                (p.horizontal_distance(&g) <= *acceptance_radius_m).then(End::nominal)
            }
            // No storage information after the capture: report with the level known.
            (Binding::TakePicture { .. }, Phase::Stored(at))
                if ctx.vnow.saturating_sub(at) > STORAGE_WAIT_MS =>
            {
                self.pending.take()
            }
            (Binding::TakePicture { .. }, Phase::Stored(_)) => None,
            (Binding::TakePicture { timeout_ms, .. }, _)
                if ctx.vnow.saturating_sub(self.started_ms) > *timeout_ms =>
            {
                Some(self.failed(
                    ctx,
                    format!(
                        "no capture confirmed (CAMERA_IMAGE_CAPTURED, CAMERA_FEEDBACK) within {timeout_ms} ms"
                    ),
                ))
            }
            (Binding::TakePicture { .. }, _) => {
                if self.capture.as_mut().is_some_and(|e| e.poll_due(ctx.vnow)) {
                    ctx.request_capture_status();
                }
                None
            }
            (Binding::Sample { steps }, Phase::Holding(i, until)) if ctx.vnow >= until => {
                if i + 1 == steps.len() {
                    Some(End::nominal())
                } else {
                    let s = steps[i + 1];
                    self.servo(ctx, i + 1, s.servo, s.pwm);
                    None
                }
            }
            // The link slot is over, whether the downlink's final ACK came or not.
            (
                Binding::Download {
                    max_ms: Some(m), ..
                },
                _,
            ) if ctx.vnow.saturating_sub(self.started_ms) >= *m => {
                self.stop_downlink(ctx);
                Some(End::nominal())
            }
            (Binding::Timed { duration_ms }, Phase::Running) => {
                (ctx.vnow.saturating_sub(self.started_ms) >= *duration_ms).then(End::nominal)
            }
            (Binding::Recharge { .. }, Phase::Running) => {
                (ctx.tel.battery_percent? >= self.target_level).then(End::nominal)
            }
            (
                Binding::Download {
                    until_used,
                    poll_ms,
                    ..
                },
                Phase::Running,
            ) => {
                if ctx.tel.storage_used.is_some_and(|u| u <= *until_used) {
                    return Some(End::nominal());
                }

                if ctx.vnow.saturating_sub(self.last_poll) >= *poll_ms {
                    self.last_poll = ctx.vnow;
                    ctx.request_storage();
                }
                None
            }
            _ => None,
        }
    }

    /// A downlink is stopped by its command with p1 = 0 (nothing for other bindings).
    fn stop_downlink(&self, ctx: &mut Ctx) {
        if let Binding::Download { command, .. } = self.binding {
            if let Some(cmd) = num_traits::FromPrimitive::from_u16(command) {
                ctx.cmds.send(
                    u64::MAX,
                    Command::long(cmd, ctx.target, [0.0; 7]),
                    ctx.now,
                    ctx.out,
                );
            }
        }
    }

    fn is_motion(&self) -> bool {
        matches!(
            self.binding,
            Binding::Move { .. }
                | Binding::Survey { .. }
                | Binding::ReturnHome { .. }
                | Binding::Recharge { .. }
        )
    }

    /// The operator took control (`why`): the run ends where the vehicle is, with no command. A motion is
    /// interrupted at the position reached (as a stopped move); another action did not do its work
    /// (failed).
    pub fn yield_control(&mut self, ctx: &mut Ctx, why: &str) -> End {
        if let Some(end) = self.settled(ctx) {
            return end;
        }
        ctx.cmds.cancel(self.id);
        if self.is_vehicle_motion() {
            End {
                status: ReportStatus::Interrupted,
                reason: Some(format!("the operator took control: {why}")),
                state: self.state_values(ctx, false),
            }
        } else {
            self.failed(ctx, format!("the operator took control: {why}"))
        }
    }

    /// `END i_a`: stops the action; motion is stopped by HOLD, a downlink by its command with p1 = 0.
    /// The report is `Interrupted` with the state.
    pub fn stop(&mut self, ctx: &mut Ctx) -> End {
        if let Some(end) = self.settled(ctx) {
            // It had failed already: that is its report.
            return end;
        }
        ctx.cmds.cancel(self.id);
        self.stop_downlink(ctx);
        if self.is_vehicle_motion() {
            let hold = ctx.cfg.modes.hold;
            // The HOLD's ACK is nobody's business once the action ended: owner u64::MAX.
            let (p2, p3) = hold.set_mode_params();
            let cmd = Command::long(
                MavCmd::MAV_CMD_DO_SET_MODE,
                ctx.target,
                [1.0, p2, p3, 0.0, 0.0, 0.0, 0.0],
            );
            ctx.cmds.send(u64::MAX, cmd, ctx.now, ctx.out);
        }
        End {
            status: ReportStatus::Interrupted,
            reason: Some("stopped (END)".into()),
            // An interrupted preemptive motion ended as preempted (its end effects hold): no moving value.
            state: self.state_values(ctx, false),
        }
    }
}

/// ArduPilot: a motion's ground speed by DO_CHANGE_SPEED (speed type 1), once the destination is set
/// (nothing on PX4, which takes the speed with the destination, or for the autopilot's own speed).
pub(crate) fn change_speed(ctx: &mut Ctx, id: VehicleActionId, speed_m_s: f64) {
    if ctx.cfg.autopilot == Autopilot::Ardupilot && speed_m_s > 0.0 {
        let cmd = Command::long(
            MavCmd::MAV_CMD_DO_CHANGE_SPEED,
            ctx.target,
            [1.0, speed_m_s as f32, -1.0, 0.0, 0.0, 0.0, 0.0],
        );
        ctx.command(id, cmd);
    }
}

/// The downlink's start: its command with p1 = 1.
fn start_download(ctx: &mut Ctx, id: VehicleActionId, command: u16) -> Result<(), StartError> {
    let Some(cmd) = num_traits::FromPrimitive::from_u16(command) else {
        return Err(StartError::UnknownCommand(command));
    };
    ctx.command(
        id,
        Command::long(cmd, ctx.target, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]),
    );
    Ok(())
}

pub(crate) fn result_name(r: MavResult) -> &'static str {
    match r {
        MavResult::MAV_RESULT_DENIED => "DENIED",
        MavResult::MAV_RESULT_FAILED => "FAILED",
        MavResult::MAV_RESULT_UNSUPPORTED => "UNSUPPORTED",
        MavResult::MAV_RESULT_TEMPORARILY_REJECTED => "TEMPORARILY_REJECTED",
        MavResult::MAV_RESULT_CANCELLED => "CANCELLED",
        MavResult::MAV_RESULT_COMMAND_INT_ONLY => "COMMAND_INT_ONLY",
        MavResult::MAV_RESULT_COMMAND_LONG_ONLY => "COMMAND_LONG_ONLY",
        MavResult::MAV_RESULT_COMMAND_UNSUPPORTED_MAV_FRAME => "UNSUPPORTED_MAV_FRAME",
        _ => "refused",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_survey_mission_has_a_home_placeholder_on_ardupilot_only() {
        let home = super::super::geo::Home {
            lat: -35.363261,
            lon: 149.16523,
            alt: 584.0,
        };
        let ap = survey_head(Autopilot::Ardupilot, &home);
        assert_eq!(ap.len(), 1);
        assert_eq!((ap[0].x, ap[0].y), (home.lat, home.lon));
        assert!(survey_head(Autopilot::Px4, &home).is_empty());
    }
}
