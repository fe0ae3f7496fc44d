//! A mode's name as the operator's ground station shows it. ArduPilot numbers its modes per vehicle (Rover's
//! 6 is FOLLOW, Copter's 6 is RTL), so the table is the one of the vehicle the autopilot's HEARTBEAT
//! reports (its `type`); PX4's custom modes (main << 16 | sub << 24) are never an ArduPilot number.

use mavlink::dialects::ardupilotmega::MavType;

/// Which of ArduPilot's mode tables a vehicle type uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Table {
    Rover,
    Copter,
    Sub,
}

fn table(vehicle: Option<MavType>) -> Table {
    use MavType::*;
    match vehicle {
        Some(
            MAV_TYPE_QUADROTOR | MAV_TYPE_HEXAROTOR | MAV_TYPE_OCTOROTOR | MAV_TYPE_TRICOPTER
            | MAV_TYPE_HELICOPTER | MAV_TYPE_COAXIAL | MAV_TYPE_DODECAROTOR | MAV_TYPE_DECAROTOR,
        ) => Table::Copter,
        Some(MAV_TYPE_SUBMARINE) => Table::Sub,
        // Rover and boat, and a vehicle not heard from yet (the companion's first vehicle).
        _ => Table::Rover,
    }
}

/// ArduPilot Rover's `Mode::Number` (Rover/mode.h).
fn rover(mode: u32) -> Option<&'static str> {
    Some(match mode {
        0 => "MANUAL",
        1 => "ACRO",
        3 => "STEERING",
        4 => "HOLD",
        5 => "LOITER",
        6 => "FOLLOW",
        7 => "SIMPLE",
        8 => "DOCK",
        9 => "CIRCLE",
        10 => "AUTO",
        11 => "RTL",
        12 => "SMART_RTL",
        15 => "GUIDED",
        16 => "INITIALISING",
        _ => return None,
    })
}

/// ArduCopter's `Mode::Number` (ArduCopter/mode.h).
fn copter(mode: u32) -> Option<&'static str> {
    Some(match mode {
        0 => "STABILIZE",
        1 => "ACRO",
        2 => "ALT_HOLD",
        3 => "AUTO",
        4 => "GUIDED",
        5 => "LOITER",
        6 => "RTL",
        7 => "CIRCLE",
        9 => "LAND",
        11 => "DRIFT",
        13 => "SPORT",
        14 => "FLIP",
        15 => "AUTOTUNE",
        16 => "POSHOLD",
        17 => "BRAKE",
        18 => "THROW",
        19 => "AVOID_ADSB",
        20 => "GUIDED_NOGPS",
        21 => "SMART_RTL",
        22 => "FLOWHOLD",
        23 => "FOLLOW",
        24 => "ZIGZAG",
        25 => "SYSTEMID",
        26 => "AUTOROTATE",
        27 => "AUTO_RTL",
        28 => "TURTLE",
        _ => return None,
    })
}

/// ArduSub's `Mode::Number` (ArduSub/mode.h): STABILIZE to GUIDED and CIRCLE are ArduCopter's numbers.
fn sub(mode: u32) -> Option<&'static str> {
    Some(match mode {
        0..=4 | 7 => return copter(mode),
        9 => "SURFACE",
        16 => "POSHOLD",
        19 => "MANUAL",
        20 => "MOTOR_DETECT",
        21 => "SURFTRAK",
        _ => return None,
    })
}

/// The name of `mode` on a vehicle of type `vehicle` (the autopilot's HEARTBEAT), else `mode N`.
pub fn mode_name(mode: u32, vehicle: Option<MavType>) -> String {
    let name = match table(vehicle) {
        Table::Rover => rover(mode),
        Table::Copter => copter(mode),
        Table::Sub => sub(mode),
    };
    match name {
        Some(n) => n.to_string(),
        None => super::px4::mode_name(mode).unwrap_or_else(|| format!("mode {mode}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_copter_is_named_from_arducopters_table_and_a_rover_from_rovers() {
        let quad = Some(MavType::MAV_TYPE_QUADROTOR);
        assert_eq!(mode_name(6, quad), "RTL");
        assert_eq!(mode_name(9, quad), "LAND");
        assert_eq!(mode_name(5, quad), "LOITER");
        assert_eq!(mode_name(4, quad), "GUIDED");
        let rover = Some(MavType::MAV_TYPE_GROUND_ROVER);
        assert_eq!(mode_name(6, rover), "FOLLOW");
        assert_eq!(mode_name(4, rover), "HOLD");
        assert_eq!(
            mode_name(4, None),
            "HOLD",
            "a vehicle not heard from: Rover's"
        );
        assert_eq!(mode_name(9, Some(MavType::MAV_TYPE_SUBMARINE)), "SURFACE");
        assert_eq!(mode_name(99, quad), "mode 99");
    }

    #[test]
    fn px4_modes_keep_their_names_whatever_the_vehicle() {
        let px4_rtl = 4 << 16 | 5 << 24;
        assert_eq!(
            mode_name(px4_rtl, Some(MavType::MAV_TYPE_QUADROTOR)),
            "Return (4/5)"
        );
        assert_eq!(
            mode_name(4 << 16 | 3 << 24, Some(MavType::MAV_TYPE_GROUND_ROVER)),
            "Hold (4/3)"
        );
    }
}
