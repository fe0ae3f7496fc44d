//! Local frame (metres north/east of home) <-> WGS-84 lat/lon, through the Earth model shared with the
//! companion ([`geodesy::LocalFrame`]): the rover drives the distances the planner planned.

use nalgebra::Vector2;

use crate::config::GeoPoint;

/// The rover's 2-D frame: heights are not simulated, so the plane is at home's (zero) height.
#[derive(Debug, Clone, Copy)]
pub struct LocalFrame {
    origin: GeoPoint,
    frame: geodesy::LocalFrame,
}

impl LocalFrame {
    pub fn new(origin: GeoPoint) -> Self {
        Self {
            origin,
            frame: geodesy::LocalFrame::new(geodesy::Geodetic::new(origin.lat, origin.lon, 0.0)),
        }
    }

    pub fn origin(&self) -> GeoPoint {
        self.origin
    }

    /// [north, east] metres.
    pub fn to_local(self, p: GeoPoint) -> Vector2<f64> {
        let e = self.frame.to_enu(geodesy::Geodetic::new(p.lat, p.lon, 0.0));
        Vector2::new(e.north, e.east)
    }

    pub fn to_geo(self, ne: Vector2<f64>) -> GeoPoint {
        let g = self.frame.to_geodetic(geodesy::Enu::new(ne.y, ne.x, 0.0));
        GeoPoint {
            lat: g.lat,
            lon: g.lon,
        }
    }

    /// From MAVLink integer degrees ×1e7.
    pub fn to_local_e7(self, lat_e7: i32, lon_e7: i32) -> Vector2<f64> {
        self.to_local(GeoPoint {
            lat: geodesy::e7_to_deg(lat_e7),
            lon: geodesy::e7_to_deg(lon_e7),
        })
    }
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
}
