//! The PX4 profile (`[autopilot] profile = "px4"`): what a PX4 (main, 2026-03, SIH rover) answers and
//! refuses where ArduPilot would not, checked against PX4-Autopilot's sources (files named below):
//! - modes are `custom_mode = main << 16 | sub << 24`; DO_SET_MODE carries main in p2 and sub in p3
//!   (src/modules/commander/px4_custom_mode.h, Commander.cpp `VEHICLE_CMD_DO_SET_MODE`). Hold and a
//!   reposition are both AUTO/LOITER: the sim's Hold and Guided share one number, and AUTO/LOITER is read
//!   as Guided with no target (the vehicle stops where it is, as PX4's Hold does);
//! - COMMAND_INT in any frame but MAV_FRAME_GLOBAL_INT is answered UNSUPPORTED_MAV_FRAME (9), whatever
//!   the command (src/modules/mavlink/mavlink_receiver.cpp, `handle_message_command_int`);
//! - DO_REPOSITION without the change-mode bit (p2 bit 0) is UNSUPPORTED (Commander.cpp); disarmed, the
//!   mode changes but no target is set (src/modules/navigator/navigator_main.cpp, only when armed);
//! - REQUEST_MESSAGE for a message PX4 has no stream for (EKF_STATUS_REPORT, CAMERA_FEEDBACK) is DENIED
//!   (mavlink_receiver.cpp, `handle_request_message_command`); the estimator is ESTIMATOR_STATUS, streamed
//!   at 1 Hz on the onboard link (mavlink_main.cpp);
//! - ARM while the arming checks fail is TEMPORARILY_REJECTED with "Preflight Fail: ..." texts
//!   (Commander.cpp, HealthAndArmingChecks/checks/estimatorCheck.cpp); SYS_STATUS's PREARM_CHECK health
//!   bit says whether it would arm (src/modules/mavlink/streams/SYS_STATUS.hpp);
//! - a mode needing a position before the fix is TEMPORARILY_REJECTED (Commander.cpp `printRejectMode`);
//! - without a camera component (PX4 SIH has none), IMAGE_START_CAPTURE to the autopilot falls to
//!   Commander's default case: UNSUPPORTED;
//! - a multicopter (checked on SIH's `sihsim_quadx`, 2026-11-27): NAV_TAKEOFF enters AUTO.TAKEOFF
//!   (Commander.cpp `VEHICLE_CMD_NAV_TAKEOFF`) to param7 metres AMSL (MIS_TAKEOFF_ALT, 2.5 m above home,
//!   when not a number: navigator_main.cpp), and Commander switches to AUTO.LOITER by itself once the
//!   takeoff is over (Commander.cpp, "Transition mode to loiter ... after takeoff is completed"); AUTO.LAND
//!   and AUTO.RTL, which prevent arming (ModeUtil/mode_requirements.cpp), land, disarm, and hand back the
//!   last mode that allows arming (UserModeIntention::onDisarm; in the sim, Hold);
//! - EKF2 reports CONST_POS_MODE while the vehicle rests on the ground (`vehicle_at_rest` from the land
//!   detector: ekf/ekf_helper.cpp `get_ekf_soln_status`), with its absolute position and PRED_POS_HORIZ_ABS
//!   (GNSS fused) set: a quadrotor waiting to take off reads 0x3ff.

use mavlink::dialects::ardupilotmega::*;

use super::commands::Cmd;
use super::{Autopilot, Mode};
use crate::scenario::{CameraBackend, Profile};

const MAIN_MANUAL: u32 = 1;
const MAIN_AUTO: u32 = 4;
/// px4_custom_mode.h PX4_CUSTOM_SUB_MODE_AUTO_TAKEOFF.
const SUB_AUTO_TAKEOFF: u32 = 2;
const SUB_AUTO_LOITER: u32 = 3;
const SUB_AUTO_MISSION: u32 = 4;
const SUB_AUTO_RTL: u32 = 5;
/// px4_custom_mode.h PX4_CUSTOM_SUB_MODE_AUTO_LAND.
const SUB_AUTO_LAND: u32 = 6;

/// ESTIMATOR_STATUS's message id.
pub const ESTIMATOR_STATUS: u32 = 230;
/// Messages PX4 has no stream for, that the sim builds for ArduPilot.
const NO_STREAM: [u32; 2] = [193, super::telemetry::CAMERA_FEEDBACK];

/// MIS_TAKEOFF_ALT (mission_params.c): a takeoff's height above home when param7 is not a number.
const MIS_TAKEOFF_ALT_M: f64 = 2.5;

/// The text PX4's estimator check gives while the heading settles after boot (estimatorCheck.cpp), and
/// Commander's answer to the ARM (Commander.cpp `arm`; the one a SIH rover sent on 2026-11-27).
pub const HEADING_NOT_STABLE: &str = "Preflight Fail: heading estimate not stable";
pub const ARMING_DENIED: &str = "Arming denied: Resolve system health failures first";

