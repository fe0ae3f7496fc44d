//! The dispatch experiment (src/executive/src/dispatch/experiment) on a few seeds: every uploaded goal ends achieved,
//! rejected or pending (the counts add up), runs are reproducible per seed, and the policies differ.

use mavtempo::experiment::{run, ExperimentOptions};

#[test]
fn counts_add_up_and_runs_repeat() {
    let opts = ExperimentOptions {
        seeds: 2,
        per_hour: 0.5,
        ..ExperimentOptions::default()
    };
    let mut calls = 0;
    let rows = run(&opts, &mut |done, total| {
        calls += 1;
        assert!(done <= total);
    })
    .expect("scenarios plan");
    assert_eq!(rows.len(), 2 * 3, "auv and shopping under three policies");
    assert_eq!(calls, 2 * 3 * 2);
    for r in &rows {
        assert!(r.arrived > 0, "{r:?}");
        assert_eq!(r.arrived, r.achieved + r.rejected + r.pending, "{r:?}");
        assert_eq!(
            r.rejected,
            r.rejected_reasons.values().sum::<u64>(),
            "{r:?}"
        );
        assert_eq!(r.mission_goals, 2 * 2, "two goals per mission file");
        assert!(r.distance_km > 0.0 && r.wasted_km <= r.distance_km, "{r:?}");
        let json = serde_json::to_value(r).expect("serialises");
        for key in [
            "scenario", "policy", "arrived", "achieved", "rejected", "pending",
        ] {
            assert!(json.get(key).is_some(), "{key}");
        }
    }
    let again = run(&opts, &mut |_, _| {}).expect("scenarios plan");
    let key = |r: &mavtempo::experiment::Row| {
        (
            r.arrived,
            r.achieved,
            r.rejected,
            r.pending,
            r.distance_km.to_bits(),
        )
    };
    assert_eq!(
        rows.iter().map(key).collect::<Vec<_>>(),
        again.iter().map(key).collect::<Vec<_>>(),
        "same seeds, same results"
    );
    // Dispatching differently moves the vehicle differently.
    let auv: Vec<_> = rows.iter().filter(|r| r.scenario == "auv").collect();
    assert!(
        auv.windows(2).any(|w| w[0].idle_h != w[1].idle_h),
        "{auv:?}"
    );
}
