//! One Earth model (WGS-84) for the planner, the vehicle layer and the SITL: the planner's distance between
//! two located objects of a problem is the distance the vehicle layer measures between the same two points,
//! and locations round-trip through lat/lon to the millimetre.

use mavtempo_temporal::lang::{parse_domain, parse_problem};
use mavtempo_temporal::model::Problem;
use mavtempo_vehicle::geo::Home;
use mavtempo_vehicle::Enu;
use proptest::prelude::*;

const DOMAIN: &str = include_str!(repo!("domains/rover/rover.ixt"));

/// A rover problem with a geographic home and two objects given in lat/lon/alt.
fn problem(home: (f64, f64, f64), a: (f64, f64, f64), b: (f64, f64, f64)) -> Problem {
    let domain = parse_domain("rover.ixt", DOMAIN).expect("rover domain");
    let text = format!(
        "problem geo;\ndomain rover;\nhorizon 30min;\nhome lat {} lon {} alt {};\n\
         object a: location at lat {} lon {} alt {};\nobject b: location at lat {} lon {} alt {};\n",
        home.0, home.1, home.2, a.0, a.1, a.2, b.0, b.1, b.2
    );
    parse_problem("geo.ixt", &text, &domain).expect("problem parses")
}

/// A point about `east`, `north` metres from (lat, lon), placed with a mean-Earth degree (on purpose not
/// the shared model: the test needs points, not the model's answer).
fn offset(lat: f64, lon: f64, east: f64, north: f64) -> (f64, f64) {
    let m_per_deg = 111_000.0;
    (
        lat + north / m_per_deg,
        lon + east / (m_per_deg * lat.to_radians().cos()),
    )
}

fn dist(a: Enu, b: Enu) -> f64 {
    ((a.east - b.east).powi(2) + (a.north - b.north).powi(2) + (a.up - b.up).powi(2)).sqrt()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn planner_distance_is_the_vehicle_distance(
        lat in -70.0f64..70.0, lon in -179.0f64..179.0, alt in 0.0f64..2000.0,
        ea in -30_000.0f64..30_000.0, na in -30_000.0f64..30_000.0,
        eb in -30_000.0f64..30_000.0, nb in -30_000.0f64..30_000.0,
        ua in -50.0f64..50.0, ub in -50.0f64..50.0,
    ) {
        let (la, oa) = offset(lat, lon, ea, na);
        let (lb, ob) = offset(lat, lon, eb, nb);
        let p = problem((lat, lon, alt), (la, oa, alt + ua), (lb, ob, alt + ub));
        let (a, b) = (
            p.object_id("a").expect("a"),
            p.object_id("b").expect("b"),
        );
        let planner = p.distance(a, b).expect("both located");
        let home = Home { lat, lon, alt };
        let vehicle = dist(home.to_local(la, oa, alt + ua), home.to_local(lb, ob, alt + ub));
        prop_assert!((planner - vehicle).abs() < 1e-6, "planner {planner} m, vehicle {vehicle} m");
        // What the executive sends the vehicle for `a` (Object::local) is where the vehicle puts it back.
        let (e, n, u) = p.objects[a.index()].local(p.home.as_ref()).expect("located");
        let (glat, glon, galt) = home.to_global(Enu::new(e, n, u));
        let back = home.to_local(glat, glon, galt);
        prop_assert!(dist(back, Enu::new(e, n, u)) < 1e-3);
        prop_assert!(dist(home.to_local(la, oa, alt + ua), Enu::new(e, n, u)) < 1e-6);
    }
}

#[test]
fn a_kilometre_north_is_a_kilometre_for_both() {
    // 1 km north of LAAS on the WGS-84 meridian radius (6,365.77 km at 43.56°): not the 6,371 km sphere the
    // planner used to assume (a 0.08 % gap: 0.8 m per km).
    let dlat = (1_000.0f64 / 6_365_770.5).to_degrees();
    let p = problem(
        (43.56, 1.48, 0.0),
        (43.56, 1.48, 0.0),
        (43.56 + dlat, 1.48, 0.0),
    );
    let d = p
        .distance(p.object_id("a").expect("a"), p.object_id("b").expect("b"))
        .expect("located");
    assert!((d - 1_000.0).abs() < 0.01, "{d}");
}
