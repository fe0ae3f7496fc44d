//! The autopilot's geofence as ArduPilot keeps it (AC_Fence): the parameters FENCE_ENABLE, FENCE_TYPE
//! (bits: 1 maximum altitude, 2 the circle of FENCE_RADIUS around home, 4 the polygons and circles of the
//! fence list) and FENCE_RADIUS, and the fence list itself, exchanged over the mission protocol with
//! `mission_type` = FENCE (items 5000–5004). A scenario's `[fence]` holds one from boot; ground stations
//! upload, download and clear it as on ArduPilot.

use serde::Deserialize;

/// `[fence]` of a scenario: ArduPilot's defaults when left out (disabled, circle + polygon, 300 m).
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct FenceParams {
    /// FENCE_ENABLE (0 or 1).
    pub enable: f32,
    /// FENCE_TYPE bitmask.
    #[serde(rename = "type")]
    pub fence_type: f32,
    /// FENCE_RADIUS, metres around home.
    pub radius_m: f32,
    pub polygons: Vec<FencePolygon>,
    pub circles: Vec<FenceCircle>,
}

impl Default for FenceParams {
    fn default() -> Self {
        FenceParams {
            enable: 0.0,
            fence_type: 6.0,
            radius_m: 300.0,
            polygons: Vec::new(),
            circles: Vec::new(),
        }
    }
}

/// A polygon of the fence list: the vehicle stays inside (`inclusion`) or outside.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FencePolygon {
    #[serde(default = "yes")]
    pub inclusion: bool,
    /// `[north, east]` metres from home, at least 3.
    pub corners_m: Vec<[f64; 2]>,
}

/// A circle of the fence list.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FenceCircle {
    #[serde(default = "yes")]
    pub inclusion: bool,
    /// `[north, east]` metres from home.
    pub center_m: [f64; 2],
    pub radius_m: f64,
}

fn yes() -> bool {
    true
}

impl FenceParams {
    /// The first problem: the key and why.
    pub(crate) fn check(&self) -> Result<(), (String, &'static str)> {
        if !(self.radius_m.is_finite() && self.radius_m > 0.0) {
            return Err(("fence.radius_m".into(), "must be > 0"));
        }
        for (i, p) in self.polygons.iter().enumerate() {
            if p.corners_m.len() < 3 || p.corners_m.len() > 255 {
                return Err((
                    format!("fence.polygons.{i}.corners_m"),
                    "needs 3 to 255 corners [north, east]",
                ));
            }
        }
        for (i, c) in self.circles.iter().enumerate() {
            if !(c.radius_m.is_finite() && c.radius_m > 0.0) {
                return Err((format!("fence.circles.{i}.radius_m"), "must be > 0"));
            }
        }
        Ok(())
    }

    /// The value of one of the fence parameters by name.
    pub fn param(&self, name: &str) -> Option<f32> {
        match name {
            "FENCE_ENABLE" => Some(self.enable),
            "FENCE_TYPE" => Some(self.fence_type),
            "FENCE_RADIUS" => Some(self.radius_m),
            _ => None,
        }
    }

    /// Sets a fence parameter; false when the name is not one.
    pub fn set_param(&mut self, name: &str, v: f32) -> bool {
        match name {
            "FENCE_ENABLE" => self.enable = v,
            "FENCE_TYPE" => self.fence_type = v,
            "FENCE_RADIUS" => self.radius_m = v,
            _ => return false,
        }
        true
    }
}

/// The names answered by PARAM_REQUEST_READ / PARAM_REQUEST_LIST, in index order.
pub const PARAMS: [&str; 3] = ["FENCE_ENABLE", "FENCE_TYPE", "FENCE_RADIUS"];
