//! COMMAND_LONG / COMMAND_INT handling with ArduPilot's COMMAND_ACK results.

use mavlink::dialects::ardupilotmega::*;

use super::command_memory::Answer;
use super::telemetry::{self, data_stream_ids};
use super::{Autopilot, Mode, Sender};
use crate::physics::Target;
use crate::scenario::{CameraBackend, EventKind};

/// `MAV_CMD_COMPONENT_ARM_DISARM` param2 values that skip the arming checks (ArduPilot's
/// `magic_force_arm_value` and `magic_force_arm_disarm_value`).
const FORCE_ARM: [f32; 2] = [2989.0, 21196.0];

/// AR_WPNav::set_speed_max refuses anything slower.
const WPNAV_SPEED_MIN: f64 = 0.05;

/// A command from either message, positions kept as integers when they came as COMMAND_INT.
#[derive(Debug, Clone)]
pub struct Cmd {
    pub from: Sender,
    pub command: MavCmd,
    pub p: [f32; 7],
    /// COMMAND_INT x / y (degrees ×1e7) and frame; None for COMMAND_LONG.
    pub int: Option<(i32, i32, MavFrame)>,
    /// The frame's sequence number (a duplicate on the link has the same).
    pub seq: u8,
    /// COMMAND_LONG's re-send count (0 for COMMAND_INT).
    pub confirmation: u8,
}

impl Cmd {
    pub fn from_long(from: Sender, seq: u8, m: &COMMAND_LONG_DATA) -> Self {
        Self {
            from,
            seq,
            confirmation: m.confirmation,
            command: m.command,
            p: [
                m.param1, m.param2, m.param3, m.param4, m.param5, m.param6, m.param7,
            ],
            int: None,
        }
    }

    pub fn from_int(from: Sender, seq: u8, m: &COMMAND_INT_DATA) -> Self {
        Self {
            from,
            seq,
            confirmation: 0,
            command: m.command,
            p: [
                m.param1, m.param2, m.param3, m.param4, m.x as f32, m.y as f32, m.z,
            ],
            int: Some((m.x, m.y, m.frame)),
        }
    }
}

impl Autopilot {
    pub(super) fn ack(&mut self, c: &Cmd, result: MavResult, progress: u8) {
        self.ack_to(c.from, c.command, result, progress);
    }

