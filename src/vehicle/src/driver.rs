//! The companion's protocol core, free of I/O: fed with the autopilot's messages and the passage of time, it
//! runs the action bindings, the command and mission clients, telemetry and link supervision, and yields
//! messages to send and events for the executive. The socket layer ([`super::link`]) and tests drive it alike.

use std::collections::BTreeMap;

use mavlink::dialects::ardupilotmega::{
    MavAutopilot, MavCmd, MavMessage, MavModeFlag, MavResult, MavSeverity, MavState, MavType,
    COMMAND_ACK_DATA, HEARTBEAT_DATA,
};
use mavlink::MavHeader;

use super::actions::{Ctx, End, Run};
use super::api::VehicleError;
use super::api::VehicleEvent;
use super::authority::{self, Authority, AuthorityEvent, Change};
use super::commands::{Command, CommandClient, CommandOutcome, Token};
use super::config::{Autopilot, VehicleConfig};
use super::fence::{AutopilotFence, FenceRead};
use super::mission_client::MissionClient;
use super::readiness::{Readiness, ReadyAction, Seen};
use super::safe_stop::{OnShutdown, SafeStop, SafeStopOutcome};
use super::telemetry::Telemetry;
use super::types::{ActionReport, ActionStart, LinkStatus, VehicleActionId};

/// The context of an action run: borrows the driver's parts beside `runs` (a macro, as a method would
/// borrow all of `self`).
macro_rules! ctx {
    ($d:ident, $now:expr) => {
        Ctx {
            now: $now,
            vnow: $d.tel.time_boot_ms.unwrap_or($now),
            cfg: &$d.cfg,
            tel: &$d.tel,
            cmds: &mut $d.cmds,
            mission: &mut $d.mission,
            out: &mut $d.out,
            target: $d.target.unwrap_or(($d.system_id, 1)),
        }
    };
}

/// `MAV_COMP_ID_ONBOARD_COMPUTER`.
pub const COMPANION_COMPONENT: u8 = 191;

/// The owner of the safe stop's mode command (action ids are small; `u64::MAX` is "nobody").
const SAFE_STOP_TOKEN: Token = u64::MAX - 1;
/// The owner of the readiness wait's ARM commands.
const READY_TOKEN: Token = u64::MAX - 2;
/// The owner of the fence list's download at readiness.
const FENCE_TOKEN: Token = u64::MAX - 3;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Link {
    Waiting,
    Up,
    Lost,
}

pub struct Driver {
    cfg: VehicleConfig,
    /// Our system id: the autopilot's once its heartbeat is seen.
    pub system_id: u8,
    target: Option<(u8, u8)>,
    tel: Telemetry,
    cmds: CommandClient,
    mission: MissionClient,
    runs: BTreeMap<VehicleActionId, Run>,
    out: Vec<MavMessage>,
    events: Vec<VehicleEvent>,
    link: Link,
    last_heartbeat_rx: u64,
    last_heartbeat_tx: Option<u64>,
    safe_stop: Option<SafeStop>,
    readiness: Option<Readiness>,
    /// The autopilot's fence, read at readiness (`[limits] autopilot_fence`); whether its list was asked.
    fence_read: Option<(FenceRead, bool)>,
    /// Who commands the vehicle: while the operator has it, no command goes out.
    authority: Authority,
    /// Messages before this index in `out` were produced before the pause began.
    pause_mark: Option<usize>,
}

/// The HEARTBEAT of the companion.
pub fn companion_heartbeat() -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: 0,
        mavtype: MavType::MAV_TYPE_ONBOARD_CONTROLLER,
        autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
        base_mode: MavModeFlag::empty(),
        system_status: MavState::MAV_STATE_ACTIVE,
        mavlink_version: 3,
    })
}

