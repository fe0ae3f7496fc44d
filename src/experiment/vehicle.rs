//! The experiment's vehicle: travels between places at a seeded speed (a travel task is one with `from`
//! and `to` location arguments), other tasks take a seeded time within their bounds; it keeps an odometer and
//! a log of what it did, and delivers the ground station's goal lists at their arrival times. It is the
//! executive tests' [`MockVehicle`] (clock, reports, their order) with durations drawn from the actions'
//! arguments. Manual clock: its [`Pacer`] jumps to the next thing due, so a 12-hour mission runs in
//! milliseconds.

use std::collections::{BTreeMap, HashMap};
use std::time::Duration;

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::exec::mission::Pacer;
use crate::model::Time;
use crate::vehicle::mock::{Outcome, Scripted};
use crate::vehicle::{
    ActionStart, Enu, GoalRequest, MockVehicle, ReportStatus, StateValue, Vehicle, VehicleActionId,
    VehicleError, VehicleEvent,
};

/// How long a task takes.
#[derive(Clone, Debug)]
pub enum TaskTime {
    /// Distance from `from` to `to` over a speed drawn in `[lo, hi]` m/s.
    Travel { lo: f64, hi: f64 },
    /// A duration drawn in `[lo, hi]` ms.
    Fixed { lo: Time, hi: Time },
}

impl TaskTime {
    /// Always `ms`.
    pub fn exactly(ms: Time) -> Self {
        TaskTime::Fixed { lo: ms, hi: ms }
    }
}

/// One action the vehicle ran.
#[derive(Clone, Debug, PartialEq)]
pub struct Done {
    pub task: String,
    pub start_ms: u64,
    pub end_ms: u64,
    /// Travel: the place names and the distance covered (less than the leg when stopped).
    pub leg: Option<(String, String, f64)>,
}

struct Running {
    task: String,
    start_ms: u64,
    end_ms: u64,
    leg: Option<(String, Enu, String, Enu)>,
}

/// The scripted mock with travel times drawn from the actions' arguments: the mock keeps the clock, the
/// reports and their order; this keeps what the experiment measures (legs, the log).
pub struct KinematicVehicle {
    mock: MockVehicle,
    rng: ChaCha8Rng,
    times: HashMap<String, TaskTime>,
    running: BTreeMap<VehicleActionId, Running>,
    goals: BTreeMap<u64, Vec<GoalRequest>>,
    pub log: Vec<Done>,
    /// Whether a stopped walk reports where it stopped (a vehicle without a position sensor does not).
    report_positions: bool,
}

fn dist(a: Enu, b: Enu) -> f64 {
    ((a.east - b.east).powi(2) + (a.north - b.north).powi(2) + (a.up - b.up).powi(2)).sqrt()
}

impl KinematicVehicle {
    pub fn new(rng: ChaCha8Rng, times: HashMap<String, TaskTime>) -> Self {
        KinematicVehicle {
            mock: MockVehicle::new(),
            rng,
            times,
            running: BTreeMap::new(),
            goals: BTreeMap::new(),
            log: Vec::new(),
            report_positions: true,
        }
    }

    /// A vehicle that does not report positions (its configuration maps none).
    pub fn without_positions(mut self) -> Self {
        self.report_positions = false;
        self
    }

    /// A goal list uploaded by the ground station at `at_ms`.
    pub fn goals_at(&mut self, at_ms: u64, goals: Vec<GoalRequest>) {
        self.goals.entry(at_ms).or_default().extend(goals);
    }

    fn next_due_ms(&self) -> Option<u64> {
        let report = self.running.values().map(|r| r.end_ms).min();
        let goal = self.goals.keys().next().copied();
        report.into_iter().chain(goal).min()
    }

    /// A goal list comes after the reports due at its time.
    fn advance_to(&mut self, t: u64) {
        while let Some(entry) = self.goals.first_entry().filter(|e| *e.key() <= t) {
            let (g, batch) = entry.remove_entry();
            self.mock.advance_to(g);
            self.log_finished();
            self.mock.at(g, Scripted::Goals(batch));
            self.mock.advance_to(g);
        }
        self.mock.advance_to(t);
        self.log_finished();
    }

    /// Logs the actions whose nominal reports the mock has just made ready.
    fn log_finished(&mut self) {
        let done: Vec<VehicleActionId> = self
            .mock
            .ready()
            .filter_map(|e| match e {
                VehicleEvent::Report(r) if r.status == ReportStatus::Nominal => Some(r.id),
                _ => None,
            })
            .filter(|id| self.running.contains_key(id))
            .collect();
        for id in done {
            self.finish(id, ReportStatus::Nominal);
        }
    }

