//! Flight modes and their ArduPilot numbers (Rover; ArduSub for the AUV).

use crate::config::VehicleKind;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    Manual,
    Hold,
    Auto,
    Rtl,
    Guided,
}

impl Mode {
    pub fn number(self, v: VehicleKind) -> u32 {
        match (v, self) {
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
        }
    }

    pub fn from_number(n: u32, v: VehicleKind) -> Option<Mode> {
        [
            Mode::Manual,
            Mode::Hold,
            Mode::Auto,
            Mode::Rtl,
            Mode::Guided,
        ]
        .into_iter()
        .find(|m| m.number(v) == n)
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
    fn numbers_round_trip_for_both_vehicles() {
        for v in [VehicleKind::Rover, VehicleKind::Auv] {
            for m in [
                Mode::Manual,
                Mode::Hold,
                Mode::Auto,
                Mode::Rtl,
                Mode::Guided,
            ] {
                assert_eq!(Mode::from_number(m.number(v), v), Some(m));
            }
        }
        assert_eq!(Mode::Auto.number(VehicleKind::Rover), 10);
        assert_eq!(Mode::from_number(99, VehicleKind::Rover), None);
    }
}