fn custom_mode(main: u32, sub: u32) -> u32 {
    (main << 16) | (sub << 24)
}

/// A mode's PX4 custom_mode.
pub fn mode_number(m: Mode) -> u32 {
    match m {
        Mode::Manual => custom_mode(MAIN_MANUAL, 0),
        Mode::Hold | Mode::Guided => custom_mode(MAIN_AUTO, SUB_AUTO_LOITER),
        Mode::Auto => custom_mode(MAIN_AUTO, SUB_AUTO_MISSION),
        Mode::Rtl => custom_mode(MAIN_AUTO, SUB_AUTO_RTL),
        Mode::Land => custom_mode(MAIN_AUTO, SUB_AUTO_LAND),
    }
}

/// The mode of a main/sub pair (the sim's modes only).
pub fn mode_from(main: u32, sub: u32) -> Option<Mode> {
    match (main, sub) {
        (MAIN_MANUAL, _) => Some(Mode::Manual),
        (MAIN_AUTO, SUB_AUTO_LOITER) => Some(Mode::Guided),
        (MAIN_AUTO, SUB_AUTO_MISSION) => Some(Mode::Auto),
        (MAIN_AUTO, SUB_AUTO_RTL) => Some(Mode::Rtl),
        (MAIN_AUTO, SUB_AUTO_LAND) => Some(Mode::Land),
        _ => None,
    }
}

impl Autopilot {
    pub(super) fn is_px4(&self) -> bool {
        self.behaviour.profile == Profile::Px4
    }

    /// The mode at boot: PX4 SIH's rover boots in Hold (AUTO/LOITER, seen 2026-11-27), ArduPilot in MANUAL.
    pub(super) fn boot_mode(&self) -> Mode {
        if self.is_px4() {
            Mode::Guided
        } else {
            Mode::Manual
        }
    }

    /// The first mission item flown: ArduPilot's item 0 is home, PX4 flies every item from 0
    /// (src/modules/mavlink/mavlink_mission.cpp stores item 0 as sent; the navigator starts at
    /// `current_seq` 0).
    pub(super) fn first_item(&self) -> u16 {
        if self.is_px4() {
            0
        } else {
            1
        }
    }

    /// The mission's items, home excluded (ArduPilot's item 0).
    pub(super) fn mission_items(&self) -> usize {
        self.mission
            .len()
            .saturating_sub(usize::from(self.first_item()))
    }

    /// The mission with no item: home alone on ArduPilot, nothing on PX4.
    pub(super) fn empty_mission(&self) -> Vec<super::mission::Item> {
        if self.is_px4() {
            Vec::new()
        } else {
            vec![self.home_item()]
        }
    }

    /// The custom_mode the HEARTBEAT reports: the mode's, or PX4's AUTO.TAKEOFF while a copter takes off.
    pub(super) fn reported_mode(&self) -> u32 {
        if self.is_px4() && self.copter.taking_off.is_some() {
            custom_mode(MAIN_AUTO, SUB_AUTO_TAKEOFF)
        } else {
            self.mode_number(self.mode)
        }
    }

    /// NAV_TAKEOFF's height above home: param7 is AMSL on PX4 (the sim's home is at 0 m AMSL).
    pub(super) fn px4_takeoff_altitude(&self, p7: f32) -> f64 {
        if p7.is_finite() {
            f64::from(p7)
        } else {
            MIS_TAKEOFF_ALT_M
        }
    }

    /// A landing's disarm on PX4: back to the mode before AUTO.LAND / AUTO.RTL (Hold in the sim).
    pub(super) fn px4_after_landing(&mut self) {
        self.mode = Mode::Hold;
        self.send(super::Dest::All, self.heartbeat());
    }

    /// The custom_mode the vehicle reports for `m`.
    pub(super) fn mode_number(&self, m: Mode) -> u32 {
        if self.is_px4() {
            mode_number(m)
        } else {
            m.number(self.vehicle)
        }
    }

    /// The mode a reported custom_mode (SET_MODE, a mode-change fault) means.
    pub(super) fn mode_from_number(&self, n: u32) -> Option<Mode> {
        if self.is_px4() {
            mode_from((n >> 16) & 0xff, (n >> 24) & 0xff)
        } else {
            Mode::from_number(n, self.vehicle)
        }
    }

    /// DO_SET_MODE's mode: p2 is ArduPilot's mode number, or PX4's main mode with its sub mode in p3.
    pub(super) fn mode_from_command(&self, p2: f32, p3: f32) -> Option<Mode> {
        if self.is_px4() {
            mode_from(p2 as u32, p3 as u32)
        } else {
            Mode::from_number(p2 as u32, self.vehicle)
        }
    }

