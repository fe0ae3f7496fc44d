//! The SITL's tests over a real socket: identity, commands, the mission protocol, faults, the clock, the
//! ArduPilot and PX4 profiles, the copter, the scenario files. One test binary for the crate (each module was
//! a test crate of its own); helpers in `support`.

mod support;

mod ardupilot_profile;
mod clock;
mod commands;
mod copter;
mod faults;
mod mission;
mod mission_protocol;
mod px4_copter;
mod px4_profile;
mod scenarios;
