//! Where a PX4 autopilot differs from ArduPilot on the wire, in one place (checked against PX4 main,
//! 2026-03; files named below are PX4-Autopilot's):
//! - COMMAND_INT is only accepted in MAV_FRAME_GLOBAL_INT: any other frame is answered
//!   MAV_RESULT_UNSUPPORTED_MAV_FRAME (9) (src/modules/mavlink/mavlink_receiver.cpp,
//!   `handle_message_command_int`);
//! - it has no EKF_STATUS_REPORT: REQUEST_MESSAGE for a message it has no stream for is DENIED
//!   (mavlink_receiver.cpp, `handle_request_message_command`); its estimator is reported by ESTIMATOR_STATUS,
//!   streamed at 1 Hz on the onboard link (src/modules/mavlink/mavlink_main.cpp, MAVLINK_MODE_ONBOARD), whose
//!   flags are EKF2's solution status, the same bits as EKF_STATUS_REPORT's;
//! - whether it would arm now is SYS_STATUS's MAV_SYS_STATUS_PREARM_CHECK health bit (set when the health
//!   report allows arming in the current navigation state; not flagged present:
//!   src/modules/mavlink/streams/SYS_STATUS.hpp). ARM refused is TEMPORARILY_REJECTED with "Preflight Fail:
//!   ..." texts (src/modules/commander/Commander.cpp, HealthAndArmingChecks/checks/*).

use mavlink::dialects::ardupilotmega::{
    EstimatorStatusFlags, MavFrame, MavMessage, MavSysStatusSensor,
};

use super::config::Autopilot;

/// HOME_POSITION (242), asked for while waiting for a fix (both autopilots have it).
const HOME_POSITION: u16 = 242;
/// EKF_STATUS_REPORT (193): ArduPilot's estimator report.
const EKF_STATUS_REPORT: u16 = 193;

/// The frame positional commands (DO_REPOSITION) go in as COMMAND_INT. ArduPilot reads MAV_FRAME_GLOBAL
/// (kept as it was); PX4 accepts MAV_FRAME_GLOBAL_INT only (altitude AMSL, as the companion sends it).
/// MAVLink deprecates GLOBAL_INT for GLOBAL in COMMAND_INT, but PX4 still compares against GLOBAL_INT.
#[allow(deprecated)]
pub fn command_int_frame(autopilot: Autopilot) -> MavFrame {
    match autopilot {
        Autopilot::Ardupilot => MavFrame::MAV_FRAME_GLOBAL,
        Autopilot::Px4 => MavFrame::MAV_FRAME_GLOBAL_INT,
    }
}

/// The messages asked for (REQUEST_MESSAGE) while waiting for the vehicle to be ready: PX4 streams its
/// estimator status and would only deny EKF_STATUS_REPORT.
pub fn status_requests(autopilot: Autopilot) -> &'static [u16] {
    match autopilot {
        Autopilot::Ardupilot => &[HOME_POSITION, EKF_STATUS_REPORT],
        Autopilot::Px4 => &[HOME_POSITION],
    }
}

/// The estimator trusts its horizontal position: an absolute horizontal position, and either no
/// constant-position mode or an absolute position fused (ESTIMATOR_STATUS flags; `None` for other messages).
/// EKF2 sets CONST_POS_MODE also while the vehicle rests on the ground (`vehicle_at_rest`, from the land
/// detector: src/modules/ekf2/EKF/ekf_helper.cpp `get_ekf_soln_status`), GNSS fused or not: a copter
/// waiting on the ground to take off reads 0x3ff (seen on SIH's quadrotor, 2026-11-27). PRED_POS_HORIZ_ABS
/// says GNSS (or an auxiliary global position) is fused.
pub fn navigation_from(msg: &MavMessage) -> Option<bool> {
    match msg {
        MavMessage::ESTIMATOR_STATUS(e) => {
            let has = |f| e.flags.contains(f);
            Some(
                has(EstimatorStatusFlags::ESTIMATOR_POS_HORIZ_ABS)
                    && (!has(EstimatorStatusFlags::ESTIMATOR_CONST_POS_MODE)
                        || has(EstimatorStatusFlags::ESTIMATOR_PRED_POS_HORIZ_ABS)),
            )
        }
        _ => None,
    }
}

