//! A mission of one's own on the built-in simulator without a scenario runs in the nominal world, which
//! follows the domain and the configuration (src/cli/nominal_world.rs): fault-free, it needs no repair, no
//! replanning, and every action ends within its planned bounds. Counted from the `--report` JSON, as a
//! user would read it.

use crate::support::demo_report;

use std::path::Path;

use demo_report::events;

fn demo(args: &[&str], problem: &Path) -> serde_json::Value {
    let problem = problem.to_str().expect("UTF-8 path");
    let mut all = vec!["--quiet", "--no-upload", "--problem", problem];
    all.extend_from_slice(args);
    let (stdout, report) = demo_report::demo_with_report(&all);
    assert!(stdout.contains("nominal world"), "{stdout}");
    report
}

fn assert_clean(report: &serde_json::Value, goals: usize) {
    let counters = &report["counters"];
    assert_eq!(counters["repairs"], 0, "{counters}");
    assert_eq!(counters["replans"], 0, "{counters}");
    let changes = report["plan_changes"].as_array().map_or(0, |c| c.len());
    assert_eq!(changes, 0, "{}", report["plan_changes"]);
    let fates: Vec<&str> = report["goals"]
        .as_array()
        .expect("goals")
        .iter()
        .filter_map(|g| g["fate"].as_str())
        .collect();
    assert_eq!(fates, vec!["achieved"; goals]);
    let reports: Vec<serde_json::Value> = events(report)
        .into_iter()
        .filter(|e| e["kind"] == "report")
        .collect();
    assert!(!reports.is_empty());
    for r in &reports {
        assert_eq!(r["status"], "nominal", "{r}");
    }
}

/// The first-mission guide's problem on the generic vehicle domain (docs/first-mission.md).
#[test]
fn the_first_mission_runs_clean_on_the_nominal_world() {
    let report = demo(
        &[
            "--domain",
            "domains/vehicle/vehicle.ixt",
            "--config",
            "config/sitl-vehicle.toml",
        ],
        Path::new("domains/vehicle/problems/first.ixt"),
    );
    assert_clean(&report, 4);
    for e in events(&report).iter().filter(|e| e["kind"] == "report") {
        assert_eq!(e["timing"], "InBounds", "{e}");
    }
}

/// A copy of the rover's Fig. 2 problem (so no scenario of its name): five pictures and a download, clean.
#[test]
fn a_copied_rover_problem_runs_clean_on_the_nominal_world() {
    let dir = tempfile::TempDir::new().expect("temp dir");
    let mine = dir.path().join("my.ixt");
    std::fs::copy("domains/rover/problems/fig2.ixt", &mine).expect("copy");
    let report = demo(&[], &mine);
    assert_clean(&report, 5);
}
