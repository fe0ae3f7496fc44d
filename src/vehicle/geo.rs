//! Local East-North-Up metres ↔ WGS84 lat/lon around the problem's home (equirectangular: exact enough over
//! the few kilometres a mission spans, and the inverse of itself to the centimetre).

use super::types::Enu;

const EARTH_RADIUS_M: f64 = 6_378_137.0;

/// The problem's home: the origin of the local frame.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Home {
    pub lat: f64,
    pub lon: f64,
    #[serde(default)]
    pub alt: f64,
}

impl Home {
    pub fn to_global(self, p: Enu) -> (f64, f64, f64) {
        let lat = self.lat + (p.north / EARTH_RADIUS_M).to_degrees();
        let lon = self.lon + (p.east / (EARTH_RADIUS_M * self.lat.to_radians().cos())).to_degrees();
        (lat, lon, self.alt + p.up)
    }

    pub fn to_local(self, lat: f64, lon: f64, alt: f64) -> Enu {
        let north = (lat - self.lat).to_radians() * EARTH_RADIUS_M;
        let east = (lon - self.lon).to_radians() * EARTH_RADIUS_M * self.lat.to_radians().cos();
        Enu::new(east, north, alt - self.alt)
    }
}

/// Degrees → the ×1e7 integers of MAVLink.
pub fn deg_e7(deg: f64) -> i32 {
    (deg * 1e7).round() as i32
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(128))]
        #[test]
        fn local_global_round_trip(e in -5000.0f64..5000.0, n in -5000.0f64..5000.0, lat in -70.0f64..70.0) {
            let home = Home { lat, lon: 3.0, alt: 10.0 };
            let (la, lo, al) = home.to_global(Enu::new(e, n, -2.0));
            let back = home.to_local(la, lo, al);
            prop_assert!((back.east - e).abs() < 1e-6 && (back.north - n).abs() < 1e-6);
            prop_assert!((back.up + 2.0).abs() < 1e-9);
        }
    }

    #[test]
    fn one_degree_of_latitude_is_about_111_km() {
        let home = Home {
            lat: 0.0,
            lon: 0.0,
            alt: 0.0,
        };
        let p = home.to_local(1.0, 0.0, 0.0);
        assert!((p.north - 111_319.5).abs() < 1.0, "{p:?}");
    }
}
