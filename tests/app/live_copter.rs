//! A copter mission end to end on the built-in SITL copter, over real sockets, stepped: domains/copter's
//! survey problem with config/sitl-copter.toml and sitl/scenarios/survey.toml (a headwind over the mast),
//! and a picture goal at 25 m uploaded by a ground station during the flight (config/goals/copter.plan).
//! The copter takes off, takes its pictures at altitude, hovers over the field, returns and lands with the
//! battery above its 25 % reserve all along. The same mission with config/px4-copter.toml against the
//! SITL's PX4 profile (tests/fixtures/exec/px4-copter.toml), as on a real PX4 SIH quadrotor.

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::support::live_run;

use mavtempo::cli::demo::{run_demo, DemoRun, DemoSetup, TimedUpload, UploadItems};
use mavtempo::exec::executive::Fate;
use mavtempo::exec::mission::MissionEnd;
use mavtempo::exec::trace::TraceEvent;

/// The survey mission with `config`, in `scenario` (the problem's own when `None`), the copter.plan
/// picture uploaded at 40 s.
fn survey(config: &str, scenario: Option<&str>) -> (DemoRun, Vec<String>) {
    let setup = DemoSetup {
        problem: Some(PathBuf::from("domains/copter/problems/survey.ixt")),
        domain: Some(PathBuf::from("domains/copter/copter.ixt")),
        config: Some(PathBuf::from(config)),
        scenario: scenario.map(PathBuf::from),
        vehicle: sitl::VehicleKind::Copter,
        upload: false,
        timed_upload: Some(TimedUpload {
            at_ms: 40_000,
            items: UploadItems::File(PathBuf::from("config/goals/copter.plan")),
        }),
        ..DemoSetup::default()
    };
    let mut said = Vec::new();
    let run = run_demo(&setup, &mut |l: &str| said.push(l.to_string()), &mut |_| {})
        .unwrap_or_else(|e| panic!("survey with {config}: {e}"));
    (run, said)
}

#[test]
fn the_copter_takes_its_pictures_at_altitude_and_lands_home_within_its_reserve() {
    let (run, said) = survey("config/sitl-copter.toml", None);
    assert!(
        said.iter()
            .any(|l| l.contains("sitl/scenarios/survey.toml")),
        "{said:?}"
    );
    assert_flown_within_the_reserve(&run);
}

#[test]
fn on_the_px4_profile_the_copter_waits_at_rest_takes_off_and_px4s_own_loiter_is_no_takeover() {
    let (run, _) = survey(
        "config/px4-copter.toml",
        Some("tests/fixtures/exec/px4-copter.toml"),
    );
    // Ready on the ground, disarmed, with PX4's at-rest estimator flags (CONST_POS_MODE and a fused
    // absolute position): no ARM before the takeoff.
    let ready = run.ready.as_ref().expect("the run waited for readiness");
    assert!(ready.ready, "{ready:?}");
    assert_eq!(ready.arm_attempts, 0, "{ready:?}");
    // PX4's AUTO.TAKEOFF, then its own AUTO.LOITER: the companion never yields.
    let events: Vec<&TraceEvent> = run.report.cycles.iter().flat_map(|c| &c.events).collect();
    assert!(
        !events
            .iter()
            .any(|e| matches!(e, TraceEvent::Paused { .. })),
        "{events:?}"
    );
    assert_flown_within_the_reserve(&run);
}

/// Every goal achieved (the uploaded one too), two pictures taken, one return, the battery reservoir never
/// below 0 and the copter back home.
fn assert_flown_within_the_reserve(run: &DemoRun) {
    let r = &run.report;
    assert_eq!(r.end, MissionEnd::Finished, "{:?}", r.goals);
    let fates: BTreeMap<&str, &Fate> = r.goals.iter().map(|g| (g.name.as_str(), &g.fate)).collect();
    for g in ["picture_mast", "survey_field", "back_home"] {
        assert_eq!(fates.get(g), Some(&&Fate::Achieved), "{g}: {:?}", r.goals);
    }
    // The uploaded goal: one more, achieved.
    assert_eq!(r.goals.len(), 4, "{:?}", r.goals);
    assert!(
        r.goals.iter().all(|g| g.fate == Fate::Achieved),
        "{:?}",
        r.goals
    );
    // The actions launched, in order.
    let launched = live_run::launched(r.cycles.iter().flat_map(|c| &c.events));
    assert_eq!(launched.first(), Some(&"takeoff(home)"), "{launched:?}");
    assert_eq!(
        launched
            .iter()
            .filter(|a| a.starts_with("take_picture"))
            .count(),
        2,
        "{launched:?}"
    );
    assert_eq!(
        launched
            .iter()
            .filter(|a| a.starts_with("return_home"))
            .count(),
        1,
        "{launched:?}"
    );
    // The battery reservoir (the charge above the reserve) reported never below 0.
    let battery: Vec<f64> = r
        .resources
        .iter()
        .filter(|s| s.resource == "BATTERY")
        .filter_map(|s| s.reported)
        .collect();
    assert!(!battery.is_empty());
    let lowest = battery.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(lowest >= 0.0, "went {lowest} below the reserve");
    // Back home: the last point of the track is within the return's acceptance radius.
    let last = r.track.last().expect("a track");
    assert!(last.east.hypot(last.north) <= 3.0, "{last:?}");
}