impl Driver {
    pub fn new(cfg: VehicleConfig) -> Self {
        let cmds = CommandClient::new(cfg.link.command_ack_timeout_ms, cfg.link.command_retries);
        let mission = MissionClient::new(
            (1, 1),
            cfg.link.mission_timeout_ms,
            cfg.link.mission_retries,
        );
        let authority = Authority::new(cfg.authority, &cfg.modes);
        Self {
            cfg,
            authority,
            pause_mark: None,
            system_id: 1,
            target: None,
            tel: Telemetry::default(),
            cmds,
            mission,
            runs: BTreeMap::new(),
            out: Vec::new(),
            events: Vec::new(),
            link: Link::Waiting,
            last_heartbeat_rx: 0,
            last_heartbeat_tx: None,
            safe_stop: None,
            readiness: None,
            fence_read: None,
        }
    }

    pub fn config(&self) -> &VehicleConfig {
        &self.cfg
    }

    pub fn telemetry(&self) -> &Telemetry {
        &self.tel
    }

    pub fn target(&self) -> Option<(u8, u8)> {
        self.target
    }

    pub fn running(&self) -> impl Iterator<Item = &VehicleActionId> {
        self.runs.keys()
    }

    /// Messages produced and not yet taken by the link.
    pub fn outgoing_len(&self) -> usize {
        self.out.len()
    }

    /// The messages to send. The modes they command are what the companion expects to see; while it
    /// yields, whatever would command the vehicle is held back (a retry of a command from before).
    pub fn take_outgoing(&mut self) -> Vec<MavMessage> {
        let mut out = std::mem::take(&mut self.out);
        let mark = self.pause_mark.take().unwrap_or(0).min(out.len());
        if self.authority.is_paused() {
            let before = out.len();
            let mut i = 0;
            out.retain(|m| {
                i += 1;
                i <= mark || authority::allowed_while_paused(m)
            });
            if out.len() < before {
                tracing::warn!(
                    held = before - out.len(),
                    "the operator has the vehicle: commands not sent"
                );
            }
        }
        for m in &out {
            if let Some(mode) = authority::commanded_mode(m, &self.cfg.modes, self.cfg.autopilot) {
                self.authority.commanded(mode);
            }
        }
        out
    }

    /// Whether the companion yields to the operator (a foreign mode, a disarm, a pause asked).
    pub fn is_paused(&self) -> bool {
        self.authority.is_paused()
    }

    /// A change of who commands the vehicle: on a pause the running actions end where the vehicle is,
    /// with no command (a motion as interrupted, the others as failed); the operator is told by STATUSTEXT,
    /// the executive by an event.
    fn authority_changed(&mut self, change: Change, now: u64) {
        match change {
            Change::Paused { why } => {
                let ids: Vec<VehicleActionId> = self.runs.keys().copied().collect();
                for id in ids {
                    let why = why.clone();
                    self.with_run(id, now, |run, ctx| Some(run.yield_control(ctx, &why)));
                }
                // What was produced before the pause (a HOLD the operator asked for) still goes out.
                self.pause_mark.get_or_insert(self.out.len());
                let guided = super::mode_names::mode_name(
                    self.cfg.modes.guided.custom_mode(),
                    self.tel.vehicle_type,
                );
                let text = format!("mavtempo paused: {why}; {guided} or continue resumes");
                tracing::warn!("{text}");
                self.tell(&text, MavSeverity::MAV_SEVERITY_WARNING);
                self.events
                    .push(VehicleEvent::Authority(AuthorityEvent::Paused { why }));
            }
            Change::Resumed { how } => {
                let text = format!("mavtempo resumes: {how}");
                tracing::info!("{text}");
                self.tell(&text, MavSeverity::MAV_SEVERITY_NOTICE);
                self.events
                    .push(VehicleEvent::Authority(AuthorityEvent::Resumed {
                        how,
                        position: self.tel.position,
                        radius_m: authority::start_radius_m(&self.cfg),
                    }));
            }
        }
    }

    /// A STATUSTEXT for the ground stations.
    fn tell(&mut self, text: &str, severity: MavSeverity) {
        self.out
            .extend(super::intake::statustext(text, severity, 0));
    }

