//! Where the vehicle may go (`[limits]` of the vehicle configuration): a maximum range from home and,
//! optionally, a polygon the vehicle must stay in. A goal outside is rejected at intake, at once, with the
//! distance and the limit in the operator's words ("2.1 km from home, beyond the 500 m range"). One check,
//! [`Limits::check`], for every caller.

use serde::Deserialize;

use super::geo::Home;
use super::types::Enu;

/// `[limits]` as written.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitsConfig {
    /// Metres from home.
    pub max_range_m: Option<f64>,
    /// `[[lat, lon], …]`, at least 3 corners: the vehicle stays inside.
    pub polygon: Option<Vec<[f64; 2]>>,
    /// Read the autopilot's fence at readiness and keep to it too (src/vehicle/src/fence.rs); default true.
    pub autopilot_fence: Option<bool>,
}

impl LimitsConfig {
    /// Why the table cannot be used: the key and the reason.
    pub fn invalid(&self) -> Option<(&'static str, String)> {
        if let Some(r) = self.max_range_m {
            if !(r.is_finite() && r > 0.0) {
                return Some(("limits.max_range_m", "must be a distance > 0 m".into()));
            }
        }
        if let Some(p) = &self.polygon {
            if p.len() < 3 {
                return Some((
                    "limits.polygon",
                    "needs at least 3 corners [lat, lon]".into(),
                ));
            }
            let bad = p.iter().find(|[lat, lon]| {
                !((-90.0..=90.0).contains(lat) && (-180.0..=180.0).contains(lon))
            });
            if let Some([lat, lon]) = bad {
                return Some((
                    "limits.polygon",
                    format!("corner {lat}, {lon} is not a latitude, longitude in degrees"),
                ));
            }
        }
        None
    }
}

