//! How a simulator instance is set up: address, clock, vehicle, home, scenario, seed.

use std::str::FromStr;
use std::time::Duration;

use crate::error::SimError;
use crate::scenario::Scenario;

/// Accepted speed-ups: beyond these the tick pacing means nothing.
pub const MIN_SPEEDUP: f64 = 1e-3;
pub const MAX_SPEEDUP: f64 = 1e6;

/// Which vehicle is simulated. Mode numbering follows the matching ArduPilot firmware.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VehicleKind {
    /// ArduPilot Rover: `MAV_TYPE_GROUND_ROVER`, modes MANUAL 0, HOLD 4, AUTO 10, RTL 11, GUIDED 15.
    #[default]
    Rover,
    /// ArduSub-like AUV: `MAV_TYPE_SUBMARINE` with depth, modes MANUAL 19, POSHOLD 16 (hold), AUTO 3,
    /// SURFACE 9 (return), GUIDED 4.
    Auv,
    /// ArduCopter-like quad: `MAV_TYPE_QUADROTOR` with altitude, takeoff and landing, modes STABILIZE 0
    /// (manual), LOITER 5 (hold), AUTO 3, RTL 6, GUIDED 4, LAND 9 (`autopilot/copter.rs`).
    Copter,
}

impl FromStr for VehicleKind {
    type Err = SimError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "rover" => Ok(Self::Rover),
            "auv" | "sub" => Ok(Self::Auv),
            "copter" | "quad" => Ok(Self::Copter),
            other => Err(SimError::UnknownVehicle(other.to_string())),
        }
    }
}

/// How simulated time advances.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ClockMode {
    /// Sim time follows wall time multiplied by `SimConfig::speedup`, in fixed ticks.
    #[default]
    Paced,
    /// Sim time advances only through [`crate::SimHandle::step`]: fully deterministic tests.
    Manual,
}

/// Which request the vehicle sends during a mission upload.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MissionRequestKind {
    /// `MISSION_REQUEST_INT` (the MAVLink mission protocol).
    #[default]
    Int,
    /// Legacy `MISSION_REQUEST` (msg 40), as observed from ArduPilot Rover SITL.
    Legacy,
}

/// A WGS84 position in degrees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeoPoint {
    pub lat: f64,
    pub lon: f64,
}

impl GeoPoint {
    /// The default home: LAAS-CNRS, Toulouse (where IxTeT-eXeC ran on Dala).
    pub const LAAS: GeoPoint = GeoPoint {
        lat: 43.5615,
        lon: 1.4778,
    };
}

impl From<crate::scenario::HomeParams> for GeoPoint {
    fn from(h: crate::scenario::HomeParams) -> Self {
        GeoPoint {
            lat: h.lat,
            lon: h.lon,
        }
    }
}

/// Parses `LAT,LON` in degrees.
pub fn parse_home(s: &str) -> Result<GeoPoint, SimError> {
    let bad = || SimError::BadHome(s.to_string());
    let (lat, lon) = s.split_once(',').ok_or_else(bad)?;
    let lat: f64 = lat.trim().parse().map_err(|_| bad())?;
    let lon: f64 = lon.trim().parse().map_err(|_| bad())?;
    if !(-90.0..=90.0).contains(&lat) || !(-180.0..=180.0).contains(&lon) {
        return Err(bad());
    }
    Ok(GeoPoint { lat, lon })
}

/// Everything a simulator instance needs. `SimConfig::default()` is ArduPilot SITL's
/// `tcpin:127.0.0.1:5760`, real time, rover at LAAS, no faults, seed 0.
#[derive(Debug, Clone)]
pub struct SimConfig {
    /// `tcpin:HOST:PORT` (accepts any number of clients), `udpin:HOST:PORT` (answers every sender
    /// seen), `tcpout:HOST:PORT` or `udpout:HOST:PORT`. Port 0 binds a free port (see
    /// [`crate::SimHandle::local_addr`]).
    pub listen: String,
    /// Sim seconds per wall second in [`ClockMode::Paced`].
    pub speedup: f64,
    pub clock: ClockMode,
    pub vehicle: VehicleKind,
    pub home: GeoPoint,
    /// World, vehicle parameters and faults.
    pub scenario: Scenario,
    /// Seeds picture sizes and link faults: same seed + scenario + inputs => same run.
    pub seed: u64,
    pub system_id: u8,
    pub mission_request: MissionRequestKind,
    /// Physics and mission step, in sim milliseconds.
    pub tick_ms: u32,
    /// Mission upload re-request period and cancel timeout, on the wall clock (ArduPilot: 1 s / 8 s)
    /// so that clients can upload at any speed-up.
    pub mission_rerequest: Duration,
    pub mission_timeout: Duration,
    /// `SYSTEM_TIME.time_unix_usec` at sim time 0.
    pub epoch_unix_us: u64,
}