    /// A ground station's `MAV_CMD_DO_PAUSE_CONTINUE` to component 191 (p1 = 1: continue, 0: pause):
    /// applied, and its COMMAND_ACK returned (for the link the command came in on).
    pub fn operator_command(
        &mut self,
        header: MavHeader,
        msg: &MavMessage,
        now: u64,
    ) -> Option<MavMessage> {
        let MavMessage::COMMAND_LONG(c) = msg else {
            return None;
        };
        if c.command != MavCmd::MAV_CMD_DO_PAUSE_CONTINUE
            || c.target_component != COMPANION_COMPONENT
            || (c.target_system != 0 && c.target_system != self.system_id)
        {
            return None;
        }
        let result = match self.authority.on_pause_continue(c.param1 >= 0.5) {
            Ok(change) => {
                if let Some(change) = change {
                    if matches!(change, Change::Paused { .. }) {
                        // A pause asked: the vehicle is stopped (HOLD) before the companion yields.
                        self.stop_all_motion(now);
                    }
                    self.authority_changed(change, now);
                }
                MavResult::MAV_RESULT_ACCEPTED
            }
            Err(why) => {
                tracing::warn!("continue refused: {why}");
                MavResult::MAV_RESULT_TEMPORARILY_REJECTED
            }
        };
        Some(MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
            command: c.command,
            result,
            target_system: header.system_id as u8,
            target_component: header.component_id,
            ..Default::default()
        }))
    }

    /// `END` to every running motion (HOLD is commanded): a pause asked by the operator.
    fn stop_all_motion(&mut self, now: u64) {
        let ids: Vec<VehicleActionId> = self.runs.keys().copied().collect();
        for id in ids {
            self.with_run(id, now, |run, ctx| Some(run.stop(ctx)));
        }
    }

    /// The mission is over: the companion leaves the vehicle as `[authority] at_end` says (HOLD, then
    /// disarm once held) and lets go of it.
    pub fn end_of_mission(&mut self, now: u64) {
        self.authority.release();
        let at_end = self.cfg.authority.at_end;
        if at_end == authority::AtEnd::None || self.authority.is_paused() {
            return;
        }
        let Some(target) = self.target else {
            return;
        };
        let (p2, p3) = self.cfg.modes.hold.set_mode_params();
        let hold = Command::long(
            MavCmd::MAV_CMD_DO_SET_MODE,
            target,
            [1.0, p2, p3, 0.0, 0.0, 0.0, 0.0],
        );
        self.cmds.send(u64::MAX, hold, now, &mut self.out);
        if at_end == authority::AtEnd::HoldDisarm {
            let disarm = Command::long(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, target, [0.0; 7]);
            self.cmds.send(u64::MAX, disarm, now, &mut self.out);
        }
        tracing::info!(?at_end, "mission over: the vehicle left in HOLD");
    }

    pub fn take_events(&mut self) -> Vec<VehicleEvent> {
        std::mem::take(&mut self.events)
    }

    fn report(&mut self, id: VehicleActionId, end: End) {
        self.cmds.cancel(id);
        let run = self.runs.remove(&id);
        tracing::info!(id, task = run.as_ref().map(|r| r.task.as_str()), status = %end.status, reason = ?end.reason, "action report");
        self.events.push(VehicleEvent::Report(ActionReport {
            id,
            status: end.status,
            time_ms: self.tel.time_boot_ms.unwrap_or(0),
            resources: self.tel.levels(&self.cfg.resources),
            state: end.state,
            reason: end.reason,
        }));
    }

    /// Runs `f` on one run with a context; a returned end becomes its report.
    fn with_run(
        &mut self,
        id: VehicleActionId,
        now: u64,
        f: impl FnOnce(&mut Run, &mut Ctx) -> Option<End>,
    ) {
        let Some(run) = self.runs.get_mut(&id) else {
            return;
        };
        let mut ctx = ctx!(self, now);
        let end = f(run, &mut ctx).and_then(|end| run.settle(&mut ctx, end));
        if let Some(end) = end {
            self.report(id, end);
        }
    }

    /// `START a p_a i_a`.
    pub fn start(&mut self, action: ActionStart, now: u64) -> Result<(), VehicleError> {
        if self.runs.contains_key(&action.id) {
            return Err(VehicleError::AlreadyRunning(action.id));
        }
        if self.authority.is_paused() {
            return Err(VehicleError::Yielded);
        }
        let binding = self
            .cfg
            .actions
            .get(&action.task)
            .ok_or_else(|| VehicleError::UnknownTask(action.task.clone()))?
            .clone();
        let mut ctx = ctx!(self, now);
        let run = Run::begin(&action, &binding, &mut ctx).map_err(|reason| {
            VehicleError::BadArguments {
                task: action.task.clone(),
                reason: reason.to_string(),
            }
        })?;
        tracing::info!(id = action.id, task = %action.task, "action started");
        self.runs.insert(action.id, run);
        Ok(())
    }

    /// [`Self::start`] of a motion that ends only once the vehicle is still, too (the next action needs it
    /// still: [`super::api::Vehicle::start_still`]).
    pub fn start_still(&mut self, action: ActionStart, now: u64) -> Result<(), VehicleError> {
        let id = action.id;
        self.start(action, now)?;
        if let Some(run) = self.runs.get_mut(&id) {
            run.end_still = true;
        }
        Ok(())
    }

    /// `END i_a`.
    pub fn stop(&mut self, id: VehicleActionId, now: u64) -> Result<(), VehicleError> {
        if !self.runs.contains_key(&id) {
            return Err(VehicleError::NotRunning(id));
        }
        self.with_run(id, now, |run, ctx| Some(run.stop(ctx)));
        Ok(())
    }

    /// The companion is stopping: unless `modes.on_shutdown` is `none`, every running action is ended as
    /// `END` ends it and the configured mode (HOLD or RTL) is commanded; [`Driver::safe_stop`] follows it.
    pub fn begin_safe_stop(&mut self, now: u64) {
        let action = self.cfg.modes.on_shutdown;
        let mode = match action {
            OnShutdown::None => {
                self.safe_stop = Some(SafeStop::settled(action, SafeStopOutcome::LeftAsIs));
                return;
            }
            OnShutdown::Hold => self.cfg.modes.hold,
            OnShutdown::Rtl => self.cfg.modes.rtl,
        };
        let Some(target) = self.target else {
            self.safe_stop = Some(SafeStop::settled(action, SafeStopOutcome::NoVehicle));
            return;
        };
        let mut stopped = Vec::new();
        let ids: Vec<VehicleActionId> = self.runs.keys().copied().collect();
        for id in ids {
            if let Some(run) = self.runs.get(&id) {
                stopped.push(run.task.clone());
            }
            self.with_run(id, now, |run, ctx| Some(run.stop(ctx)));
        }
        tracing::warn!(?action, ?stopped, "shutdown: vehicle to its safe mode");
        let (p2, p3) = mode.set_mode_params();
        let cmd = Command::long(
            MavCmd::MAV_CMD_DO_SET_MODE,
            target,
            [1.0, p2, p3, 0.0, 0.0, 0.0, 0.0],
        );
        self.cmds.send(SAFE_STOP_TOKEN, cmd, now, &mut self.out);
        self.safe_stop = Some(SafeStop::commanding(action, mode, stopped));
    }

    /// The safe stop, once begun.
    pub fn safe_stop(&self) -> Option<&SafeStop> {
        self.safe_stop.as_ref()
    }

    /// How long a safe stop may wait for its confirmation: the command's retries, then two seconds for a
    /// HEARTBEAT in the mode.
    pub fn safe_stop_bound_ms(&self) -> u64 {
        let link = &self.cfg.link;
        link.command_ack_timeout_ms
            .saturating_mul(u64::from(link.command_retries) + 1)
            .saturating_add(2_000)
    }

    /// Starts waiting for the autopilot to be ready (a position fix, then arming accepted, ARM retried with
    /// a backoff); [`Driver::readiness`] tells how it goes.
    pub fn begin_ready(&mut self, now: u64) {
        let vnow = self.tel.time_boot_ms.unwrap_or(now);
        let r = Readiness::new(vnow);
        self.readiness = Some(match self.cfg.authority.arm {
            authority::Arming::Operator => r.operator_arms(),
            authority::Arming::Companion if !self.cfg.ready.arm => r.fix_only(),
            authority::Arming::Companion => r,
        });
        if self.cfg.limits.autopilot_fence != Some(false) {
            self.fence_read = Some((FenceRead::new(), false));
        }
        self.drive_readiness(now);
    }

    pub fn readiness(&self) -> Option<&Readiness> {
        self.readiness.as_ref()
    }

    /// The autopilot's fence once read, with its home (`None` while reading, or when not read at all).
    pub fn autopilot_fence(&self) -> Option<AutopilotFence> {
        self.fence_read
            .as_ref()
            .filter(|(f, _)| f.done())
            .map(|(f, _)| AutopilotFence {
                home: self.tel.home_position,
                ..f.fence().clone()
            })
    }

    /// Whether the fence reading started at readiness is over (true when there is none).
    pub fn fence_read_done(&self) -> bool {
        self.fence_read.as_ref().is_none_or(|(f, _)| f.done())
    }

    /// The fence list asked for once the autopilot is known; its parameters (re-)asked when due.
    fn drive_fence_read(&mut self, now: u64) {
        let (Some(target), Some((read, asked))) = (self.target, &mut self.fence_read) else {
            return;
        };
        let vnow = self.tel.time_boot_ms.unwrap_or(now);
        if !*asked {
            *asked = self.mission.download_of(
                mavlink::dialects::ardupilotmega::MavMissionType::MAV_MISSION_TYPE_FENCE,
                FENCE_TOKEN,
                now,
                &mut self.out,
            );
        }
        read.tick(vnow, target, &mut self.out);
    }

    /// A mission transfer ended: the fence list's, or an action's.
    fn mission_outcome(
        &mut self,
        token: Token,
        outcome: super::mission_client::MissionOutcome,
        now: u64,
    ) {
        use super::mission_client::MissionOutcome;
        if token == FENCE_TOKEN {
            if let Some((read, _)) = &mut self.fence_read {
                read.on_list(match outcome {
                    MissionOutcome::Downloaded(items) => Ok(items),
                    MissionOutcome::Failed(why) => Err(why),
                    _ => Ok(Vec::new()),
                });
            }
            return;
        }
        self.with_run(token, now, |run, ctx| run.on_mission(ctx, outcome));
    }

    fn drive_readiness(&mut self, now: u64) {
        self.drive_fence_read(now);
        let Some(r) = &mut self.readiness else {
            return;
        };
        let vnow = self.tel.time_boot_ms.unwrap_or(now);
        let seen = Seen {
            position: self.tel.position.is_some(),
            home: self.tel.home_known,
            armed: self.tel.armed,
            navigation: self.tel.navigation_ok,
            prearm: match self.cfg.autopilot {
                Autopilot::Px4 => self.tel.prearm_ok,
                Autopilot::Ardupilot => None,
            },
        };
        let target = self.target.unwrap_or((self.system_id, 1));
        match r.tick(vnow, seen) {
            ReadyAction::Arm => {
                let cmd = Command::long(
                    MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
                    target,
                    [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                );
                self.cmds.send(READY_TOKEN, cmd, now, &mut self.out);
            }
            ReadyAction::RequestStatus => {
                // Fire and forget: HOME_POSITION comes once home is set (before, ArduPilot sends
                // nothing); EKF_STATUS_REPORT only from ArduPilot (PX4 denies it: px4.rs).
                for id in super::px4::status_requests(self.cfg.autopilot) {
                    let cmd = Command::long(
                        MavCmd::MAV_CMD_REQUEST_MESSAGE,
                        target,
                        [f32::from(*id), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                    );
                    self.cmds.send(u64::MAX, cmd, now, &mut self.out);
                }
            }
            ReadyAction::AskOperator => {
                let text = "mavtempo ready: waiting for the operator to arm";
                tracing::warn!("{text} ([authority] arm = \"operator\")");
                self.tell(text, MavSeverity::MAV_SEVERITY_NOTICE);
            }
            ReadyAction::Nothing => {}
        }
    }

    fn command_outcome(&mut self, token: Token, cmd: MavCmd, outcome: CommandOutcome, now: u64) {
        if token == READY_TOKEN {
            let vnow = self.tel.time_boot_ms.unwrap_or(now);
            if let Some(r) = &mut self.readiness {
                r.on_arm(vnow, outcome, self.tel.armed);
            }
            return;
        }
        if token == SAFE_STOP_TOKEN {
            if let Some(s) = &mut self.safe_stop {
                s.on_ack(outcome);
            }
            return;
        }
        self.with_run(token, now, |run, ctx| run.on_command(ctx, cmd, outcome));
    }

    /// A message received from the link.
    pub fn handle(&mut self, header: MavHeader, msg: &MavMessage, now: u64) {
        let (sys, comp) = (header.system_id as u8, header.component_id);
        if let MavMessage::HEARTBEAT(h) = msg {
            let is_autopilot = h.autopilot != MavAutopilot::MAV_AUTOPILOT_INVALID
                && !matches!(
                    h.mavtype,
                    MavType::MAV_TYPE_GCS | MavType::MAV_TYPE_ONBOARD_CONTROLLER
                );
            if is_autopilot && self.target.is_none() {
                // Adopt the system id of the first autopilot seen.
                self.target = Some((sys, comp));
                self.system_id = sys;
                self.mission.target = (sys, comp);
                tracing::info!(system_id = sys, component = comp, "autopilot found");
            }
            if self.target == Some((sys, comp)) {
                self.last_heartbeat_rx = now;
                match self.link {
                    Link::Waiting => self
                        .events
                        .push(VehicleEvent::Link(LinkStatus::Up { system_id: sys })),
                    Link::Lost => self.events.push(VehicleEvent::Link(LinkStatus::Recovered)),
                    Link::Up => {}
                }
                self.link = Link::Up;
            }
        }
        if self.target != Some((sys, comp)) {
            if let Some(ack) = self.operator_command(header, msg, now) {
                self.out.push(ack);
            }
            return;
        }
        let cfg = &self.cfg;
        self.tel
            .update(msg, &cfg.home, &cfg.resources, &mut self.events);
        if let Some(t) = self.tel.time_boot_ms {
            self.cmds.set_vehicle_time(t);
            self.mission.set_vehicle_time(t);
        }
        if self.tel.take_restart() {
            if let Some(change) = self.authority.on_restart() {
                self.authority_changed(change, now);
            }
            self.resume_after_restart(now);
        }
        if let MavMessage::HEARTBEAT(h) = msg {
            let armed = h
                .base_mode
                .contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED);
            let vnow = self.tel.time_boot_ms.unwrap_or(now);
            self.authority.set_vehicle_type(h.mavtype);
            if let Some(change) = self.authority.on_heartbeat(h.custom_mode, armed, vnow) {
                self.authority_changed(change, now);
            }
        }
        if matches!(
            msg,
            MavMessage::SYSTEM_TIME(_) | MavMessage::GLOBAL_POSITION_INT(_)
        ) {
            // The vehicle's clock moved: ACKs and mission answers overdue in its time are re-sent now, not
            // at the next wall tick (a simulator may run minutes between two).
            self.expire_commands(now);
            self.expire_mission(now);
        }
        if let (Some(s), MavMessage::HEARTBEAT(h)) = (&mut self.safe_stop, msg) {
            s.on_heartbeat(h.custom_mode);
        }
        if let MavMessage::STATUSTEXT(t) = msg {
            if (t.severity as u8) <= 3 {
                self.authority
                    .on_error_text(self.tel.time_boot_ms.unwrap_or(now));
            }
        }
        if let (Some(r), MavMessage::STATUSTEXT(t)) = (&mut self.readiness, msg) {
            // WARNING or worse: ArduPilot's "PreArm: ..." and "Arm: ..." reasons are CRITICAL.
            if (t.severity as u8) <= 4 {
                r.on_text(t.text.to_str().unwrap_or("").trim_end_matches('\0'));
            }
        }
        if let MavMessage::COMMAND_ACK(ack) = msg {
            if let Some((token, cmd, outcome)) = self.cmds.on_ack(ack, now) {
                self.command_outcome(token, cmd, outcome, now);
            }
        }
        if let Some((read, _)) = &mut self.fence_read {
            read.on_message(msg);
        }
        if let Some((token, outcome)) = self.mission.handle(msg, now, &mut self.out) {
            self.mission_outcome(token, outcome, now);
        }
        self.authority_tick(now);
        let ids: Vec<VehicleActionId> = self.runs.keys().copied().collect();
        for id in ids {
            self.with_run(id, now, |run, ctx| run.on_message(ctx, msg));
            self.with_run(id, now, |run, ctx| run.on_tick(ctx));
        }
        self.drive_readiness(now);
    }

    /// The autopilot restarted: it forgot what it was doing (disarmed, in its boot mode). Each running action
    /// is commanded again from where the vehicle is — armed, put back in its mode, its move, capture or
    /// downlink re-sent — as many times as `restart_resumes` allows, then it fails with the restart as reason.
    fn resume_after_restart(&mut self, now: u64) {
        tracing::warn!(
            running = self.runs.len(),
            "autopilot restarted: resuming the running actions"
        );
        self.events.push(VehicleEvent::Link(LinkStatus::Restarted));
        let ids: Vec<VehicleActionId> = self.runs.keys().copied().collect();
        for id in ids {
            self.with_run(id, now, |run, ctx| run.resume(ctx));
        }
    }

    /// Re-sends the mission message whose answer is overdue; a transfer given up on ends its run.
    fn expire_mission(&mut self, now: u64) {
        if let Some((token, outcome)) = self.mission.tick(now, &mut self.out) {
            self.mission_outcome(token, outcome, now);
        }
    }

    /// Re-sends the commands whose ACK is overdue; those given up on end their runs.
    fn expire_commands(&mut self, now: u64) {
        for (token, cmd, outcome) in self.cmds.tick(now, &mut self.out) {
            self.command_outcome(token, cmd, outcome, now);
        }
    }

    /// The transport closed (TCP reset, serial unplugged).
    pub fn transport_lost(&mut self) {
        if self.link == Link::Up {
            self.link = Link::Lost;
            self.events.push(VehicleEvent::Link(LinkStatus::Lost));
        }
    }

    /// Time passed: heartbeats out, link supervision, timeouts, state-based ends.
    pub fn tick(&mut self, now: u64) {
        if self
            .last_heartbeat_tx
            .is_none_or(|t| now.saturating_sub(t) >= 1000)
        {
            self.last_heartbeat_tx = Some(now);
            self.out.push(companion_heartbeat());
        }
        if self.link == Link::Up
            && now.saturating_sub(self.last_heartbeat_rx) > self.cfg.link.heartbeat_timeout_ms
        {
            tracing::warn!(
                "no autopilot heartbeat for {} ms: link lost",
                self.cfg.link.heartbeat_timeout_ms
            );
            self.link = Link::Lost;
            self.events.push(VehicleEvent::Link(LinkStatus::Lost));
        }
        self.expire_commands(now);
        self.expire_mission(now);
        self.authority_tick(now);
        let ids: Vec<VehicleActionId> = self.runs.keys().copied().collect();
        for id in ids {
            self.with_run(id, now, |run, ctx| run.on_tick(ctx));
        }
        self.drive_readiness(now);
    }

    /// A disarm no restart explained, past its grace: the operator's.
    fn authority_tick(&mut self, now: u64) {
        let vnow = self.tel.time_boot_ms.unwrap_or(now);
        if let Some(change) = self.authority.on_tick(vnow) {
            self.authority_changed(change, now);
        }
    }
}