    /// Logs an action's end (nominal, or stopped now); a stopped travel's state is where it stopped.
    fn finish(&mut self, id: VehicleActionId, status: ReportStatus) -> Vec<(String, StateValue)> {
        let Some(r) = self.running.remove(&id) else {
            return Vec::new();
        };
        let end = if status == ReportStatus::Nominal {
            r.end_ms
        } else {
            self.mock.now_ms().min(r.end_ms)
        };
        let mut state = Vec::new();
        let leg = r.leg.map(|(from, a, to, b)| {
            let total = dist(a, b);
            let frac = if r.end_ms > r.start_ms {
                (end - r.start_ms) as f64 / (r.end_ms - r.start_ms) as f64
            } else {
                1.0
            };
            if status != ReportStatus::Nominal && self.report_positions {
                let at = Enu::new(
                    a.east + (b.east - a.east) * frac,
                    a.north + (b.north - a.north) * frac,
                    a.up + (b.up - a.up) * frac,
                );
                state.push(("position".to_string(), StateValue::Position(at)));
            }
            (from, to, total * frac)
        });
        self.log.push(Done {
            task: r.task,
            start_ms: r.start_ms,
            end_ms: end,
            leg,
        });
        state
    }
}

impl Vehicle for KinematicVehicle {
    fn start(&mut self, a: ActionStart) -> Result<(), VehicleError> {
        if self.running.contains_key(&a.id) {
            return Err(VehicleError::AlreadyRunning(a.id));
        }
        let time = self
            .times
            .get(&a.task)
            .cloned()
            .ok_or_else(|| VehicleError::UnknownTask(a.task.clone()))?;
        let place = |name: &str| {
            a.arg(name).and_then(|arg| match arg {
                crate::vehicle::Arg::Location { name, .. } => {
                    arg.as_enu().map(|e| (name.clone(), e))
                }
                _ => None,
            })
        };
        let (duration, leg) = match time {
            TaskTime::Travel { lo, hi } => {
                let (Some((f, a_at)), Some((t, b_at))) = (place("from"), place("to")) else {
                    return Err(VehicleError::BadArguments {
                        task: a.task.clone(),
                        reason: "travel without located from/to".into(),
                    });
                };
                let speed = self.rng.gen_range(lo..=hi).max(1e-3);
                let ms = (dist(a_at, b_at) / speed * 1000.0).round() as u64;
                (ms, Some((f, a_at, t, b_at)))
            }
            TaskTime::Fixed { lo, hi } => (self.rng.gen_range(lo..=hi).max(0) as u64, None),
        };
        let now = self.mock.now_ms();
        self.running.insert(
            a.id,
            Running {
                task: a.task.clone(),
                start_ms: now,
                end_ms: now + duration,
                leg,
            },
        );
        self.mock.start_with(a, Outcome::nominal(duration))
    }

    fn stop(&mut self, id: VehicleActionId) -> Result<(), VehicleError> {
        if !self.running.contains_key(&id) {
            return Err(VehicleError::NotRunning(id));
        }
        let state = self.finish(id, ReportStatus::Interrupted);
        self.mock.stop_with(id, state)
    }

    fn try_event(&mut self) -> Option<VehicleEvent> {
        self.mock.try_event()
    }

    fn wait_event(&mut self, timeout: Duration) -> Option<VehicleEvent> {
        self.mock.wait_event(timeout)
    }

    fn now_ms(&self) -> u64 {
        self.mock.now_ms()
    }
}

/// The manual clock: waiting jumps to the next report or goal upload, or to `until`.
#[derive(Debug, Default)]
pub struct KinematicPacer;

impl Pacer<KinematicVehicle> for KinematicPacer {
    fn origin_ms(&self) -> u64 {
        0
    }

    fn now(&self, v: &KinematicVehicle) -> Time {
        v.now_ms().min(i64::MAX as u64) as Time
    }

    fn wait(&mut self, v: &mut KinematicVehicle, until: Time) -> Option<VehicleEvent> {
        if let Some(e) = v.try_event() {
            return Some(e);
        }
        let until = until.max(0) as u64;
        let to = v.next_due_ms().map_or(until, |d| d.min(until));
        v.advance_to(to);
        v.try_event()
    }
}
