//! Issue 30 item 7: each resource's resolution and tolerance come from the vehicle configuration's
//! `[resources]` (one rule for `demo`, `soak` and `run`, `ResourceNames::level_tolerance`). A battery
//! that ticks between 1 % below the plan and the plan's level — a reading in whole percents — is noise:
//! no over-consumption, no repair; the same readings with no resolution declared are news.

use crate::support::rover_mock;

use mavtempo_executive::exec::mission::MissionReport;
use mavtempo_executive::exec::resource_report::LevelVerdict;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_vehicle::config::{ResourceNames, VehicleConfig};
use mavtempo_vehicle::mock::Scripted;
use mavtempo_vehicle::ResourceLevel;
use rover_mock::*;

/// rover_two's mission: its first move, base → p1 (10.8 m at 0.5 %/m), brings the plan's battery to
/// 84.61 %; during it the battery is read in whole percents, 84 % and 85 % in turn, every 2 s for 12 s.
fn ticking(resources: Option<&ResourceNames>) -> MissionReport {
    let mut ex = executive();
    if let Some(r) = resources {
        ex = ex.with_resource_levels(r);
    }
    let mut v = moving_rover();
    let mut first = true;
    run(&mut ex, &mut v, move |v, at, task| {
        if task == "move" && first {
            first = false;
            for k in 1..=6u64 {
                let level = if k % 2 == 1 { 84.0 } else { 85.0 };
                v.at(
                    at + 2_000 * k,
                    Scripted::Resource(ResourceLevel {
                        resource: "BATTERY".into(),
                        level,
                    }),
                );
            }
        }
    })
}

/// The battery's verdicts and the repairs while it ticks (the first 14 s).
fn while_ticking(r: &MissionReport) -> (Vec<LevelVerdict>, usize) {
    let ev: Vec<TraceEvent> = events(r)
        .into_iter()
        .filter(|(t, _)| *t <= 14_000)
        .map(|(_, e)| e)
        .collect();
    let repairs = ev
        .iter()
        .filter(|e| e.line().starts_with("plan repaired"))
        .count();
    let verdicts = ev
        .into_iter()
        .filter_map(|e| match e {
            TraceEvent::Level {
                resource, verdict, ..
            } if resource == "BATTERY" => Some(verdict),
            _ => None,
        })
        .collect();
    (verdicts, repairs)
}

#[test]
fn battery_readings_within_the_resolution_cause_no_repair() {
    // `battery = "BATTERY"` and nothing else: the default resolution, a whole percent.
    let resources = ResourceNames {
        battery: Some("BATTERY".into()),
        ..ResourceNames::default()
    };
    // (Levels found consistent are not traced: only news is.)
    let (verdicts, repairs) = while_ticking(&ticking(Some(&resources)));
    assert_eq!(verdicts, Vec::new());
    assert_eq!(repairs, 0);

    // The same readings with no resolution (1e-6, the executive's own): each is news, repaired.
    let (verdicts, repairs) = while_ticking(&ticking(None));
    let news = verdicts
        .iter()
        .filter(|v| !matches!(v, LevelVerdict::Consistent))
        .count();
    assert!(news >= 1, "{verdicts:?}");
    assert!(repairs >= 1, "{repairs}");
}

#[test]
fn the_default_battery_resolution_is_a_whole_percent() {
    let text = "[link]\naddress = \"tcpout:127.0.0.1:5760\"\n[home]\nlat = 43.5\nlon = 1.4\n[modes]\nhold = 4\nauto = 10\nrtl = 11\nguided = 15\n[resources]\nbattery = \"BATTERY\"\nstorage = \"STORAGE\"\n";
    let cfg = VehicleConfig::parse(text, "t").expect("config");
    assert_eq!(cfg.resources.level_tolerance("BATTERY"), Some(1.0));
    assert_eq!(cfg.resources.level_tolerance("STORAGE"), Some(0.0));
    assert_eq!(cfg.resources.level_tolerance("OTHER"), None);
    let bad = format!("{text}battery_tolerance = -1\n");
    let e = VehicleConfig::parse(&bad, "t").expect_err("refused");
    assert!(e.to_string().contains("resources.battery_tolerance"), "{e}");
}
