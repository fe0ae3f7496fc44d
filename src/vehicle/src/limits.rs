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
}

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
    /// Polygons the vehicle must stay in: the configuration's, the autopilot's fence.
    areas: Vec<(&'static str, Vec<(f64, f64)>)>,
    /// Circles (centre east, north; radius) it must stay in: the autopilot's circular fences.
    circles: Vec<((f64, f64), f64)>,
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

    /// An inclusion polygon (`[lat, lon]` corners), e.g. the autopilot's fence.
    pub fn add_polygon(&mut self, what: &'static str, corners: &[[f64; 2]]) {
        let local = corners
            .iter()
            .map(|[lat, lon]| {
                let p = self.home.to_local(*lat, *lon, self.home.alt);
                (p.east, p.north)
            })
            .collect();
        self.areas.push((what, local));
    }

    /// An inclusion circle, e.g. the autopilot's circular fence.
    pub fn add_circle(&mut self, lat: f64, lon: f64, radius_m: f64) {
        let c = self.home.to_local(lat, lon, self.home.alt);
        self.circles.push(((c.east, c.north), radius_m));
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
        for (what, poly) in &self.areas {
            if !inside(poly, (at.east, at.north)) {
                return Err(LimitViolation::Outside { what, distance_m });
            }
        }
        for &((e, n), r) in &self.circles {
            if (at.east - e).hypot(at.north - n) > r {
                return Err(LimitViolation::Outside {
                    what: "autopilot's fence",
                    distance_m,
                });
            }
        }
        Ok(())
    }
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
mod tests {
    use super::*;

    const HOME: Home = Home {
        lat: 43.5616,
        lon: 1.4847,
        alt: 0.0,
    };

    #[test]
    fn a_place_beyond_the_range_is_refused_with_the_distance_and_the_limit() {
        let l = Limits::from_config(
            &LimitsConfig {
                max_range_m: Some(500.0),
                polygon: None,
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
    fn bad_limits_are_named() {
        let bad = LimitsConfig {
            max_range_m: Some(-1.0),
            polygon: None,
        };
        assert_eq!(bad.invalid().map(|(k, _)| k), Some("limits.max_range_m"));
        let two = LimitsConfig {
            max_range_m: None,
            polygon: Some(vec![[43.0, 1.0], [43.1, 1.0]]),
        };
        assert_eq!(two.invalid().map(|(k, _)| k), Some("limits.polygon"));
        assert!(Limits::from_config(&LimitsConfig::default(), HOME).is_none());
    }
}
