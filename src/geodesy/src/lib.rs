//! The one Earth model shared by mavtempo's planner, its vehicle layer and the SITL: the WGS-84 ellipsoid,
//! and a local tangent plane at home (east, north, up metres).
//!
//! The plane is scaled by the ellipsoid's radii of curvature at home: the meridian radius M for north, the
//! prime-vertical radius N (times cos φ) for east, both raised by home's height. The map is linear in
//! (Δlat, Δlon, Δalt), so local ↔ geodetic is an exact inverse (to rounding) however far the point is; the
//! distortion it accepts (meridian convergence, curvature) stays well under a metre per kilometre for the
//! tens of kilometres a mission spans. Every component converting coordinates goes through [`LocalFrame`],
//! so the planner's distances are the vehicle's and the simulator's.

/// WGS-84 semi-major axis, m.
pub const WGS84_A: f64 = 6_378_137.0;
/// WGS-84 flattening.
pub const WGS84_F: f64 = 1.0 / 298.257_223_563;
/// First eccentricity squared, e² = f (2 − f).
pub const WGS84_E2: f64 = WGS84_F * (2.0 - WGS84_F);

/// Below this cos φ (within ~0.2 m of a pole) the east axis is degenerate; it is clamped so that
/// conversions stay finite.
const MIN_COS_LAT: f64 = 1e-8;

/// A geodetic position: latitude and longitude in degrees, altitude in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Geodetic {
    pub lat: f64,
    pub lon: f64,
    pub alt: f64,
}

impl Geodetic {
    pub const fn new(lat: f64, lon: f64, alt: f64) -> Self {
        Geodetic { lat, lon, alt }
    }
}

/// Local metres east, north, up of a frame's origin.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Enu {
    pub east: f64,
    pub north: f64,
    pub up: f64,
}

impl Enu {
    pub const fn new(east: f64, north: f64, up: f64) -> Self {
        Enu { east, north, up }
    }

    /// Straight-line distance in the local frame, m.
    pub fn distance(&self, other: &Enu) -> f64 {
        let (de, dn, du) = (
            self.east - other.east,
            self.north - other.north,
            self.up - other.up,
        );
        (de * de + dn * dn + du * du).sqrt()
    }

    /// Horizontal distance (east, north only), m.
    pub fn horizontal_distance(&self, other: &Enu) -> f64 {
        (self.east - other.east).hypot(self.north - other.north)
    }
}

/// The meridian radius of curvature M at latitude `lat_deg`, m.
pub fn meridian_radius(lat_deg: f64) -> f64 {
    let s = lat_deg.to_radians().sin();
    let w2 = 1.0 - WGS84_E2 * s * s;
    WGS84_A * (1.0 - WGS84_E2) / (w2 * w2.sqrt())
}

/// The prime-vertical radius of curvature N at latitude `lat_deg`, m.
pub fn prime_vertical_radius(lat_deg: f64) -> f64 {
    let s = lat_deg.to_radians().sin();
    WGS84_A / (1.0 - WGS84_E2 * s * s).sqrt()
}

/// Longitude difference folded into [−180, 180): a frame near the antimeridian still sees its neighbours
/// as near.
fn wrap_deg(d: f64) -> f64 {
    (d + 180.0).rem_euclid(360.0) - 180.0
}

/// The local tangent plane at an origin (home).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalFrame {
    origin: Geodetic,
    /// Metres per radian of latitude: M + h.
    m_per_rad_lat: f64,
    /// Metres per radian of longitude: (N + h) cos φ.
    m_per_rad_lon: f64,
}

impl LocalFrame {
    pub fn new(origin: Geodetic) -> Self {
        let cos = origin.lat.to_radians().cos().max(MIN_COS_LAT);
        LocalFrame {
            origin,
            m_per_rad_lat: meridian_radius(origin.lat) + origin.alt,
            m_per_rad_lon: (prime_vertical_radius(origin.lat) + origin.alt) * cos,
        }
    }

    pub fn origin(&self) -> Geodetic {
        self.origin
    }

    /// Geodetic → local metres.
    pub fn to_enu(&self, p: Geodetic) -> Enu {
        Enu {
            east: wrap_deg(p.lon - self.origin.lon).to_radians() * self.m_per_rad_lon,
            north: (p.lat - self.origin.lat).to_radians() * self.m_per_rad_lat,
            up: p.alt - self.origin.alt,
        }
    }

    /// Local metres → geodetic.
    pub fn to_geodetic(&self, e: Enu) -> Geodetic {
        Geodetic {
            lat: self.origin.lat + (e.north / self.m_per_rad_lat).to_degrees(),
            lon: wrap_deg(self.origin.lon + (e.east / self.m_per_rad_lon).to_degrees()),
            alt: self.origin.alt + e.up,
        }
    }

