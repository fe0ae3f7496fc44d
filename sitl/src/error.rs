//! Typed errors of the simulator, each carrying its reason.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum SimError {
    #[error("bad listen address `{addr}`: {reason} (expected tcpin:HOST:PORT, tcpout:HOST:PORT, udpin:HOST:PORT or udpout:HOST:PORT)")]
    BadAddress { addr: String, reason: String },
    #[error("bad listen address {0} (expected tcpin:HOST:PORT, tcpout:HOST:PORT, udpin:HOST:PORT or udpout:HOST:PORT)")]
    Address(#[from] mavaddr::AddressError),
    #[error("cannot open `{addr}`: {source}")]
    Io {
        addr: String,
        #[source]
        source: std::io::Error,
    },
    #[error("bad home `{0}`: expected LAT,LON in degrees (e.g. 43.5615,1.4778)")]
    BadHome(String),
    #[error("bad speed-up {0}: must be within [0.001, 1000000]")]
    BadSpeedup(f64),
    #[error("scenario: {0}")]
    ScenarioRead(#[from] srctext::ReadError),
    #[error("bad scenario {path}: {reason}")]
    Scenario { path: String, reason: String },
    /// A scenario file wrong at `file:line:col` (the line shown).
    #[error("bad scenario {0}")]
    ScenarioAt(Box<srctext::Located>),
    #[error("unknown profile `{0}` (default, ardupilot or px4)")]
    UnknownProfile(String),
    #[error("unknown vehicle `{0}` (rover, auv or copter)")]
    UnknownVehicle(String),
    #[error("the simulator has stopped")]
    Stopped,
}
