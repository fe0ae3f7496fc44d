//! The temporal executive (seed 1 §3) and its dispatch policies (seed 2): it runs a plan made by the
//! temporal core on a vehicle of the vehicle layer, repairing it while the valid part executes.

// The layers below, named at the root so that `crate::model::…` reads as the layer it is.
use mavtempo_temporal::{model, plan, planner, stn};
use mavtempo_vehicle as vehicle;

pub mod dispatch;
pub mod exec;
