//! `run_mission` against a MockVehicle on the manual clock, as the executive tests call it.

use mavtempo_executive::exec::executive::Executive;
use mavtempo_executive::exec::mission::{run_mission, MissionOptions, MissionReport};
use mavtempo_executive::exec::pacer::MockPacer;
use mavtempo_temporal::model::Time;
use mavtempo_vehicle::MockVehicle;

/// Runs `ex` against `v` (no cycle callback) until it ends or `time_limit_ms` of mission time.
pub fn run_mock(ex: &mut Executive, v: &mut MockVehicle, time_limit_ms: Time) -> MissionReport {
    let opts = MissionOptions {
        time_limit_ms,
        ..MissionOptions::default()
    };
    run_mission(ex, v, &mut MockPacer::default(), &opts, &mut |_, _| {})
}