/// PX4's pre-arm verdict from SYS_STATUS (`None` for other messages): the PREARM_CHECK health bit.
pub fn prearm_from(msg: &MavMessage) -> Option<bool> {
    match msg {
        MavMessage::SYS_STATUS(s) => Some(
            s.onboard_control_sensors_health
                .contains(MavSysStatusSensor::MAV_SYS_STATUS_PREARM_CHECK),
        ),
        _ => None,
    }
}

/// A PX4 custom mode's name as QGroundControl shows it (src/modules/commander/px4_custom_mode.h); `None`
/// for a number that is no PX4 main mode.
pub fn mode_name(custom_mode: u32) -> Option<String> {
    let (main, sub) = ((custom_mode >> 16) & 0xff, custom_mode >> 24);
    let name = match (main, sub) {
        (1, _) => "Manual",
        (2, _) => "Altitude",
        (3, _) => "Position",
        (4, 2) => "Takeoff",
        (4, 3) => "Hold",
        (4, 4) => "Mission",
        (4, 5) => "Return",
        (4, 6) => "Land",
        (4, _) => "Auto",
        (5, _) => "Acro",
        (6, _) => "Offboard",
        (7, _) => "Stabilized",
        _ => return None,
    };
    Some(format!("{name} ({main}/{sub})"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavlink::dialects::ardupilotmega::{ESTIMATOR_STATUS_DATA, SYS_STATUS_DATA};

    #[test]
    #[allow(deprecated)]
    fn px4_gets_global_int_and_ardupilot_keeps_global() {
        assert_eq!(
            command_int_frame(Autopilot::Px4),
            MavFrame::MAV_FRAME_GLOBAL_INT
        );
        assert_eq!(
            command_int_frame(Autopilot::Ardupilot),
            MavFrame::MAV_FRAME_GLOBAL
        );
        assert!(!status_requests(Autopilot::Px4).contains(&EKF_STATUS_REPORT));
        assert!(status_requests(Autopilot::Ardupilot).contains(&EKF_STATUS_REPORT));
    }

    #[test]
    fn px4_modes_have_their_names_and_ardupilot_numbers_none() {
        assert_eq!(
            mode_name(4 << 16 | 5 << 24).as_deref(),
            Some("Return (4/5)")
        );
        assert_eq!(mode_name(4 << 16 | 3 << 24).as_deref(), Some("Hold (4/3)"));
        assert_eq!(mode_name(15), None);
        assert_eq!(
            crate::mode_names::mode_name(4 << 16 | 3 << 24, None),
            "Hold (4/3)"
        );
        assert_eq!(crate::mode_names::mode_name(4, None), "HOLD");
    }

    #[test]
    fn estimator_flags_and_the_prearm_bit_are_read() {
        let est = |flags| {
            MavMessage::ESTIMATOR_STATUS(ESTIMATOR_STATUS_DATA {
                flags,
                ..Default::default()
            })
        };
        let abs = EstimatorStatusFlags::ESTIMATOR_POS_HORIZ_ABS;
        assert_eq!(navigation_from(&est(abs)), Some(true));
        let constant = abs | EstimatorStatusFlags::ESTIMATOR_CONST_POS_MODE;
        assert_eq!(navigation_from(&est(constant)), Some(false));
        // At rest on the ground with GNSS fused (a PX4 copter before its takeoff): trusted.
        let at_rest = EstimatorStatusFlags::from_bits_truncate(0x3ff);
        assert_eq!(navigation_from(&est(at_rest)), Some(true));
        let no_abs = at_rest - abs;
        assert_eq!(navigation_from(&est(no_abs)), Some(false));
        assert_eq!(
            navigation_from(&est(EstimatorStatusFlags::ESTIMATOR_ATTITUDE)),
            Some(false)
        );
        let sys = |health| {
            MavMessage::SYS_STATUS(SYS_STATUS_DATA {
                onboard_control_sensors_health: health,
                ..Default::default()
            })
        };
        assert_eq!(
            prearm_from(&sys(MavSysStatusSensor::MAV_SYS_STATUS_PREARM_CHECK)),
            Some(true)
        );
        assert_eq!(
            prearm_from(&sys(MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_GPS)),
            Some(false)
        );
        assert_eq!(navigation_from(&sys(MavSysStatusSensor::empty())), None);
    }
}
