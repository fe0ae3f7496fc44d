//! The temporal executive (seed 1 §3) and its dispatch policies (seed 2): it runs a plan made by the
//! temporal core on a vehicle of the vehicle layer, repairing it while the valid part executes.

pub mod config_check;
pub mod dispatch;
pub mod exec;
pub mod id_vec;
pub mod leg_limits;
pub mod mapping;