impl Default for SimConfig {
    fn default() -> Self {
        Self {
            listen: "tcpin:127.0.0.1:5760".to_string(),
            speedup: 1.0,
            clock: ClockMode::Paced,
            vehicle: VehicleKind::Rover,
            home: GeoPoint::LAAS,
            scenario: Scenario::default(),
            seed: 0,
            system_id: 1,
            mission_request: MissionRequestKind::Int,
            tick_ms: 20,
            mission_rerequest: Duration::from_millis(1000),
            mission_timeout: Duration::from_millis(8000),
            // 2026-01-01T00:00:00Z: a fixed epoch keeps runs reproducible.
            epoch_unix_us: 1_767_225_600_000_000,
        }
    }
}

impl SimConfig {
    /// A config for tests: `tcpin:127.0.0.1:0`, manual clock, short protocol timeouts.
    pub fn for_tests() -> Self {
        Self {
            listen: "tcpin:127.0.0.1:0".to_string(),
            clock: ClockMode::Manual,
            mission_rerequest: Duration::from_millis(300),
            mission_timeout: Duration::from_millis(1500),
            ..Self::default()
        }
    }

    /// Checks the speed-up and the address (also done by `spawn`).
    pub fn validate(&self) -> Result<(), SimError> {
        if !(MIN_SPEEDUP..=MAX_SPEEDUP).contains(&self.speedup) {
            return Err(SimError::BadSpeedup(self.speedup));
        }
        mavaddr::Address::parse(&self.listen)?;
        self.scenario.check().map_err(|e| SimError::Scenario {
            path: "(config)".into(),
            reason: e.to_string(),
        })?;
        // Two different homes are a mistake to report, not a choice to make silently.
        match self.scenario.home {
            Some(h) if self.home != GeoPoint::LAAS && self.home != GeoPoint::from(h) => {
                Err(SimError::Scenario {
                    path: "(config)".into(),
                    reason: format!(
                        "home: the scenario's {}, {} differs from the configured {}, {}",
                        h.lat, h.lon, self.home.lat, self.home.lon
                    ),
                })
            }
            _ => Ok(()),
        }
    }

    /// Where the vehicle boots: the scenario's `[home]`, else `home`.
    pub fn home_point(&self) -> GeoPoint {
        self.scenario.home.map_or(self.home, GeoPoint::from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn home_parses_and_rejects() {
        let h = parse_home("43.5,1.25").expect("valid home");
        assert_eq!((h.lat, h.lon), (43.5, 1.25));
        assert!(parse_home("43.5").is_err());
        assert!(parse_home("91,0").is_err());
        assert!(parse_home("a,b").is_err());
    }

    #[test]
    fn validate_rejects_bad_speedups_and_scenarios() {
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e300, 1e-300] {
            let cfg = SimConfig {
                speedup: bad,
                ..SimConfig::default()
            };
            assert!(cfg.validate().is_err(), "{bad}");
        }
        let mut cfg = SimConfig::default();
        cfg.scenario.camera.size_min_mib = 5.0;
        cfg.scenario.camera.size_max_mib = 1.0;
        assert!(cfg.validate().is_err());
        assert!(SimConfig::default().validate().is_ok());
    }

    #[test]
    fn vehicle_kind_parses() {
        assert_eq!("AUV".parse::<VehicleKind>().ok(), Some(VehicleKind::Auv));
        assert!(matches!(
            "plane".parse::<VehicleKind>(),
            Err(SimError::UnknownVehicle(v)) if v == "plane"
        ));
    }
}
