//! `run_mission` against a MockVehicle on the manual clock, as the executive tests call it.
#![allow(dead_code)]

use mavtempo::exec::executive::Executive;
use mavtempo::exec::mission::{run_mission, MissionOptions, MissionReport};
use mavtempo::exec::pacer::MockPacer;
use mavtempo::model::Time;
use mavtempo::vehicle::MockVehicle;

/// Runs `ex` against `v` (no cycle callback) until it ends or `time_limit_ms` of mission time.
pub fn run_mock(ex: &mut Executive, v: &mut MockVehicle, time_limit_ms: Time) -> MissionReport {
    let opts = MissionOptions {
        time_limit_ms,
        ..MissionOptions::default()
    };
    run_mission(ex, v, &mut MockPacer::default(), &opts, &mut |_, _| {})
}
