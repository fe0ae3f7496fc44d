//! The copter (`VehicleKind::Copter`): what ArduCopter adds to the shared autopilot — takeoff, altitude,
//! landing and its landed state, hover power. Checked against ArduCopter's sources:
//! - `GCS_MAVLINK_Copter::handle_MAV_CMD_NAV_TAKEOFF`: param7 metres above home; over COMMAND_INT only frame
//!   GLOBAL_RELATIVE_ALT (else DENIED); `Mode::do_user_takeoff` fails (FAILED) disarmed, already flying or
//!   in a mode without a user takeoff (here GUIDED and LOITER);
//! - MAV_CMD_NAV_LAND enters LAND, MAV_CMD_NAV_RETURN_TO_LAUNCH enters RTL; `ModeLand` disarms once landed,
//!   and so does RTL's final landing (RTL_ALT_FINAL 0), after climbing to RTL_ALT (15 m) if lower;
//! - `GCS_MAVLINK_Copter::landed_state`: ON_GROUND once `land_complete`, LANDING in LAND and RTL's descent,
//!   TAKEOFF while taking off, else IN_AIR; EXTENDED_SYS_STATE is in no default stream (asked for);
//! - `Copter::auto_disarm_check`: a copter armed on the ground disarms after DISARM_DELAY (10 s);
//! - a landed copter does not move, whatever its GUIDED target (`ModeGuided::pos_control_run` keeps it on
//!   the ground while `land_complete`).

use mavlink::dialects::ardupilotmega::*;
use nalgebra::Vector2;

use super::commands::Cmd;
use super::{Autopilot, Mode};
use crate::config::VehicleKind;
use crate::physics::Target;

/// ArduCopter RTL_ALT (1500 cm): the lowest altitude a return flies at.
const RTL_ALT_M: f64 = 15.0;
/// ArduCopter DISARM_DELAY (s).
const DISARM_DELAY_MS: u64 = 10_000;
/// Altitude under which a descending copter has touched down.
const TOUCHDOWN_M: f64 = 0.05;
/// A takeoff is over within this of its altitude.
const TAKEOFF_DONE_M: f64 = 0.2;

/// The copter's flight state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CopterState {
    /// ArduCopter's `ap.land_complete`.
    pub landed: bool,
    /// The takeoff's altitude while taking off.
    pub taking_off: Option<f64>,
    /// Since when (sim ms) it has been armed on the ground.
    armed_on_ground_since: Option<u64>,
}

impl Default for CopterState {
    fn default() -> Self {
        Self {
            landed: true,
            taking_off: None,
            armed_on_ground_since: None,
        }
    }
}

impl Autopilot {
    pub(super) fn is_copter(&self) -> bool {
        self.vehicle == VehicleKind::Copter
    }

    /// Metres above home.
    fn altitude(&self) -> f64 {
        -self.kin.depth
    }

    /// MAV_CMD_NAV_TAKEOFF.
    pub(super) fn takeoff(&mut self, c: &Cmd) -> MavResult {
        if !self.is_copter() {
            return MavResult::MAV_RESULT_UNSUPPORTED;
        }
        if c.int
            .is_some_and(|(_, _, f)| f != MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT)
        {
            return MavResult::MAV_RESULT_DENIED;
        }
        let alt = if self.is_px4() {
            self.px4_takeoff_altitude(c.p[6])
        } else {
            f64::from(c.p[6])
        };
        // PX4's Commander enters AUTO.TAKEOFF from any mode (the sim: Guided, reported as AUTO.TAKEOFF).
        let mode_ok = matches!(self.mode, Mode::Guided | Mode::Hold) || self.is_px4();
        let can = alt.is_finite() && alt > 0.0 && mode_ok && self.armed && self.copter.landed;
        if !can {
            return if self.is_px4() {
                self.refused_result()
            } else {
                MavResult::MAV_RESULT_FAILED
            };
        }
        if self.is_px4() {
            self.mode = Mode::Guided;
        }
        self.copter.landed = false;
        self.copter.taking_off = Some(alt);
        self.copter.armed_on_ground_since = None;
        self.guided_target = Some(Target {
            pos: self.kin.pos,
            depth: -alt,
            speed: 0.0,
            stop: true,
        });
        MavResult::MAV_RESULT_ACCEPTED
    }

