//! `sitl`: a simulated vehicle that speaks only MAVLink bytes over real sockets and behaves like
//! ArduPilot Rover (modes, arming, mission protocol, telemetry), with a speed-up clock and fault injection.
//! It shares no Rust types with the companion beyond the `mavlink` crate.
