//! `sitl`: a simulated vehicle that speaks only MAVLink bytes over real sockets and behaves like
//! ArduPilot Rover (modes, arming, mission protocol, telemetry), with a speed-up clock and fault
//! injection. It shares no Rust types with the companion beyond the `mavlink` crate.
//!
//! ```no_run
//! # async fn demo() -> Result<(), sitl::SimError> {
//! let sim = sitl::spawn(sitl::SimConfig::for_tests()).await?;
//! let addr = sim.client_address().to_string(); // e.g. "tcpout:127.0.0.1:41234"
//! sim.step(std::time::Duration::from_secs(1)).await?; // manual clock
//! assert_eq!(sim.snapshot().mode, "MANUAL");
//! # let _ = addr; Ok(()) }
//! ```

// ArduPilot still speaks the legacy messages (MISSION_ITEM, MISSION_REQUEST, SET_MODE,
// REQUEST_DATA_STREAM) that the dialect marks deprecated: the sim must answer them.
#![allow(deprecated)]

mod autopilot;
mod battery;
pub mod bench;
mod config;
mod error;
mod faults;
pub mod fence;
mod geo;
mod link;
mod payload;
mod physics;
mod scenario;
mod sim;
mod snapshot;
mod time;
mod world;

pub use autopilot::NAV_FAIL_TEXT;
pub use config::{parse_home, ClockMode, GeoPoint, MissionRequestKind, SimConfig, VehicleKind};
pub use error::SimError;
pub use scenario::{
    AutopilotParams, BatteryParams, Behaviour, CameraBackend, CameraParams, EventKind, FailResult,
    Fault, FaultSpec, HomeParams, Profile, SamplerParams, Scenario, Trigger, VehicleParams,
    VisibilityWindow, Zone,
};
pub use sim::{spawn, SimClock, SimHandle};
pub use snapshot::Snapshot;
