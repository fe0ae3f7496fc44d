//! A picture goal request at a new place, as an upload brings it to the executive.

use mavtempo_vehicle::{Enu, GoalKind, GoalLocation, GoalRequest};

/// A picture of a new target `east`, `north` metres from home (the window is the whole mission).
pub fn picture(name: &str, east: f64, north: f64, priority: u32) -> GoalRequest {
    GoalRequest {
        name: name.into(),
        kind: GoalKind::PictureOf,
        proposition: format!("picture_of({name}_loc)"),
        location: Some(GoalLocation {
            name: format!("{name}_loc"),
            new: true,
            at: Enu::new(east, north, 0.0),
            lat: 0.0,
            lon: 0.0,
        }),
        priority,
        start_window_s: (0.0, 1_800.0),
        duration_s: (0.0, f64::INFINITY),
        d_achiev_s: 60.0,
    }
}
