//! `mavtempo bench repair`: plan repair against complete replanning on each event kind of seed 1 Fig. 2
//! (picture failure, move stopped in rough ground, battery drop, goal request), on the rover mission of
//! tests/fixtures/exec/rover_two.ixt executed against MockVehicle with the manual clock. The same run is
//! made twice up to the event: once the executive repairs (the repair's CPU time is summed over the cycles
//! until the repaired plan is adopted), once it is made to abort and replan from scratch at that point (the
//! replanning's wall time, each attempt capped at 1,000 planning steps).

use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use super::exec::ExecBenchError;
use crate::config_check::resolve_mapping;
use crate::exec::config::ExecConfig;
use crate::exec::cycle::CycleOutcome;
use crate::exec::executive::Executive;
use crate::exec::resource_report::LevelVerdict;
use crate::exec::trace::TraceEvent;
use crate::lang::{parse_domain, parse_problem};
use crate::mapping::DomainMapping;
use crate::plan::PartialPlan;
use crate::planner::{Budget, Search, StepOutcome};
use crate::vehicle::config::VehicleConfig;
use crate::vehicle::mock::{Outcome, Scripted};
use crate::vehicle::{
    Enu, GoalKind, GoalLocation, GoalRequest, MockVehicle, ReportStatus, ResourceLevel, StateValue,
};

const DOMAIN: &str = include_str!("../../domains/rover/rover.ixt");
const PROBLEM: &str = include_str!("../../tests/fixtures/exec/rover_two.ixt");
/// The rover's `[mapping]` (position, picture and be-at goals) comes from the demo's configuration.
const CONFIG: &str = include_str!("../../config/demo-rover.toml");

/// Repair against replanning on one event kind.
#[derive(Clone, Debug, Serialize)]
pub struct RepairFigures {
    pub event: String,
    /// `None` when the executive did not repair (it aborted and replanned instead).
    pub repair_ms: Option<f64>,
    pub repair_steps: u64,
    pub replan_ms: f64,
    pub replan_found: bool,
}

/// The event kinds measured.
pub const EVENTS: [&str; 4] = [
    "picture_failure",
    "move_stopped",
    "battery_drop",
    "goal_request",
];

fn plan() -> Result<PartialPlan, ExecBenchError> {
    let d = Arc::new(
        parse_domain("rover.ixt", DOMAIN).map_err(|e| ExecBenchError::load("rover.ixt", e))?,
    );
    let p = Arc::new(
        parse_problem("rover_two.ixt", PROBLEM, &d)
            .map_err(|e| ExecBenchError::load("rover_two.ixt", e))?,
    );
    let mut s = Search::new(PartialPlan::new(d, p)?);
    match s.run(Budget::steps(20_000)) {
        StepOutcome::Solved => Ok(s.into_plan()),
        o => Err(ExecBenchError::NotPlanned {
            problem: "rover_two",
            outcome: format!("{o:?}"),
        }),
    }
}

/// The mock rover scripted for `event` (as in src/executive/tests/it/exec_rover.rs).
fn vehicle(event: &str) -> MockVehicle {
    let mut v = MockVehicle::new();
    v.set_level("BATTERY", 90.0).set_level("STORAGE", 3.0);
    v.script("move_ptu", Outcome::nominal(3_000));
    v.script("recharge_battery", Outcome::nominal(120_000));
    if event == "move_stopped" {
        v.script("move", Outcome::nominal(600_000));
        v.on_stop(
            "move",
            vec![(
                "position".into(),
                StateValue::Position(Enu::new(13.0, -3.0, 0.0)),
            )],
        );
    }
    v.script("move", Outcome::nominal(42_000).with_level("BATTERY", 80.5));
    v.script("move", Outcome::nominal(28_500).with_level("BATTERY", 74.1));
    if event == "picture_failure" {
        v.script("take_picture", Outcome::failed(8_000, "not captured"));
    }
    v.script(
        "take_picture",
        Outcome::nominal(8_000).with_level("STORAGE", 2.1),
    );
    match event {
        "battery_drop" => {
            v.at(
                20_000,
                Scripted::Resource(ResourceLevel {
                    resource: "BATTERY".into(),
                    level: 3.0,
                }),
            );
        }
        "goal_request" => {
            v.at(
                47_000,
                Scripted::Goals(vec![GoalRequest {
                    name: "g6".into(),
                    kind: GoalKind::BeAt,
                    proposition: "at(base)".into(),
                    location: Some(GoalLocation {
                        name: "base".into(),
                        new: false,
                        at: Enu::default(),
                        lat: 0.0,
                        lon: 0.0,
                    }),
                    priority: 1,
                    start_window_s: (0.0, 1_800.0),
                    duration_s: (0.0, f64::INFINITY),
                    d_achiev_s: 60.0,
                }]),
            );
        }
        _ => {}
    }
    v
}

