//! Seed 1 Fig. 2's rover on MockVehicle and its manual clock (tests/fixtures/exec/rover_two.ixt planned by
//! the planner, config/demo-rover.toml's mapping): the executive, a vehicle that does what the domain says,
//! a pacer that lets the test react to each START, and readers of the mission report. Include it beside
//! `common/mapping.rs` (as `mod mapping`).

use std::path::Path;
use std::sync::Arc;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::{Executive, Fate};
use mavtempo_executive::exec::mission::{run_mission, MissionOptions, MissionReport, Pacer};
use mavtempo_executive::exec::pacer::MockPacer;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_temporal::lang::{load_domain, load_problem};
use mavtempo_temporal::model::Time;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_temporal::planner::{Budget, Search, StepOutcome};
use mavtempo_vehicle::mock::Outcome;
use mavtempo_vehicle::{MockVehicle, VehicleEvent};

/// Seed 1 §4's ts 1.3 s and μ 0.6, d 2 s, 500 repair steps per cycle's budget base (μ·n = 300).
pub fn rover_config() -> ExecConfig {
    ExecConfig {
        timestep_ms: 1_300,
        repair_share: 0.6,
        replan_slack_ms: 2_000,
        repair_max_steps: Some(500),
        ..ExecConfig::default()
    }
}

/// An executive over the planner's plan for rover_two.ixt with [`rover_config`].
pub fn executive() -> Executive {
    executive_with(rover_config())
}

pub fn executive_with(cfg: ExecConfig) -> Executive {
    let d = load_domain(Path::new(repo!("domains/rover/rover.ixt"))).expect("rover loads");
    let p = load_problem(Path::new(repo!("tests/fixtures/exec/rover_two.ixt")), &d)
        .expect("fixture loads");
    let root = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mut search = Search::new(root);
    assert_eq!(search.run(Budget::steps(20_000)), StepOutcome::Solved);
    let plan = search.into_plan();
    let mapping = mavtempo_testkit::mapping::rover(&plan);
    Executive::new(plan, cfg).with_mapping(mapping)
}

/// A rover that does what the domain says: moves at 0.45 m/s using 0.5 % of battery per metre (levels
/// scripted in `levels`), PTU turns in 3 s, pictures in 8 s of about 0.9 slot.
pub fn rover() -> MockVehicle {
    let mut v = MockVehicle::new();
    v.set_level("BATTERY", 90.0).set_level("STORAGE", 3.0);
    v.script("move_ptu", Outcome::nominal(3_000));
    v
}

/// Reacts to what the executive starts, as the world would: the `rules` see each new START line of the
/// mock's log (`"<ms> START <task> <id>"`) and may schedule events.
pub struct World<F: FnMut(&mut MockVehicle, u64, &str)> {
    inner: MockPacer,
    seen: usize,
    rule: F,
}

impl<F: FnMut(&mut MockVehicle, u64, &str)> Pacer<MockVehicle> for World<F> {
    fn origin_ms(&self) -> u64 {
        0
    }
    fn now(&self, v: &MockVehicle) -> Time {
        self.inner.now(v)
    }
    fn wait(&mut self, v: &mut MockVehicle, until: Time) -> Option<VehicleEvent> {
        while self.seen < v.log.len() {
            let line = v.log[self.seen].clone();
            self.seen += 1;
            let mut parts = line.split(' ');
            let at: u64 = parts.next().and_then(|s| s.parse().ok()).unwrap_or(0);
            if parts.next() == Some("START") {
                let task = parts.next().unwrap_or("").to_string();
                (self.rule)(v, at, &task);
            }
        }
        self.inner.wait(v, until)
    }
}

/// The mission to its end (30 min at most), `rule` reacting to each START.
pub fn run(
    ex: &mut Executive,
    v: &mut MockVehicle,
    rule: impl FnMut(&mut MockVehicle, u64, &str),
) -> MissionReport {
    let mut world = World {
        inner: MockPacer::default(),
        seen: 0,
        rule,
    };
    let opts = MissionOptions {
        time_limit_ms: 30 * 60_000,
        ..MissionOptions::default()
    };
    run_mission(ex, v, &mut world, &opts, &mut |_, _| {})
}

/// Every event of the report with its cycle's time.
pub fn events(r: &MissionReport) -> Vec<(Time, TraceEvent)> {
    r.cycles
        .iter()
        .flat_map(|c| c.events.iter().map(move |e| (c.time_ms, e.clone())))
        .collect()
}

/// The actions launched, in order.
pub fn launches(r: &MissionReport) -> Vec<String> {
    events(r)
        .into_iter()
        .filter_map(|(_, e)| match e {
            TraceEvent::Launch { action, .. } => Some(action),
            _ => None,
        })
        .collect()
}

/// The pictures launched, in order.
pub fn pictures(r: &MissionReport) -> Vec<String> {
    launches(r)
        .into_iter()
        .filter(|a| a.starts_with("take_picture"))
        .collect()
}

/// Both goals of rover_two.ixt, g1 and g2, are achieved.
pub fn assert_both_achieved(r: &MissionReport) {
    assert_eq!(
        (fate(r, "g1"), fate(r, "g2")),
        (Fate::Achieved, Fate::Achieved),
        "{:?}",
        r.goals
    );
}

pub fn fate(r: &MissionReport, name: &str) -> Fate {
    r.goals
        .iter()
        .find(|g| g.name == name)
        .map(|g| g.fate.clone())
        .unwrap_or(Fate::Pending)
}

/// The rover of the nominal mission: [`moving_rover`] and pictures of 0.9 slot (storage 2.1 after each).
pub fn nominal_rover() -> MockVehicle {
    let mut v = moving_rover();
    v.script(
        "take_picture",
        Outcome::nominal(8_000).with_level("STORAGE", 2.1),
    );
    v
}

/// The rover with its nominal moves scripted: base → p2 (19 m) then p2 → p1 (12.8 m) at 0.45 m/s.
pub fn moving_rover() -> MockVehicle {
    let mut v = rover();
    v.script("move", Outcome::nominal(42_000).with_level("BATTERY", 80.5));
    v.script("move", Outcome::nominal(28_500).with_level("BATTERY", 74.1));
    v
}
