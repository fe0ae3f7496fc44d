//! The vehicle side: the executive's view of a vehicle ([`Vehicle`]), its in-memory [`MockVehicle`], and the
//! MAVLink implementation ([`MavlinkVehicle`]): action bindings from config, telemetry → state, goal intake
//! from a ground station, `.tlog` recording. Layers, bottom up:
//! - `frame`, `tlog`: bytes ↔ frames, signing, recording;
//! - `commands`, `mission_client`, `telemetry`, `actions`, `driver`: the protocol core, pure (no I/O);
//! - `intake`, `goals`, `item_goals`, `goal_files`, `goal_answers`: goal lists from a ground station or a file, and the
//!   executive's answers;
//! - `config`: a configuration, in the vehicle's words (checked against a domain by the executive crate's
//!   `config_check`: this crate knows nothing of the planner);
//! - `readiness`: the autopilot ready (a fix, arming accepted) before the mission's first start;
//! - `safe_stop`: the vehicle left safe when the companion is stopped by a signal;
//! - `endpoint`, `peers`, `link`: tokio transports, their peers (one decoder per UDP sender), and the tasks
//!   that pump bytes through the core.

pub mod actions;
pub mod api;
pub mod authority;
pub mod binding_table;
pub mod capture_evidence;
pub mod commands;
pub mod config;
pub mod driver;
pub mod endpoint;
pub mod fence;
pub mod flight;
pub mod frame;
pub mod geo;
pub mod goal_answers;
pub mod goal_client;
pub mod goal_files;
pub mod goals;
pub mod held;
pub mod intake;
pub mod item_goals;
pub mod items;
pub mod limits;
pub mod link;
pub mod mission_client;
pub mod mock;
pub mod mode_names;
pub mod observed;
pub mod peers;
pub mod px4;
pub mod readiness;
pub mod safe_stop;
pub mod status;
pub mod telemetry;
pub mod tlog;
pub mod types;
pub mod wire_float;

pub use api::{Vehicle, VehicleError, VehicleEvent};
pub use link::MavlinkVehicle;
pub use mock::MockVehicle;
pub use types::*;
