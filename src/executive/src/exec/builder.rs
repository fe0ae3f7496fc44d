//! The one way the application wires an executive to a vehicle (issue 36: `demo`, `soak` and the CPU
//! bench are `run` with an in-process SITL): the plan, the `[exec]` table read over the command's defaults
//! ([`super::config::ExecConfig::over`]), and what the vehicle configuration says — the `[mapping]`, the
//! `[resources]` tolerances, `[state] moving`, and the limits (`[limits]` with the autopilot's fence). Tests
//! that hand-build an executive use [`Executive::new`] and the `with_*` steps they need.

use super::config::ExecConfig;
use super::executive::Executive;
use crate::mapping::DomainMapping;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_vehicle::config::ResourceNames;
use mavtempo_vehicle::limits::Limits;
use mavtempo_vehicle::observed::Flag;

/// What the vehicle's configuration, checked against the plan's domain, gives the executive.
pub struct VehicleSetup<'a> {
    pub mapping: DomainMapping,
    pub resources: &'a ResourceNames,
    /// `[state] moving`, when motions must end still.
    pub moving: Option<&'a Flag>,
    /// Where the vehicle may go.
    pub limits: Option<Limits>,
}

impl Executive {
    /// An executive over `plan` with `cfg`, bound to the vehicle `setup` describes. The limits come last:
    /// a plan that leaves them is made again before any launch ([`Executive::with_limits`]).
    pub fn build(plan: PartialPlan, cfg: ExecConfig, setup: VehicleSetup<'_>) -> Self {
        Executive::new(plan, cfg)
            .with_mapping(setup.mapping)
            .with_resource_levels(setup.resources)
            .with_still_state(setup.moving)
            .with_limits(setup.limits)
    }
}
