//! The executive's `[mapping]` of a shipped vehicle configuration, resolved against a plan's domain and
//! problem through the same check `run` and `demo` use (no name guessing in tests either).

use mavtempo_executive::config_check::check;
use mavtempo_executive::exec::DomainMapping;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_vehicle::config::VehicleConfig;

/// config/demo-rover.toml's mapping: positions on AT_ROBOT, new places of type location, waypoint and
/// picture goals.
pub fn rover(plan: &PartialPlan) -> DomainMapping {
    shipped(repo!("config/demo-rover.toml"), plan)
}

/// config/sitl-auv.toml's mapping: positions on AUV_AT, new places of type location, `surface` as home.
pub fn auv(plan: &PartialPlan) -> DomainMapping {
    shipped(repo!("config/sitl-auv.toml"), plan)
}

fn shipped(path: &str, plan: &PartialPlan) -> DomainMapping {
    let cfg = VehicleConfig::load(std::path::Path::new(path)).unwrap_or_else(|e| panic!("{e}"));
    match check(&cfg, plan.domain(), Some(plan.problem())) {
        Ok(c) => c.mapping,
        Err(issues) => panic!("{issues:?}"),
    }
}
