//! Seed 2's shopping day planned and handed to an executive (the mock-vehicle executive tests' set-up).

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::Executive;
use mavtempo_executive::exec::trace::{CycleRecord, TraceEvent};
use mavtempo_temporal::lang::load_problem_and_domain;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_temporal::planner::{Budget, Search, StepOutcome};
use mavtempo_vehicle::mock::Outcome;
use mavtempo_vehicle::MockVehicle;

/// ts 30 s, μ 0.6, d 30 s, 200 repair steps per cycle: the day's executive parameters in these tests.
pub fn day_config() -> ExecConfig {
    ExecConfig {
        timestep_ms: 30_000,
        repair_share: 0.6,
        replan_slack_ms: 30_000,
        repair_max_steps: Some(200),
        ..ExecConfig::default()
    }
}

/// An executive over the planner's plan for domains/shopping/problems/day.ixt.
pub fn day_executive(cfg: ExecConfig) -> Executive {
    let (d, p) = load_problem_and_domain(Path::new(repo!("domains/shopping/problems/day.ixt")))
        .expect("day loads");
    let root = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mut search = Search::new(root);
    assert_eq!(search.run(Budget::steps(20_000)), StepOutcome::Solved);
    Executive::new(search.into_plan(), cfg)
}

/// The day's vehicle when all goes well: the walk takes 16 min, the shopping 5 min.
pub fn day_vehicle() -> MockVehicle {
    let mut v = MockVehicle::new();
    v.script("go", Outcome::nominal(16 * 60_000));
    v.script("buy", Outcome::nominal(5 * 60_000));
    v
}

/// How many actions the cycles launched.
pub fn launches(cycles: &[CycleRecord]) -> usize {
    cycles
        .iter()
        .flat_map(|c| &c.events)
        .filter(|e| matches!(e, TraceEvent::Launch { .. }))
        .count()
}
