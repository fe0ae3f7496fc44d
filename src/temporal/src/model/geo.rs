//! Location coordinates: local metres east/north/up from the problem's home, or WGS-84 lat/lon/alt.
//! Conversions and distances go through the one Earth model shared with the vehicle layer and the SITL
//! ([`geodesy::LocalFrame`]), so the planner's distances are the ones the vehicle drives.

use serde::Serialize;

/// A WGS-84 position: degrees and metres above mean sea level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GeoPoint {
    pub lat: f64,
    pub lon: f64,
    pub alt: f64,
}

/// Where a location object is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Position {
    /// Metres from the problem's home (east, north, up) — `at (9, 0)` or `at (10, -3, 0)` in the language.
    Local { east: f64, north: f64, up: f64 },
    /// Absolute coordinates — `at lat 36.8 lon -122.0 alt -200` in the language.
    Geo(GeoPoint),
}

impl GeoPoint {
    fn geodetic(self) -> geodesy::Geodetic {
        geodesy::Geodetic::new(self.lat, self.lon, self.alt)
    }
}

impl Position {
    /// Local east/north/up metres relative to `home`. A geographic position without a home is projected
    /// around itself (so two such positions still get a sensible mutual distance via [`Position::distance`]).
    pub fn to_local(&self, home: Option<&GeoPoint>) -> (f64, f64, f64) {
        match *self {
            Position::Local { east, north, up } => (east, north, up),
            Position::Geo(p) => {
                let h = home.copied().unwrap_or(p);
                let e = geodesy::LocalFrame::new(h.geodetic()).to_enu(p.geodetic());
                (e.east, e.north, e.up)
            }
        }
    }

    /// Geographic coordinates, given the home that local coordinates are relative to; `None` for a local
    /// position without a home.
    pub fn to_geo(&self, home: Option<&GeoPoint>) -> Option<GeoPoint> {
        match *self {
            Position::Geo(p) => Some(p),
            Position::Local { east, north, up } => {
                let h = home?;
                let g = geodesy::LocalFrame::new(h.geodetic())
                    .to_geodetic(geodesy::Enu::new(east, north, up));
                Some(GeoPoint {
                    lat: g.lat,
                    lon: g.lon,
                    alt: g.alt,
                })
            }
        }
    }

    /// Straight-line distance in metres (3-D). Mixed local/geo positions need the home; without one, a
    /// geographic point is taken as the home of the projection.
    pub fn distance(&self, other: &Position, home: Option<&GeoPoint>) -> f64 {
        let home = home.copied().or(match (self, other) {
            (Position::Geo(p), _) | (_, Position::Geo(p)) => Some(*p),
            _ => None,
        });
        let (e1, n1, u1) = self.to_local(home.as_ref());
        let (e2, n2, u2) = other.to_local(home.as_ref());
        ((e1 - e2).powi(2) + (n1 - n2).powi(2) + (u1 - u2).powi(2)).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn local_distance_is_euclidean() {
        let a = Position::Local {
            east: 0.0,
            north: 0.0,
            up: 0.0,
        };
        let b = Position::Local {
            east: 10.0,
            north: -3.0,
            up: 0.0,
        };
        assert!((a.distance(&b, None) - 109f64.sqrt()).abs() < 1e-9);
    }

    #[test]
    fn geo_round_trip_through_local() {
        let home = GeoPoint {
            lat: 43.56,
            lon: 1.48,
            alt: 150.0,
        };
        let p = Position::Local {
            east: 120.0,
            north: -80.0,
            up: 2.0,
        };
        let g = p.to_geo(Some(&home)).map(Position::Geo);
        let back = g.map(|g| g.to_local(Some(&home)));
        let (e, n, u) = back.unwrap_or((f64::NAN, f64::NAN, f64::NAN));
        assert!((e - 120.0).abs() < 1e-6 && (n + 80.0).abs() < 1e-6 && (u - 2.0).abs() < 1e-9);
        // ~1 km north is ~0.009 degrees of latitude (WGS-84 meridian radius at 43.56°: 6,365.8 km).
        let km = Position::Geo(GeoPoint {
            lat: home.lat + 0.009_000_4,
            ..home
        });
        let d = km.distance(&Position::Geo(home), None);
        assert!((d - 1000.0).abs() < 1.0, "{d}");
    }
}