/// Why a place is out of bounds, in the operator's words.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LimitViolation {
    #[error("{} from home, beyond the {} range", distance(*distance_m), distance(*max_m))]
    BeyondRange { distance_m: f64, max_m: f64 },
    #[error("outside the {what} ({} from home)", distance(*distance_m))]
    Outside { what: &'static str, distance_m: f64 },
    #[error("inside an exclusion zone of the {what} ({} from home)", distance(*distance_m))]
    Inside { what: &'static str, distance_m: f64 },
    #[error("the straight way there crosses the edge of the {what}")]
    Crosses { what: &'static str },
}

/// The autopilot's fence, as the operator reads it.
pub const AUTOPILOT_FENCE: &str = "autopilot's fence";

/// `850 m`, `2.1 km`, `3,000 km`.
fn distance(m: f64) -> String {
    if m < 1_000.0 {
        format!("{m:.0} m")
    } else if m < 100_000.0 {
        format!("{:.1} km", m / 1_000.0)
    } else {
        let km = (m / 1_000.0).round() as u64;
        let s = km.to_string();
        let mut out = String::new();
        for (i, c) in s.chars().enumerate() {
            if i > 0 && (s.len() - i).is_multiple_of(3) {
                out.push(',');
            }
            out.push(c);
        }
        format!("{out} km")
    }
}

/// The limits in metres from home (east, north).
#[derive(Debug, Clone, PartialEq)]
pub struct Limits {
    home: Home,
    max_range_m: Option<f64>,
    /// Polygons the vehicle must stay in (inclusion) or out of: the configuration's, the autopilot's fence.
    areas: Vec<Area>,
    /// Circles (centre east, north; radius) it must stay in or out of: the autopilot's circular fences.
    circles: Vec<Circle>,
}

#[derive(Debug, Clone, PartialEq)]
struct Area {
    what: &'static str,
    inclusion: bool,
    corners: Vec<(f64, f64)>,
}

#[derive(Debug, Clone, PartialEq)]
struct Circle {
    what: &'static str,
    inclusion: bool,
    centre: (f64, f64),
    radius_m: f64,
}

impl Limits {
    /// The configuration's limits, none when it sets none.
    pub fn from_config(cfg: &LimitsConfig, home: Home) -> Option<Limits> {
        let mut l = Limits {
            home,
            max_range_m: cfg.max_range_m,
            areas: Vec::new(),
            circles: Vec::new(),
        };
        if let Some(p) = &cfg.polygon {
            l.add_polygon("operating area", p);
        }
        (!l.is_empty()).then_some(l)
    }

    /// No limit at all.
    pub fn none(home: Home) -> Limits {
        Limits {
            home,
            max_range_m: None,
            areas: Vec::new(),
            circles: Vec::new(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.max_range_m.is_none() && self.areas.is_empty() && self.circles.is_empty()
    }

    /// The home distances are measured from.
    pub fn home(&self) -> Home {
        self.home
    }

    /// An inclusion polygon (`[lat, lon]` corners), e.g. the autopilot's fence.
    pub fn add_polygon(&mut self, what: &'static str, corners: &[[f64; 2]]) {
        self.add_area(what, true, corners);
    }

    /// A polygon (`[lat, lon]` corners) the vehicle stays in (`inclusion`) or out of.
    pub fn add_area(&mut self, what: &'static str, inclusion: bool, corners: &[[f64; 2]]) {
        let corners = corners
            .iter()
            .map(|[lat, lon]| {
                let p = self.home.to_local(*lat, *lon, self.home.alt);
                (p.east, p.north)
            })
            .collect();
        self.areas.push(Area {
            what,
            inclusion,
            corners,
        });
    }

    /// An inclusion circle, e.g. the autopilot's circular fence.
    pub fn add_circle(&mut self, lat: f64, lon: f64, radius_m: f64) {
        self.add_disc(AUTOPILOT_FENCE, true, lat, lon, radius_m);
    }

    /// A circle the vehicle stays in (`inclusion`) or out of.
    pub fn add_disc(&mut self, what: &'static str, inclusion: bool, lat: f64, lon: f64, r: f64) {
        let c = self.home.to_local(lat, lon, self.home.alt);
        self.circles.push(Circle {
            what,
            inclusion,
            centre: (c.east, c.north),
            radius_m: r,
        });
    }

    /// Whether the place at `lat, lon` is within every limit.
    pub fn check(&self, lat: f64, lon: f64) -> Result<(), LimitViolation> {
        self.check_local(self.home.to_local(lat, lon, self.home.alt))
    }

    /// [`Self::check`] of a place in metres from home.
    pub fn check_local(&self, at: Enu) -> Result<(), LimitViolation> {
        let distance_m = at.east.hypot(at.north);
        if let Some(max_m) = self.max_range_m {
            if distance_m > max_m {
                return Err(LimitViolation::BeyondRange { distance_m, max_m });
            }
        }
        let p = (at.east, at.north);
        for a in &self.areas {
            if inside(&a.corners, p) != a.inclusion {
                return Err(zone_violation(a.what, a.inclusion, distance_m));
            }
        }
        for c in &self.circles {
            let d = (p.0 - c.centre.0).hypot(p.1 - c.centre.1);
            if (d <= c.radius_m) != c.inclusion {
                return Err(zone_violation(c.what, c.inclusion, distance_m));
            }
        }
        Ok(())
    }

    /// Whether the straight leg from `a` to `b` stays within every limit: both ends within, and the leg
    /// crosses no polygon's edge and passes through no exclusion circle (the range and inclusion circles
    /// are convex: their ends suffice).
    pub fn check_leg(&self, a: Enu, b: Enu) -> Result<(), LimitViolation> {
        self.check_local(a)?;
        self.check_local(b)?;
        let (p, q) = ((a.east, a.north), (b.east, b.north));
        for area in &self.areas {
            let n = area.corners.len();
            let crosses =
                (0..n).any(|i| segments_cross(p, q, area.corners[i], area.corners[(i + 1) % n]));
            if crosses {
                return Err(LimitViolation::Crosses { what: area.what });
            }
        }
        for c in self.circles.iter().filter(|c| !c.inclusion) {
            if segment_distance(p, q, c.centre) <= c.radius_m {
                return Err(LimitViolation::Crosses { what: c.what });
            }
        }
        Ok(())
    }
}

fn zone_violation(what: &'static str, inclusion: bool, distance_m: f64) -> LimitViolation {
    if inclusion {
        LimitViolation::Outside { what, distance_m }
    } else {
        LimitViolation::Inside { what, distance_m }
    }
}

/// Whether segments `pq` and `rs` properly cross (touching at an end does not count).
fn segments_cross(p: (f64, f64), q: (f64, f64), r: (f64, f64), s: (f64, f64)) -> bool {
    let side = |a: (f64, f64), b: (f64, f64), c: (f64, f64)| {
        (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
    };
    let (d1, d2) = (side(r, s, p), side(r, s, q));
    let (d3, d4) = (side(p, q, r), side(p, q, s));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// Distance from `c` to the segment `pq`.
fn segment_distance(p: (f64, f64), q: (f64, f64), c: (f64, f64)) -> f64 {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((c.0 - p.0) * dx + (c.1 - p.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 + t * dx - c.0).hypot(p.1 + t * dy - c.1)
}

/// Even-odd ray casting.
fn inside(poly: &[(f64, f64)], (x, y): (f64, f64)) -> bool {
    let mut inside = false;
    let mut j = poly.len().saturating_sub(1);
    for i in 0..poly.len() {
        let ((xi, yi), (xj, yj)) = (poly[i], poly[j]);
        if (yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi {
            inside = !inside;
        }
        j = i;
    }
    inside
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A home for the tests of limits and fences.
    pub(crate) const HOME: Home = Home {
        lat: 43.5616,
        lon: 1.4847,
        alt: 0.0,
    };

    #[test]
    fn a_place_beyond_the_range_is_refused_with_the_distance_and_the_limit() {
        let l = Limits::from_config(
            &LimitsConfig {
                max_range_m: Some(500.0),
                ..LimitsConfig::default()
            },
            HOME,
        )
        .expect("limits");
        assert_eq!(l.check_local(Enu::new(300.0, 300.0, 0.0)), Ok(()));
        let far = l.check_local(Enu::new(2_100.0, 0.0, 0.0)).expect_err("far");
        assert_eq!(far.to_string(), "2.1 km from home, beyond the 500 m range");
        let very = l
            .check_local(Enu::new(3_000_000.0, 0.0, 0.0))
            .expect_err("very far");
        assert_eq!(
            very.to_string(),
            "3,000 km from home, beyond the 500 m range"
        );
        let (lat, lon, _) = HOME.to_global(Enu::new(0.0, 600.0, 0.0));
        assert!(l.check(lat, lon).is_err());
    }

    #[test]
    fn a_polygon_and_a_circle_keep_the_vehicle_inside() {
        let corner = |e: f64, n: f64| {
            let (lat, lon, _) = HOME.to_global(Enu::new(e, n, 0.0));
            [lat, lon]
        };
        let cfg = LimitsConfig {
            autopilot_fence: None,
            max_range_m: None,
            polygon: Some(vec![
                corner(-100.0, -100.0),
                corner(100.0, -100.0),
                corner(100.0, 100.0),
                corner(-100.0, 100.0),
            ]),
        };
        assert_eq!(cfg.invalid(), None);
        let mut l = Limits::from_config(&cfg, HOME).expect("limits");
        assert_eq!(l.check_local(Enu::new(50.0, -50.0, 0.0)), Ok(()));
        let out = l.check_local(Enu::new(150.0, 0.0, 0.0)).expect_err("out");
        assert_eq!(
            out.to_string(),
            "outside the operating area (150 m from home)"
        );
        let (lat, lon, _) = HOME.to_global(Enu::new(0.0, 0.0, 0.0));
        l.add_circle(lat, lon, 60.0);
        assert!(l.check_local(Enu::new(50.0, -50.0, 0.0)).is_err());
        assert_eq!(l.check_local(Enu::new(30.0, 0.0, 0.0)), Ok(()));
    }

    #[test]
    fn a_leg_through_an_exclusion_zone_or_across_a_concave_edge_is_refused() {
        let corner = |e: f64, n: f64| {
            let (lat, lon, _) = HOME.to_global(Enu::new(e, n, 0.0));
            [lat, lon]
        };
        let mut l = Limits::none(HOME);
        // A U-shaped inclusion area: its notch is between x = -10 and 10 above n = 0.
        l.add_area(
            AUTOPILOT_FENCE,
            true,
            &[
                corner(-50.0, -50.0),
                corner(50.0, -50.0),
                corner(50.0, 50.0),
                corner(10.0, 50.0),
                corner(10.0, 0.0),
                corner(-10.0, 0.0),
                corner(-10.0, 50.0),
                corner(-50.0, 50.0),
            ],
        );
        let (a, b) = (Enu::new(-30.0, 30.0, 0.0), Enu::new(30.0, 30.0, 0.0));
        assert_eq!(l.check_local(a), Ok(()));
        assert_eq!(l.check_local(b), Ok(()));
        assert_eq!(
            l.check_leg(a, b).map_err(|e| e.to_string()),
            Err("the straight way there crosses the edge of the autopilot's fence".into())
        );
        assert_eq!(l.check_leg(a, Enu::new(-30.0, -30.0, 0.0)), Ok(()));
        // An exclusion circle on the way south.
        let (lat, lon, _) = HOME.to_global(Enu::new(0.0, -30.0, 0.0));
        l.add_disc(AUTOPILOT_FENCE, false, lat, lon, 5.0);
        assert!(l
            .check_leg(Enu::new(-30.0, -30.0, 0.0), Enu::new(30.0, -30.0, 0.0))
            .is_err());
        assert_eq!(
            l.check_local(Enu::new(1.0, -30.0, 0.0))
                .map_err(|e| e.to_string()),
            Err("inside an exclusion zone of the autopilot's fence (30 m from home)".into())
        );
        assert_eq!(
            l.check_leg(Enu::new(-30.0, -40.0, 0.0), Enu::new(30.0, -40.0, 0.0)),
            Ok(())
        );
    }

    #[test]
    fn bad_limits_are_named() {
        let bad = LimitsConfig {
            max_range_m: Some(-1.0),
            ..LimitsConfig::default()
        };
        assert_eq!(bad.invalid().map(|(k, _)| k), Some("limits.max_range_m"));
        let two = LimitsConfig {
            polygon: Some(vec![[43.0, 1.0], [43.1, 1.0]]),
            ..LimitsConfig::default()
        };
        assert_eq!(two.invalid().map(|(k, _)| k), Some("limits.polygon"));
        assert!(Limits::from_config(&LimitsConfig::default(), HOME).is_none());
    }
}
