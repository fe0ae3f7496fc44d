//! Issue 15, as it was found: on Fig. 2 (the executive against the SITL rover over real sockets, stepped
//! by the executive's clock: deterministic), a ground station uploads a goal 500 m, 50 km or 3,000 km away,
//! or the shipped config/goals/example.plan (~560 m away), at t = 100 s. The goals already held end as in
//! the run without that upload, the far goals are rejected with the planner's reason (the ground station is
//! told), no running action is stopped, and the steps spent on them are bounded.

use mavtempo::cli::demo::{run_demo, DemoRun, DemoSetup, TimedUpload, UploadItems};
use mavtempo::exec::executive::Fate;
use mavtempo::exec::outcome::FateReason;
use mavtempo::exec::trace::TraceEvent;

/// Fig. 2 on the SITL without the story's g6/g7 upload; `upload` at 100 s if given.
fn fig2(upload: Option<UploadItems>) -> DemoRun {
    let setup = DemoSetup {
        upload: false,
        timed_upload: upload.map(|items| TimedUpload {
            at_ms: 100_000,
            items,
        }),
        ..DemoSetup::default()
    };
    run_demo(&setup, &mut |_| {}, &mut |_| {}).unwrap_or_else(|e| panic!("demo: {e}"))
}

/// The names of the actions that `pick` selects from the trace, in order.
fn actions(run: &DemoRun, pick: fn(&TraceEvent) -> Option<&String>) -> Vec<String> {
    run.report
        .cycles
        .iter()
        .flat_map(|c| c.events.iter().filter_map(pick).cloned())
        .collect()
}

fn launched(e: &TraceEvent) -> Option<&String> {
    match e {
        TraceEvent::Launch { action, .. } => Some(action),
        _ => None,
    }
}

fn stopped(e: &TraceEvent) -> Option<&String> {
    match e {
        TraceEvent::Stop { action, .. } => Some(action),
        _ => None,
    }
}

/// The upload at 100 s costs nothing to g1..g5 and its goals (`new`) are rejected with a reason.
fn costs_only_itself(base: &DemoRun, upload: UploadItems, new: &[&str]) {
    let what = format!("{upload:?}");
    let run = fig2(Some(upload));
    let (b, r) = (&base.report, &run.report);
    let held = |goals: &[mavtempo::exec::executive::GoalFate]| -> Vec<(String, Fate)> {
        goals
            .iter()
            .filter(|g| !new.contains(&g.name.as_str()))
            .map(|g| (g.name.clone(), g.fate.clone()))
            .collect()
    };
    assert_eq!(held(&r.goals), held(&b.goals), "{what}");
    assert_eq!(r.end, b.end, "{what}");
    for name in new {
        let g = r
            .goals
            .iter()
            .find(|g| g.name == *name)
            .unwrap_or_else(|| panic!("{what}: {name} not reported: {:?}", r.goals));
        assert_eq!(g.fate, Fate::Rejected, "{what}: {g:?}");
        // By its insertion's search, or at once when its last leg alone needs more than a full battery.
        assert!(
            matches!(
                &g.reason,
                Some(FateReason::InsertionFailed { .. } | FateReason::InsertionTimedOut { .. })
            ) || matches!(&g.reason, Some(FateReason::BeyondLimits { why })
                if why.starts_with("getting there needs")),
            "{what}: {g:?}"
        );
        // The ground station got the final verdict.
        let account = run.timed_upload.as_deref().unwrap_or("");
        assert!(
            account.contains("upload accepted") && account.contains(&format!("{name} rejected: ")),
            "{what}: {account}"
        );
    }
    // The same actions launched, the same (planned) stops, the same complete replannings: none caused by
    // the upload.
    assert_eq!(actions(&run, launched), actions(base, launched), "{what}");
    assert_eq!(actions(&run, stopped), actions(base, stopped), "{what}");
    assert_eq!(r.counters.replans, b.counters.replans, "{what}");
    // Bounded: each new goal at most `goal_insertion_cycles` cycles of μ·n steps (the demo's n = 300).
    let cfg = mavtempo::cli::demo::exec_config();
    let per_cycle = (cfg.repair_max_steps.unwrap_or(0) as f64 * cfg.repair_share).ceil() as u64;
    let bound = new.len() as u64 * u64::from(cfg.goal_insertion_cycles) * per_cycle;
    assert!(
        r.counters.insertion_steps <= bound,
        "{what}: {} insertion steps > {bound}",
        r.counters.insertion_steps
    );
}

#[test]
fn far_goals_uploaded_mid_mission_cost_only_themselves() {
    let base = fig2(None);
    assert!(base
        .report
        .goals
        .iter()
        .any(|g| g.name == "g1" && g.fate == Fate::Achieved));
    for place in [(500.0, 0.0), (50_000.0, 0.0), (0.0, 3_000_000.0)] {
        costs_only_itself(&base, UploadItems::PicturesAt(vec![place]), &["g6"]);
    }
}

#[test]
fn the_shipped_example_plan_uploaded_mid_mission_costs_only_itself() {
    let base = fig2(None);
    costs_only_itself(
        &base,
        UploadItems::File("config/goals/example.plan".into()),
        &["g6", "g7"],
    );
}