/// The cycle in which the event was integrated.
fn is_event(e: &TraceEvent, event: &str) -> bool {
    match (event, e) {
        ("picture_failure", TraceEvent::Report { status, .. }) => *status == ReportStatus::Failed,
        ("move_stopped", TraceEvent::Report { status, .. }) => *status == ReportStatus::Interrupted,
        ("battery_drop", TraceEvent::Level { verdict, .. }) => {
            matches!(verdict, LevelVerdict::OverConsumption { .. })
        }
        ("goal_request", TraceEvent::GoalAccepted { .. }) => true,
        _ => false,
    }
}

fn cfg() -> ExecConfig {
    ExecConfig {
        timestep_ms: 1_300,
        repair_share: 0.6,
        replan_slack_ms: 2_000,
        repair_max_steps: Some(25),
        ..ExecConfig::default()
    }
}

/// Runs the mission until the event, then repairs (`replan == false`) or replans; returns (ms, steps, ok).
fn measure(
    plan: &PartialPlan,
    mapping: &DomainMapping,
    event: &str,
    replan: bool,
) -> (Option<f64>, u64, bool) {
    let mut ex = Executive::new(plan.clone(), cfg()).with_mapping(mapping.clone());
    let mut v = vehicle(event);
    let mut t = 0;
    let mut seen = false;
    let mut repair_us = 0u64;
    while t < 30 * 60_000 {
        v.advance_to(t as u64);
        let out = ex.cycle(&mut v, t);
        let c = ex.cycles().last().cloned().unwrap_or_default();
        if !seen && c.events.iter().any(|e| is_event(e, event)) {
            seen = true;
            if replan {
                let start = Instant::now();
                let now = || t;
                let found = matches!(
                    ex.replan(&now, &mut |_| {}),
                    crate::exec::replan::ReplanResult::Plan(_)
                );
                return (Some(start.elapsed().as_secs_f64() * 1e3), 0, found);
            }
        }
        if seen {
            repair_us += c.repair_us;
            if c.events
                .iter()
                .any(|e| matches!(e, TraceEvent::RepairDone { .. }))
            {
                return (
                    Some(repair_us as f64 / 1e3),
                    ex.counters().repair_steps,
                    true,
                );
            }
        }
        match out {
            CycleOutcome::Continue { next, repairing } => {
                t = if repairing {
                    t + ex.config().repair_budget_ms().max(1)
                } else {
                    next.map_or(t + 500, |n| n.clamp(t + 1, t + 500))
                };
            }
            _ => return (None, ex.counters().repair_steps, false),
        }
    }
    (None, ex.counters().repair_steps, false)
}

/// Repair and replanning figures on each event kind.
pub fn run() -> Result<Vec<RepairFigures>, ExecBenchError> {
    let plan = plan()?;
    let cfg = VehicleConfig::parse(CONFIG, "config/demo-rover.toml")
        .map_err(|e| ExecBenchError::load("config/demo-rover.toml", e))?;
    let mapping = resolve_mapping(
        &cfg.mapping,
        plan.domain(),
        Some(plan.problem()),
        cfg.source.as_ref(),
    )
    .map_err(|issues| {
        let lines: Vec<String> = issues.iter().map(|i| i.to_string()).collect();
        ExecBenchError::load("config/demo-rover.toml", lines.join("\n"))
    })?;
    Ok(EVENTS
        .iter()
        .map(|&event| {
            let (repair_ms, repair_steps, _) = measure(&plan, &mapping, event, false);
            let (replan_ms, _, replan_found) = measure(&plan, &mapping, event, true);
            RepairFigures {
                event: event.into(),
                repair_ms,
                repair_steps,
                replan_ms: replan_ms.unwrap_or(f64::NAN),
                replan_found,
            }
        })
        .collect())
}
