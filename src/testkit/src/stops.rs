//! Late-preemptive stops on the MockVehicle: where a stopped move leaves the robot.

use mavtempo_vehicle::{Enu, MockVehicle, StateValue};

/// A `move` of `v` that is stopped reports the robot's position `at`.
pub fn move_stops_at(v: &mut MockVehicle, at: Enu) {
    v.on_stop("move", vec![("position".into(), StateValue::Position(at))]);
}
