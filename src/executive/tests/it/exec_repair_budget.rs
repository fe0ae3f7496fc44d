//! Plan repair's budget (seed 1 §3.4): μ·ts of *mission* time per cycle, read from the executive's clock
//! (the vehicle's), not the wall clock; a hard per-cycle step cap when that clock does not move; the
//! deterministic step budget (`repair_max_steps`) unchanged.

use std::cell::Cell;
use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::Executive;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_temporal::lang::load_problem_and_domain;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_vehicle::{
    ActionStart, MockVehicle, Vehicle, VehicleActionId, VehicleError, VehicleEvent,
};

/// A vehicle whose clock moves `tick_ms` each time it is read (mission time passes while planning).
struct Ticking {
    inner: MockVehicle,
    now: Cell<u64>,
    tick_ms: u64,
}

impl Vehicle for Ticking {
    fn start(&mut self, action: ActionStart) -> Result<(), VehicleError> {
        self.inner.start(action)
    }
    fn stop(&mut self, id: VehicleActionId) -> Result<(), VehicleError> {
        self.inner.stop(id)
    }
    fn try_event(&mut self) -> Option<VehicleEvent> {
        self.inner.try_event()
    }
    fn wait_event(&mut self, timeout: Duration) -> Option<VehicleEvent> {
        self.inner.wait_event(timeout)
    }
    fn now_ms(&self) -> u64 {
        let t = self.now.get();
        self.now.set(t + self.tick_ms);
        t
    }
}

/// An executive over fig2's root plan: every goal is an open condition, far more repair than a cycle does.
fn unplanned(cfg: ExecConfig) -> Executive {
    let (d, p) = load_problem_and_domain(Path::new(repo!("domains/rover/problems/fig2.ixt")))
        .expect("fig2 loads");
    let plan = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    Executive::new(plan, cfg)
}

fn cfg() -> ExecConfig {
    ExecConfig {
        timestep_ms: 1_000,
        repair_share: 0.6,
        ..ExecConfig::default()
    }
}

/// Repair steps done by the first cycle.
fn first_cycle_steps(ex: &mut Executive, v: &mut dyn Vehicle) -> u64 {
    let _ = ex.cycle(v, 0);
    let c = ex.cycles().records().first().expect("a cycle");
    let steps = c.events.iter().find_map(|e| match e {
        TraceEvent::RepairStep { steps, .. } => Some(*steps),
        _ => None,
    });
    steps.unwrap_or_else(|| panic!("no repair step in {:?}", c.events))
}

#[test]
fn the_repair_budget_is_mu_ts_of_mission_time() {
    // μ·ts = 600 ms; the clock moves 100 ms per read: read at the start (t0), then before each step:
    // t0+100 .. t0+500 allow 5 steps, t0+600 is the deadline. A wall-clock budget of 600 ms would do
    // however many steps the machine manages.
    let mut ex = unplanned(cfg());
    let mut v = Ticking {
        inner: MockVehicle::new(),
        now: Cell::new(5_000),
        tick_ms: 100,
    };
    ex.set_vehicle_origin(5_000);
    assert_eq!(first_cycle_steps(&mut ex, &mut v), 5);
    // Mission time running three times faster (a vehicle at a higher speed-up): one step.
    let mut ex = unplanned(cfg());
    let mut v = Ticking {
        inner: MockVehicle::new(),
        now: Cell::new(0),
        tick_ms: 300,
    };
    assert_eq!(first_cycle_steps(&mut ex, &mut v), 1);
}

#[test]
fn a_clock_that_does_not_move_is_bounded_by_the_cycle_step_cap() {
    let mut ex = unplanned(ExecConfig {
        repair_cycle_max_steps: 40,
        ..cfg()
    });
    let mut v = MockVehicle::new();
    assert_eq!(first_cycle_steps(&mut ex, &mut v), 40);
}

#[test]
fn deterministic_step_budgets_still_rule_when_set() {
    // μ·n = 0.6 × 50 = 30 steps, whatever the clock does.
    let mut ex = unplanned(ExecConfig {
        repair_max_steps: Some(50),
        ..cfg()
    });
    let mut v = Ticking {
        inner: MockVehicle::new(),
        now: Cell::new(0),
        tick_ms: 1_000,
    };
    assert_eq!(first_cycle_steps(&mut ex, &mut v), 30);
    // ... under the hard cap.
    let mut ex = unplanned(ExecConfig {
        repair_max_steps: Some(50),
        repair_cycle_max_steps: 12,
        ..cfg()
    });
    assert_eq!(first_cycle_steps(&mut ex, &mut MockVehicle::new()), 12);
}
