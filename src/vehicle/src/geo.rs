//! Local East-North-Up metres ↔ WGS-84 lat/lon around the vehicle's home, through the one Earth model shared
//! with the planner and the SITL ([`geodesy::LocalFrame`]).

use super::types::Enu;

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
    fn frame(self) -> geodesy::LocalFrame {
        geodesy::LocalFrame::new(geodesy::Geodetic::new(self.lat, self.lon, self.alt))
    }

    pub fn to_global(self, p: Enu) -> (f64, f64, f64) {
        let g = self
            .frame()
            .to_geodetic(geodesy::Enu::new(p.east, p.north, p.up));
        (g.lat, g.lon, g.alt)
    }

    pub fn to_local(self, lat: f64, lon: f64, alt: f64) -> Enu {
        let e = self.frame().to_enu(geodesy::Geodetic::new(lat, lon, alt));
        Enu::new(e.east, e.north, e.up)
    }
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
}
