//! The executive's `[mapping]` of a shipped vehicle configuration, resolved against a plan's domain and
//! problem through the same check `run` and `demo` use (no name guessing in tests either).

#![allow(dead_code)]

use mavtempo::exec::DomainMapping;
use mavtempo::plan::PartialPlan;
use mavtempo::vehicle::config::VehicleConfig;
use mavtempo::vehicle::config_check::check;

/// config/demo-rover.toml's mapping: positions on AT_ROBOT, new places of type location, waypoint and
/// picture goals.
pub fn rover(plan: &PartialPlan) -> DomainMapping {
    shipped(
        concat!(env!("CARGO_MANIFEST_DIR"), "/config/demo-rover.toml"),
        plan,
    )
}

/// config/sitl-auv.toml's mapping: positions on AUV_AT, new places of type location, `surface` as home.
pub fn auv(plan: &PartialPlan) -> DomainMapping {
    shipped(
        concat!(env!("CARGO_MANIFEST_DIR"), "/config/sitl-auv.toml"),
        plan,
    )
}

fn shipped(path: &str, plan: &PartialPlan) -> DomainMapping {
    let cfg = VehicleConfig::load(std::path::Path::new(path)).unwrap_or_else(|e| panic!("{e}"));
    match check(&cfg, plan.domain(), Some(plan.problem())) {
        Ok(c) => c.mapping,
        Err(issues) => panic!("{issues:?}"),
    }
}