    pub(super) fn ack_to(&mut self, to: Sender, command: MavCmd, result: MavResult, progress: u8) {
        self.cmd_memory
            .answered(to.sysid, to.compid, command, Answer { result, progress });
        self.send_to(
            to.peer,
            MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
                command,
                result,
                progress,
                result_param2: 0,
                target_system: to.sysid,
                target_component: to.compid,
            }),
        );
    }

    pub(super) fn on_command(&mut self, c: Cmd) {
        if !matches!(
            c.command,
            MavCmd::MAV_CMD_REQUEST_MESSAGE | MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL
        ) {
            self.control_commands += 1;
        }
        if c.command == MavCmd::MAV_CMD_COMPONENT_ARM_DISARM && c.p[0] >= 0.5 {
            self.arm_commands += 1;
        }
        if let Some(a) = self.cmd_memory.repeat(&c, self.now_ms) {
            // A duplicate or a re-sent copy of what was done: answered again, not done twice.
            self.ack(&c, a.result, a.progress);
            return;
        }
        if let Some(r) = self.px4_refusal(&c) {
            self.ack(&c, r, 0);
            return;
        }
        let id = c.command as u32;
        self.emit_event(EventKind::Command, i64::from(id));
        if let Some(i) = self
            .command_failures
            .iter()
            .position(|(cmd, _, n)| u32::from(*cmd) == id && *n > 0)
        {
            let result = self.command_failures[i].1;
            self.command_failures[i].2 -= 1;
            if self.command_failures[i].2 == 0 {
                self.command_failures.remove(i);
            }
            self.text(
                MavSeverity::MAV_SEVERITY_WARNING,
                &format!("Command {id} refused (injected fault)"),
            );
            self.ack(&c, result, 0);
            return;
        }
        let result = match c.command {
            MavCmd::MAV_CMD_DO_SET_MODE => {
                // p1 must carry MAV_MODE_FLAG_CUSTOM_MODE_ENABLED; p2 is the custom mode.
                match self.mode_from_command(c.p[1], c.p[2]) {
                    Some(m) if (c.p[0] as u32) & 1 == 1 => self.set_mode_result(m),
                    _ => MavResult::MAV_RESULT_FAILED,
                }
            }
            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM => {
                if c.p[0] >= 0.5 {
                    match self.arm(FORCE_ARM.contains(&c.p[1])) {
                        Ok(()) => MavResult::MAV_RESULT_ACCEPTED,
                        Err(reasons) => {
                            for reason in reasons {
                                self.text(MavSeverity::MAV_SEVERITY_CRITICAL, &reason);
                            }
                            self.refused_result()
                        }
                    }
                } else {
                    self.disarm();
                    MavResult::MAV_RESULT_ACCEPTED
                }
            }
            MavCmd::MAV_CMD_MISSION_START => {
                if self.mission_items() == 0 {
                    self.text(
                        MavSeverity::MAV_SEVERITY_NOTICE,
                        "No Mission. Can't set AUTO.",
                    );
                    MavResult::MAV_RESULT_FAILED
                } else {
                    let r = self.set_mode_result(Mode::Auto);
                    if r == MavResult::MAV_RESULT_ACCEPTED && self.armed && !self.exec.started {
                        self.start_mission();
                    }
                    r
                }
            }
            MavCmd::MAV_CMD_DO_SET_MISSION_CURRENT => self.set_mission_current(c.p[0] as i64),
            MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH => self.set_mode_result(Mode::Rtl),
            MavCmd::MAV_CMD_NAV_TAKEOFF => self.takeoff(&c),
            MavCmd::MAV_CMD_NAV_LAND if self.is_copter() => self.set_mode_result(Mode::Land),
            MavCmd::MAV_CMD_DO_REPOSITION => self.reposition(&c),
            MavCmd::MAV_CMD_DO_CHANGE_SPEED => self.change_speed_command(&c),
            MavCmd::MAV_CMD_DO_SET_SERVO => {
                self.set_servo(c.p[0] as u8, c.p[1] as u16);
                MavResult::MAV_RESULT_ACCEPTED
            }
            MavCmd::MAV_CMD_IMAGE_START_CAPTURE => self.image_start_capture(c.p[0], c.p[1], c.p[2]),
            MavCmd::MAV_CMD_DO_DIGICAM_CONTROL => {
                self.digicam_control(c.p[4]);
                MavResult::MAV_RESULT_ACCEPTED
            }
            MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL => {
                self.streams
                    .set_interval_us(c.p[0] as u32, c.p[1], self.now_ms)
            }
            MavCmd::MAV_CMD_REQUEST_MESSAGE => return self.request_message(&c, c.p[0] as u32),
            MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES => {
                return self.request_message(&c, telemetry::AUTOPILOT_VERSION)
            }
            MavCmd::MAV_CMD_GET_HOME_POSITION => {
                return self.request_message(&c, telemetry::HOME_POSITION)
            }
            MavCmd::MAV_CMD_USER_1 => return self.downlink_command(&c),
            _ => MavResult::MAV_RESULT_UNSUPPORTED,
        };
        self.ack(&c, result, 0);
    }

    fn request_message(&mut self, c: &Cmd, id: u32) {
        if self.px4_denies_request(id) {
            self.ack(c, MavResult::MAV_RESULT_DENIED, 0);
            return;
        }
        if id == telemetry::STORAGE_INFORMATION && !self.behaviour.storage_information {
            // ArduPilot has no STORAGE_INFORMATION: an unknown id is FAILED.
            self.ack(c, MavResult::MAV_RESULT_FAILED, 0);
            return;
        }
        match self.build(id) {
            Some(m) => {
                self.ack(c, MavResult::MAV_RESULT_ACCEPTED, 0);
                self.send_to(c.from.peer, m);
            }
            // A message ArduPilot knows but has nothing for yet (no home before the fix, no
            // camera) is ACCEPTED and not sent.
            None if telemetry::SENDABLE.contains(&id) || self.knows_camera_feedback(id) => {
                self.ack(c, MavResult::MAV_RESULT_ACCEPTED, 0)
            }
            None => self.ack(c, MavResult::MAV_RESULT_UNSUPPORTED, 0),
        }
    }

    fn knows_camera_feedback(&self, id: u32) -> bool {
        id == telemetry::CAMERA_FEEDBACK && self.behaviour.camera != CameraBackend::Mavlink
    }

    fn set_mode_result(&mut self, m: Mode) -> MavResult {
        match self.set_mode(m) {
            Ok(()) => MavResult::MAV_RESULT_ACCEPTED,
            Err(_) => self.refused_result(),
        }
    }

    fn set_mission_current(&mut self, seq: i64) -> MavResult {
        // ArduPilot's DO_SET_MISSION_CURRENT counts home as 0; seq 0 means the first item.
        let seq = seq.max(i64::from(self.first_item()));
        if seq as usize >= self.mission.len() {
            return MavResult::MAV_RESULT_DENIED;
        }
        self.exec.restart_at(seq as u16);
        self.broadcast_mission_current();
        MavResult::MAV_RESULT_ACCEPTED
    }

    /// DO_REPOSITION: COMMAND_INT only; bit 1 of p2 switches to GUIDED, else GUIDED is required.
    fn reposition(&mut self, c: &Cmd) -> MavResult {
        let Some((x, y, _frame)) = c.int else {
            return MavResult::MAV_RESULT_COMMAND_INT_ONLY;
        };
        // A target that cannot be a place, or a speed that is not a number, is refused (ArduPilot: DENIED).
        let place =
            super::mission::absurd_position(true, f64::from(x) / 1e7, f64::from(y) / 1e7, c.p[6]);
        if place.is_some() || !c.p[0].is_finite() {
            return MavResult::MAV_RESULT_DENIED;
        }
        let submodes = self.behaviour.guided_submodes;
        // ArduPilot refuses (0, 0); the simple model reads it as "here".
        if submodes && x == 0 && y == 0 {
            return MavResult::MAV_RESULT_DENIED;
        }
        let change_mode = (c.p[1] as u32) & 1 == 1;
        if self.mode != Mode::Guided {
            if !change_mode {
                return MavResult::MAV_RESULT_DENIED;
            }
            if self.set_mode(Mode::Guided).is_err() {
                return MavResult::MAV_RESULT_FAILED;
            }
        }
        let speed = f64::from(c.p[0]);
        if self.is_px4() && !self.armed {
            // PX4's navigator takes a reposition only armed: the mode changed, no target.
            return MavResult::MAV_RESULT_ACCEPTED;
        }
        if !submodes {
            // The simple model: the speed goes with this target, whatever the state before.
            self.set_guided_target(x, y, c.p[6], speed);
            return MavResult::MAV_RESULT_ACCEPTED;
        }
        // handle_command_int_do_reposition sets the speed before the destination: from GUIDED's
        // Stop submode (just entered, or no destination yet) that fails, the mode stays GUIDED and
        // the destination is not set.
        if speed > 0.0 && !self.set_desired_speed(speed) {
            return MavResult::MAV_RESULT_FAILED;
        }
        self.set_guided_target(x, y, c.p[6], 0.0);
        MavResult::MAV_RESULT_ACCEPTED
    }

    /// MAV_CMD_DO_CHANGE_SPEED (p1 speed type, p2 m/s).
    fn change_speed_command(&mut self, c: &Cmd) -> MavResult {
        let speed = f64::from(c.p[1]);
        if !self.behaviour.guided_submodes {
            return if self.change_speed(speed) {
                MavResult::MAV_RESULT_ACCEPTED
            } else {
                MavResult::MAV_RESULT_DENIED
            };
        }
        // SPEED_TYPE: airspeed (0) is read as ground speed (1); climb (2), descent (3) and the
        // enum end (4) are refused.
        if matches!(c.p[0] as i64, 2..=4) {
            return MavResult::MAV_RESULT_DENIED;
        }
        if self.change_speed(speed) {
            MavResult::MAV_RESULT_ACCEPTED
        } else {
            MavResult::MAV_RESULT_FAILED
        }
    }

    /// A speed change from a command or a mission item; false when refused. The simple model takes
    /// any positive speed in any mode, until a reboot.
    pub(super) fn change_speed(&mut self, speed: f64) -> bool {
        if self.behaviour.guided_submodes {
            return self.set_desired_speed(speed);
        }
        if speed > 0.0 {
            self.speed_override = Some(speed);
        }
        speed > 0.0
    }

    /// Rover's `Mode::set_desired_speed`: AUTO and RTL set AR_WPNav's maximum speed, GUIDED only in
    /// its WP submode (a destination given since GUIDED was entered), MANUAL and HOLD never. It lasts
    /// until a navigating mode is entered again.
    fn set_desired_speed(&mut self, speed: f64) -> bool {
        let ok = speed >= WPNAV_SPEED_MIN
            && match self.mode {
                Mode::Auto | Mode::Rtl => true,
                Mode::Guided => self.guided_target.is_some(),
                Mode::Manual | Mode::Hold | Mode::Land => false,
            };
        if ok {
            self.speed_override = Some(speed);
        }
        ok
    }

    pub(super) fn set_guided_target(&mut self, lat_e7: i32, lon_e7: i32, alt: f32, speed: f64) {
        let pos = if lat_e7 == 0 && lon_e7 == 0 {
            self.kin.pos
        } else {
            self.frame.to_local_e7(lat_e7, lon_e7)
        };
        let depth = self.depth_of(alt);
        self.guided_target = Some(Target {
            pos,
            depth,
            speed: if speed > 0.0 { speed } else { 0.0 },
            stop: true,
        });
    }

    pub(super) fn on_set_position_target(&mut self, m: &SET_POSITION_TARGET_GLOBAL_INT_DATA) {
        // Ignored outside GUIDED, as ArduPilot Rover does.
        if self.mode != Mode::Guided {
            return;
        }
        let pos_ignored = m
            .type_mask
            .contains(PositionTargetTypemask::POSITION_TARGET_TYPEMASK_X_IGNORE);
        let place = super::mission::absurd_position(
            true,
            f64::from(m.lat_int) / 1e7,
            f64::from(m.lon_int) / 1e7,
            m.alt,
        );
        if !pos_ignored && place.is_none() {
            self.set_guided_target(m.lat_int, m.lon_int, m.alt, 0.0);
        }
    }

    pub(super) fn on_set_mode(&mut self, from: Sender, m: &SET_MODE_DATA) {
        let result = match self.mode_from_number(m.custom_mode) {
            Some(mode) => self.set_mode_result(mode),
            None => MavResult::MAV_RESULT_FAILED,
        };
        self.ack_to(from, MavCmd::MAV_CMD_DO_SET_MODE, result, 0);
    }

    pub(super) fn on_request_data_stream(&mut self, m: &REQUEST_DATA_STREAM_DATA) {
        let hz = if m.start_stop == 0 {
            0
        } else {
            m.req_message_rate
        };
        let ids = data_stream_ids(m.req_stream_id);
        self.streams.set_rate_hz(&ids, hz, self.now_ms);
    }
}
