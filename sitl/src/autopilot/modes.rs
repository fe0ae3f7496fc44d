//! Flight modes and their ArduPilot numbers (Rover; ArduSub for the AUV; ArduCopter for the copter).

use crate::config::VehicleKind;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Manual,
    Hold,
    Auto,
    Rtl,
    Guided,
    /// Copter only: descend where it is, land, disarm (ArduCopter LAND).
    Land,
}

/// Every mode, for lookups by number.
const ALL: [Mode; 6] = [
    Mode::Manual,
    Mode::Hold,
    Mode::Auto,
    Mode::Rtl,
    Mode::Guided,
    Mode::Land,
];

impl Mode {
    /// The mode's custom_mode on vehicle `v`; None for a mode the vehicle does not have.
    pub fn try_number(self, v: VehicleKind) -> Option<u32> {
        Some(match (v, self) {
            (VehicleKind::Rover, Mode::Manual) => 0,
            (VehicleKind::Rover, Mode::Hold) => 4,
            (VehicleKind::Rover, Mode::Auto) => 10,
            (VehicleKind::Rover, Mode::Rtl) => 11,
            (VehicleKind::Rover, Mode::Guided) => 15,
            (VehicleKind::Auv, Mode::Manual) => 19,
            (VehicleKind::Auv, Mode::Hold) => 16,
            (VehicleKind::Auv, Mode::Auto) => 3,
            (VehicleKind::Auv, Mode::Rtl) => 9,
            (VehicleKind::Auv, Mode::Guided) => 4,
            // ArduCopter's mode numbers (ArduCopter/mode.h, Mode::Number): STABILIZE 0, AUTO 3,
            // GUIDED 4, LOITER 5, RTL 6, LAND 9.
            (VehicleKind::Copter, Mode::Manual) => 0,
            (VehicleKind::Copter, Mode::Hold) => 5,
            (VehicleKind::Copter, Mode::Auto) => 3,
            (VehicleKind::Copter, Mode::Rtl) => 6,
            (VehicleKind::Copter, Mode::Guided) => 4,
            (VehicleKind::Copter, Mode::Land) => 9,
            (_, Mode::Land) => return None,
        })
    }

    /// The mode's custom_mode; a mode the vehicle lacks is never entered (`from_number` never gives it).
    pub fn number(self, v: VehicleKind) -> u32 {
        self.try_number(v).unwrap_or(u32::MAX)
    }

    pub fn from_number(n: u32, v: VehicleKind) -> Option<Mode> {
        ALL.into_iter()
            .find(|m| m.try_number(v) == Some(n))
            // Rover SMART_RTL (12) behaves as RTL here.
            .or(match (v, n) {
                (VehicleKind::Rover, 12) => Some(Mode::Rtl),
                _ => None,
            })
    }

    pub fn name(self) -> &'static str {
        match self {
            Mode::Manual => "MANUAL",
            Mode::Hold => "HOLD",
            Mode::Auto => "AUTO",
            Mode::Rtl => "RTL",
            Mode::Guided => "GUIDED",
            Mode::Land => "LAND",
        }
    }

    /// Modes that drive the vehicle somewhere by themselves.
    pub fn navigates(self) -> bool {
        matches!(self, Mode::Auto | Mode::Rtl | Mode::Guided)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_round_trip_for_every_vehicle() {
        for v in [VehicleKind::Rover, VehicleKind::Auv, VehicleKind::Copter] {
            for m in ALL {
                if let Some(n) = m.try_number(v) {
                    assert_eq!(Mode::from_number(n, v), Some(m));
                }
            }
        }
        assert_eq!(Mode::Auto.number(VehicleKind::Rover), 10);
        assert_eq!(Mode::from_number(99, VehicleKind::Rover), None);
        assert_eq!(Mode::from_number(9, VehicleKind::Rover), None);
        assert_eq!(Mode::from_number(9, VehicleKind::Copter), Some(Mode::Land));
        assert_eq!(Mode::Hold.number(VehicleKind::Copter), 5);
    }
}
