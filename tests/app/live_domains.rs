//! Every shipped domain runs live: the AUV's vents mission (domains/auv) with its shipped configuration
//! (config/sitl-auv.toml) and scenario (sitl/scenarios/vents.toml) against the built-in SITL AUV, over real
//! sockets, stepped — through the same code as the rover's demo. (The rover's Fig. 2 and Dala runs are
//! tests/cli/cli_demo.rs, tests/app/demo_deterministic.rs and `bench cpu`'s test; Dala's two repairs are asserted here.)

use std::collections::BTreeMap;
use std::path::PathBuf;

use crate::support::live_run;

use mavtempo::cli::demo::{run_demo, DemoSetup};
use mavtempo::exec::executive::Fate;
use mavtempo::exec::mission::MissionEnd;
use mavtempo::exec::trace::TraceEvent;

#[test]
fn the_auv_samples_vent2_and_is_back_at_the_surface() {
    let setup = DemoSetup {
        problem: Some(PathBuf::from("domains/auv/problems/vents.ixt")),
        domain: Some(PathBuf::from("domains/auv/auv.ixt")),
        config: Some(PathBuf::from("config/sitl-auv.toml")),
        vehicle: sitl::VehicleKind::Auv,
        ..DemoSetup::default()
    };
    let mut said = Vec::new();
    let run = run_demo(&setup, &mut |l: &str| said.push(l.to_string()), &mut |_| {})
        .unwrap_or_else(|e| panic!("vents: {e}"));
    assert!(
        said.iter().any(|l| l.contains("sitl/scenarios/vents.toml")),
        "{said:?}"
    );
    let r = &run.report;
    assert_eq!(r.end, MissionEnd::Finished, "{:?}", r.goals);
    let fates: BTreeMap<&str, &Fate> = r.goals.iter().map(|g| (g.name.as_str(), &g.fate)).collect();
    assert_eq!(
        fates.get("sample_vent2"),
        Some(&&Fate::Achieved),
        "{:?}",
        r.goals
    );
    assert_eq!(
        fates.get("at_surface"),
        Some(&&Fate::Achieved),
        "{:?}",
        r.goals
    );
    let launched = live_run::launched(r.cycles.iter().flat_map(|c| &c.events));
    // Down past vent1 to vent2, survey, sample, and back up the same way; nothing launched twice.
    for a in [
        "go(surface, vent1)",
        "survey(vent2)",
        "sample(vent2)",
        "go(vent1, surface)",
    ] {
        assert_eq!(
            launched.iter().filter(|&&x| x == a).count(),
            1,
            "{a} in {launched:?}"
        );
    }
    // The surface goal holds at 20:00, twelve hours after the 08:00 start.
    assert!(r.duration_ms >= 12 * 3_600_000, "{}", r.duration_ms);
}

/// Seed 1 §5 on the SITL (stepped, over sockets): the paper's two execution events each end in a plan repair
/// — the slow move(l0, l1) stopped late-preemptively and repaired, then the picture that ends before its
/// model's 5 s minimum with a smaller image (sitl/scenarios/dala.toml), integrated as too early and its
/// storage over-production repaired — and every goal is achieved without a complete replanning.
#[test]
fn dala_shows_the_papers_two_repairs_on_the_sitl() {
    use mavtempo::exec::report_timing::Timing;
    use mavtempo::exec::resource_report::LevelVerdict;
    let setup = DemoSetup {
        problem: Some(PathBuf::from("domains/rover/problems/dala.ixt")),
        ..DemoSetup::default()
    };
    let run =
        run_demo(&setup, &mut |_: &str| {}, &mut |_| {}).unwrap_or_else(|e| panic!("dala: {e}"));
    let r = &run.report;
    assert_eq!(r.end, MissionEnd::Finished, "{:?}", r.goals);
    assert!(
        r.goals.iter().all(|g| g.fate == Fate::Achieved),
        "{:?}",
        r.goals
    );
    assert_eq!(r.counters.replans, 0);
    // The cycle of each event, and whether a repair finished there or within the next few cycles.
    let cycles: Vec<(u64, &Vec<TraceEvent>)> =
        r.cycles.iter().map(|c| (c.index, &c.events)).collect();
    let at = |what: &str, f: &dyn Fn(&TraceEvent) -> bool| -> u64 {
        cycles
            .iter()
            .find(|(_, ev)| ev.iter().any(f))
            .unwrap_or_else(|| panic!("no {what}"))
            .0
    };
    let repaired_from = |i: u64| {
        cycles
            .iter()
            .filter(|(j, _)| *j >= i)
            .take(6)
            .any(|(_, ev)| {
                ev.iter()
                    .any(|e| matches!(e, TraceEvent::RepairDone { .. }))
            })
    };
    let stopped = at(
        "stopped move",
        &|e| matches!(e, TraceEvent::Report { action, .. } if action == "move(l0, l1)"),
    );
    assert!(repaired_from(stopped), "no repair after the stopped move");
    let early = at("too-early picture", &|e| {
        matches!(e, TraceEvent::Report { action, timing: Timing::TooEarly, .. }
            if action.starts_with("take_picture"))
    });
    assert!(cycles.iter().any(|(j, ev)| *j == early
        && ev.iter().any(|e| matches!(e, TraceEvent::Level { resource, verdict: LevelVerdict::OverProduction { .. }, .. }
            if resource == "STORAGE"))));
    assert!(
        early > stopped && repaired_from(early),
        "no repair after the short picture"
    );
    assert!(r.counters.repairs >= 2, "{:?}", r.counters);
}