    /// Distance between two geodetic positions measured in this frame, m.
    pub fn distance(&self, a: Geodetic, b: Geodetic) -> f64 {
        self.to_enu(a).distance(&self.to_enu(b))
    }
}

/// Degrees → MAVLink's integer degrees ×1e7 (saturating on nonsense, NaN → 0).
pub fn deg_to_e7(deg: f64) -> i32 {
    (deg * 1e7)
        .round()
        .clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
}

/// MAVLink's integer degrees ×1e7 → degrees.
pub fn e7_to_deg(e7: i32) -> f64 {
    f64::from(e7) * 1e-7
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Metres between two geodetic points that are close (for tolerances): the frame of `a`.
    fn gap_m(a: Geodetic, b: Geodetic) -> f64 {
        LocalFrame::new(a).distance(a, b)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]

        /// lat/lon → local → lat/lon within 1 mm for points within 50 km of home.
        #[test]
        fn geodetic_round_trip_within_a_millimetre(
            lat0 in -80.0f64..80.0, lon0 in -180.0f64..180.0, alt0 in -500.0f64..4000.0,
            bearing in 0.0f64..std::f64::consts::TAU, range in 0.0f64..50_000.0, dalt in -100.0f64..100.0,
        ) {
            let home = Geodetic::new(lat0, lon0, alt0);
            let f = LocalFrame::new(home);
            // A point about `range` metres away (placed through the radii, independent of the frame's code).
            let dlat = (range * bearing.cos() / meridian_radius(lat0)).to_degrees();
            let dlon = (range * bearing.sin() / (prime_vertical_radius(lat0) * lat0.to_radians().cos())).to_degrees();
            let p = Geodetic::new(lat0 + dlat, wrap_deg(lon0 + dlon), alt0 + dalt);
            let back = f.to_geodetic(f.to_enu(p));
            prop_assert!(gap_m(p, back) < 1e-3, "{p:?} -> {back:?}");
            prop_assert!((back.alt - p.alt).abs() < 1e-3);
        }

        /// local → lat/lon → local within 1 mm.
        #[test]
        fn local_round_trip_within_a_millimetre(
            lat0 in -80.0f64..80.0, lon0 in -180.0f64..180.0,
            e in -35_000.0f64..35_000.0, n in -35_000.0f64..35_000.0, u in -50.0f64..50.0,
        ) {
            let f = LocalFrame::new(Geodetic::new(lat0, lon0, 0.0));
            let back = f.to_enu(f.to_geodetic(Enu::new(e, n, u)));
            prop_assert!(back.distance(&Enu::new(e, n, u)) < 1e-3, "{back:?}");
        }
    }

    #[test]
    fn a_degree_of_latitude_follows_the_ellipsoid() {
        // WGS-84: 110,574 m per degree at the equator, 111,694 m at the poles (M grows with latitude).
        let eq = LocalFrame::new(Geodetic::new(0.0, 0.0, 0.0));
        let d = eq.to_enu(Geodetic::new(1.0, 0.0, 0.0)).north;
        assert!((d - 110_574.3).abs() < 1.0, "{d}");
        let polar = meridian_radius(90.0).to_radians();
        assert!((polar - 111_694.0).abs() < 1.0, "{polar}");
        // A degree of longitude at the equator is a / 57.3.
        let e = eq.to_enu(Geodetic::new(0.0, 1.0, 0.0)).east;
        assert!((e - 111_319.5).abs() < 1.0, "{e}");
    }

    #[test]
    fn the_antimeridian_is_not_a_wall() {
        let f = LocalFrame::new(Geodetic::new(-16.0, 179.999, 0.0));
        let p = f.to_enu(Geodetic::new(-16.0, -179.999, 0.0));
        assert!(p.east > 0.0 && p.east < 250.0, "{p:?}");
        let back = f.to_geodetic(p);
        assert!((back.lon + 179.999).abs() < 1e-9, "{back:?}");
    }

    #[test]
    fn near_a_pole_the_frame_stays_finite() {
        let f = LocalFrame::new(Geodetic::new(90.0, 0.0, 0.0));
        let g = f.to_geodetic(Enu::new(10.0, -10.0, 0.0));
        assert!(g.lat.is_finite() && g.lon.is_finite(), "{g:?}");
    }

    #[test]
    fn e7_saturates_and_round_trips() {
        assert_eq!(deg_to_e7(43.5615), 435_615_000);
        assert_eq!(deg_to_e7(1e300), i32::MAX);
        assert_eq!(deg_to_e7(f64::NAN), 0);
        assert!((e7_to_deg(deg_to_e7(-122.123_456_7)) + 122.123_456_7).abs() < 1e-7);
    }
}