    /// Where a copter's mode takes it: `Some(None)` on the ground (it does not move there), None where
    /// the shared GUIDED and AUTO targets apply.
    pub(super) fn copter_target(&self, speed: f64) -> Option<Option<Target>> {
        if self.copter.landed && self.copter.taking_off.is_none() {
            return Some(None);
        }
        let here = Target {
            pos: self.kin.pos,
            depth: self.kin.depth,
            speed: 0.0,
            stop: true,
        };
        let target = match self.mode {
            Mode::Land => Target { depth: 0.0, ..here },
            Mode::Rtl => {
                let home = Vector2::zeros();
                if (self.kin.pos - home).norm() > self.params.wp_radius_m {
                    Target {
                        pos: home,
                        depth: -self.altitude().max(RTL_ALT_M),
                        speed,
                        stop: true,
                    }
                } else {
                    Target {
                        pos: home,
                        depth: 0.0,
                        speed,
                        stop: true,
                    }
                }
            }
            // LOITER and STABILIZE (no pilot input here): holds where it is.
            Mode::Hold | Mode::Manual => here,
            Mode::Guided | Mode::Auto => return None,
        };
        Some(Some(target))
    }

    /// One tick after the motion: takeoff over, touchdown, hover power, the disarm on the ground.
    pub(super) fn step_copter(&mut self, dt: f64) {
        if !self.is_copter() {
            return;
        }
        let alt = self.altitude();
        if !self.copter.landed {
            self.battery.hover(dt);
        }
        if let Some(target) = self.copter.taking_off {
            if (alt - target).abs() <= TAKEOFF_DONE_M || self.mode != Mode::Guided {
                self.copter.taking_off = None;
            }
        } else if !self.copter.landed && alt <= TOUCHDOWN_M && self.kin.vz >= -1e-6 {
            self.copter.landed = true;
            if matches!(self.mode, Mode::Land | Mode::Rtl) && self.armed {
                self.text(MavSeverity::MAV_SEVERITY_INFO, "Land complete");
                self.disarm();
                if self.is_px4() {
                    self.px4_after_landing();
                }
            }
        }
        if !self.armed && alt <= TOUCHDOWN_M {
            self.copter.landed = true;
            self.copter.taking_off = None;
        }
        // Copter::auto_disarm_check.
        if self.armed && self.copter.landed {
            let since = *self.copter.armed_on_ground_since.get_or_insert(self.now_ms);
            if self.now_ms.saturating_sub(since) >= DISARM_DELAY_MS {
                self.text(MavSeverity::MAV_SEVERITY_INFO, "Disarming motors");
                self.disarm();
            }
        } else {
            self.copter.armed_on_ground_since = None;
        }
    }

    /// EXTENDED_SYS_STATE's landed state (UNDEFINED for vehicles that do not fly).
    pub(super) fn landed_state(&self) -> MavLandedState {
        if !self.is_copter() {
            return MavLandedState::MAV_LANDED_STATE_UNDEFINED;
        }
        let descending_home = self.mode == Mode::Rtl
            && self.kin.pos.norm() <= self.params.wp_radius_m
            && self.altitude() > TOUCHDOWN_M;
        if self.copter.landed && self.copter.taking_off.is_none() {
            MavLandedState::MAV_LANDED_STATE_ON_GROUND
        } else if self.copter.taking_off.is_some() {
            MavLandedState::MAV_LANDED_STATE_TAKEOFF
        } else if self.mode == Mode::Land || descending_home {
            MavLandedState::MAV_LANDED_STATE_LANDING
        } else {
            MavLandedState::MAV_LANDED_STATE_IN_AIR
        }
    }
}
