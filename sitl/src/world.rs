//! The terrain and sky around the vehicle: slow zones, sunlit zones, visibility windows.

use nalgebra::Vector2;

use crate::config::GeoPoint;
use crate::geo::LocalFrame;
use crate::scenario::{Scenario, VisibilityWindow, Zone};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disc {
    pub center: Vector2<f64>,
    pub radius: f64,
    pub speed_factor: f64,
}

impl Disc {
    pub fn from_zone(z: &Zone, frame: &LocalFrame) -> Self {
        let center = match (z.center_m, z.center) {
            (Some([n, e]), _) => Vector2::new(n, e),
            (None, Some([lat, lon])) => frame.to_local(GeoPoint { lat, lon }),
            // The scenario check guarantees one centre; home is the harmless fallback.
            (None, None) => Vector2::zeros(),
        };
        Self {
            center,
            radius: z.radius_m,
            speed_factor: z.speed_factor,
        }
    }

    pub fn contains(&self, p: &Vector2<f64>) -> bool {
        (p - self.center).norm() <= self.radius
    }
}

#[derive(Debug, Clone)]
pub struct World {
    pub slow: Vec<Disc>,
    pub sunlit: Vec<Disc>,
    pub windows: Vec<VisibilityWindow>,
    pub default_rate: f64,
}

impl World {
    pub fn new(s: &Scenario, frame: &LocalFrame) -> Self {
        let sunlit = if s.sunlit_zones.is_empty() {
            vec![Disc {
                center: Vector2::zeros(),
                radius: 50.0,
                speed_factor: 1.0,
            }]
        } else {
            s.sunlit_zones
                .iter()
                .map(|z| Disc::from_zone(z, frame))
                .collect()
        };
        Self {
            slow: s
                .slow_zones
                .iter()
                .map(|z| Disc::from_zone(z, frame))
                .collect(),
            sunlit,
            windows: s.visibility_windows.clone(),
            default_rate: s.camera.downlink_mib_per_s,
        }
    }

    /// The slowest zone's factor at `p` (1 outside every zone).
    pub fn speed_factor(&self, p: &Vector2<f64>) -> f64 {
        self.slow
            .iter()
            .filter(|d| d.contains(p))
            .map(|d| d.speed_factor)
            .fold(1.0, f64::min)
    }

    pub fn sunlit(&self, p: &Vector2<f64>) -> bool {
        self.sunlit.iter().any(|d| d.contains(p))
    }

    /// The downlink rate (MiB/s) at sim time `t_s`, or None outside every visibility window.
    pub fn visibility(&self, t_s: f64) -> Option<f64> {
        if self.windows.is_empty() {
            return Some(self.default_rate);
        }
        self.windows
            .iter()
            .find(|w| w.start_s <= t_s && t_s < w.end_s)
            .map(|w| w.rate_mib_per_s)
    }
}
