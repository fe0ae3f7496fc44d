//! Local frame (metres north/east of home) <-> WGS84 lat/lon, equirectangular around home:
//! exact enough for the few kilometres a rover mission spans.

use nalgebra::Vector2;

use crate::config::GeoPoint;

const EARTH_RADIUS_M: f64 = 6_378_137.0;

#[derive(Debug, Clone, Copy)]
pub struct LocalFrame {
    origin: GeoPoint,
    metres_per_deg_lat: f64,
    metres_per_deg_lon: f64,
}

impl LocalFrame {
    pub fn new(origin: GeoPoint) -> Self {
        let m = EARTH_RADIUS_M * std::f64::consts::PI / 180.0;
        Self {
            origin,
            metres_per_deg_lat: m,
            metres_per_deg_lon: m * origin.lat.to_radians().cos().max(1e-6),
        }
    }

    pub fn origin(&self) -> GeoPoint {
        self.origin
    }

    /// [north, east] metres.
    pub fn to_local(self, p: GeoPoint) -> Vector2<f64> {
        Vector2::new(
            (p.lat - self.origin.lat) * self.metres_per_deg_lat,
            (p.lon - self.origin.lon) * self.metres_per_deg_lon,
        )
    }

    pub fn to_geo(self, ne: Vector2<f64>) -> GeoPoint {
        GeoPoint {
            lat: self.origin.lat + ne.x / self.metres_per_deg_lat,
            lon: self.origin.lon + ne.y / self.metres_per_deg_lon,
        }
    }

    /// From MAVLink integer degrees ×1e7.
    pub fn to_local_e7(self, lat_e7: i32, lon_e7: i32) -> Vector2<f64> {
        self.to_local(GeoPoint {
            lat: f64::from(lat_e7) * 1e-7,
            lon: f64::from(lon_e7) * 1e-7,
        })
    }
}

/// Degrees to MAVLink integer degrees ×1e7 (saturating on nonsense).
pub fn e7(deg: f64) -> i32 {
    (deg * 1e7).round().clamp(i32::MIN as f64, i32::MAX as f64) as i32
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]
        #[test]
        fn round_trip(n in -5000.0f64..5000.0, e in -5000.0f64..5000.0, lat in -60.0f64..60.0) {
            let f = LocalFrame::new(GeoPoint { lat, lon: 10.0 });
            let back = f.to_local(f.to_geo(Vector2::new(n, e)));
            prop_assert!((back.x - n).abs() < 1e-6 && (back.y - e).abs() < 1e-6);
        }
    }

    #[test]
    fn one_degree_of_latitude_is_about_111_km() {
        let f = LocalFrame::new(GeoPoint { lat: 0.0, lon: 0.0 });
        let d = f.to_local(GeoPoint { lat: 1.0, lon: 0.0 });
        assert!((d.x - 111_319.5).abs() < 1.0);
    }
}