    /// What PX4 answers before doing anything of a command (`None`: handled as usual). MAVLink deprecates
    /// GLOBAL_INT in COMMAND_INT, but PX4 still compares against it.
    #[allow(deprecated)]
    pub(super) fn px4_refusal(&self, c: &Cmd) -> Option<MavResult> {
        if !self.is_px4() {
            return None;
        }
        if let Some((_, _, frame)) = c.int {
            if frame != MavFrame::MAV_FRAME_GLOBAL_INT {
                return Some(MavResult::MAV_RESULT_COMMAND_UNSUPPORTED_MAV_FRAME);
            }
        }
        match c.command {
            MavCmd::MAV_CMD_DO_REPOSITION if (c.p[1] as u32) != 1 => {
                Some(MavResult::MAV_RESULT_UNSUPPORTED)
            }
            MavCmd::MAV_CMD_IMAGE_START_CAPTURE if self.behaviour.camera == CameraBackend::None => {
                Some(MavResult::MAV_RESULT_UNSUPPORTED)
            }
            // PX4's rover has no speed or AUTO-start commands the sim models otherwise.
            _ => None,
        }
    }

    /// REQUEST_MESSAGE of an id PX4 has no stream for, or nothing to send yet: DENIED.
    pub(super) fn px4_denies_request(&self, id: u32) -> bool {
        self.is_px4() && (NO_STREAM.contains(&id) || self.build(id).is_none())
    }

    /// A refused mode change or arming: PX4 rejects it for now (it may pass later); ArduPilot fails it.
    pub(super) fn refused_result(&self) -> MavResult {
        if self.is_px4() {
            MavResult::MAV_RESULT_TEMPORARILY_REJECTED
        } else {
            MavResult::MAV_RESULT_FAILED
        }
    }

    /// What the autopilot says when a mode cannot be entered for want of a position.
    pub(super) fn mode_refused_text(&self, m: Mode) -> String {
        if self.is_px4() {
            // Commander::printRejectMode; PX4 calls AUTO/LOITER "Hold".
            let name = match m {
                Mode::Hold | Mode::Guided => "Hold",
                Mode::Auto => "Mission",
                Mode::Rtl => "Return",
                Mode::Manual => "Manual",
                Mode::Land => "Land",
            };
            format!("Switching to {name} is currently not available")
        } else {
            "Flight mode change failed".to_string()
        }
    }

    /// SYS_STATUS health: every sensor, plus PX4's PREARM_CHECK once it would arm.
    pub(super) fn health_sensors(&self, sensors: MavSysStatusSensor) -> MavSysStatusSensor {
        if self.is_px4() && self.ready() && self.battery.can_arm() {
            sensors | MavSysStatusSensor::MAV_SYS_STATUS_PREARM_CHECK
        } else {
            sensors
        }
    }

    /// ESTIMATOR_STATUS (PX4 only): attitude and velocity at once; an absolute horizontal position once
    /// the GPS has a fix, constant-position mode before.
    pub(super) fn estimator_status(&self) -> Option<MavMessage> {
        if !self.is_px4() {
            return None;
        }
        let mut flags = EstimatorStatusFlags::ESTIMATOR_ATTITUDE
            | EstimatorStatusFlags::ESTIMATOR_VELOCITY_HORIZ
            | EstimatorStatusFlags::ESTIMATOR_VELOCITY_VERT
            | EstimatorStatusFlags::ESTIMATOR_POS_VERT_ABS;
        if self.gps_fixed() {
            flags |= EstimatorStatusFlags::ESTIMATOR_POS_HORIZ_REL
                | EstimatorStatusFlags::ESTIMATOR_POS_HORIZ_ABS
                | EstimatorStatusFlags::ESTIMATOR_PRED_POS_HORIZ_ABS;
        }
        // At rest: a copter landed, a ground vehicle disarmed (the land detector's "landed"), and still.
        let landed = if self.is_copter() {
            self.copter.landed
        } else {
            !self.armed
        };
        if !self.gps_fixed() || (landed && self.kin.speed.abs() < 0.01) {
            flags |= EstimatorStatusFlags::ESTIMATOR_CONST_POS_MODE;
        }
        Some(MavMessage::ESTIMATOR_STATUS(ESTIMATOR_STATUS_DATA {
            time_usec: u64::from(self.time_boot_ms()) * 1000,
            flags,
            ..Default::default()
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn px4_mode_numbers_round_trip_and_hold_is_loiter() {
        for m in [Mode::Manual, Mode::Auto, Mode::Rtl, Mode::Guided] {
            let n = mode_number(m);
            assert_eq!(mode_from((n >> 16) & 0xff, (n >> 24) & 0xff), Some(m));
        }
        assert_eq!(mode_number(Mode::Hold), 4 << 16 | 3 << 24);
        assert_eq!(mode_number(Mode::Hold), mode_number(Mode::Guided));
        assert_eq!(mode_number(Mode::Auto), 67_371_008);
        assert_eq!(mode_from(6, 0), None, "OFFBOARD is not modelled");
    }
}
