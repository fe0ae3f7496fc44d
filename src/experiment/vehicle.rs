//! The experiment's vehicle: travels between places at a seeded speed (a travel task is one with `from`
//! and `to` location arguments), other tasks take a seeded time within their bounds; it keeps an odometer and
//! a log of what it did, and delivers the ground station's goal lists at their arrival times. Manual clock:
//! its [`Pacer`] jumps to the next thing due, so a 12-hour mission runs in milliseconds.

use std::collections::{BTreeMap, HashMap, VecDeque};
use std::time::Duration;

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::exec::mission::Pacer;
use crate::model::Time;
use crate::vehicle::goals::GoalBatch;
use crate::vehicle::{
    ActionId, ActionReport, ActionStart, Enu, GoalRequest, ReportStatus, StateValue, Vehicle,
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

pub struct KinematicVehicle {
    now_ms: u64,
    rng: ChaCha8Rng,
    times: HashMap<String, TaskTime>,
    running: BTreeMap<ActionId, Running>,
    goals: BTreeMap<u64, Vec<GoalRequest>>,
    ready: VecDeque<VehicleEvent>,
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
            now_ms: 0,
            rng,
            times,
            running: BTreeMap::new(),
            goals: BTreeMap::new(),
            ready: VecDeque::new(),
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

    fn advance_to(&mut self, t: u64) {
        self.now_ms = self.now_ms.max(t);
        loop {
            let due_report = self
                .running
                .iter()
                .filter(|(_, r)| r.end_ms <= self.now_ms)
                .min_by_key(|(id, r)| (r.end_ms, **id))
                .map(|(id, _)| *id);
            let due_goal = self
                .goals
                .keys()
                .next()
                .copied()
                .filter(|&g| g <= self.now_ms);
            match (due_report, due_goal) {
                (Some(id), g) if g.is_none_or(|g| self.running[&id].end_ms <= g) => {
                    self.finish(id, ReportStatus::Nominal)
                }
                (_, Some(g)) => {
                    if let Some(batch) = self.goals.remove(&g) {
                        self.ready
                            .push_back(VehicleEvent::Goals(GoalBatch::detached(batch)));
                    }
                }
                _ => break,
            }
        }
    }

    fn finish(&mut self, id: ActionId, status: ReportStatus) {
        let Some(r) = self.running.remove(&id) else {
            return;
        };
        let end = if status == ReportStatus::Nominal {
            r.end_ms
        } else {
            self.now_ms.min(r.end_ms)
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
        self.ready.push_back(VehicleEvent::Report(ActionReport {
            id,
            status,
            time_ms: end,
            resources: Vec::new(),
            state,
            reason: (status != ReportStatus::Nominal).then(|| "stopped (END)".to_string()),
        }));
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
        self.running.insert(
            a.id,
            Running {
                task: a.task,
                start_ms: self.now_ms,
                end_ms: self.now_ms + duration,
                leg,
            },
        );
        Ok(())
    }

    fn stop(&mut self, id: ActionId) -> Result<(), VehicleError> {
        if !self.running.contains_key(&id) {
            return Err(VehicleError::NotRunning(id));
        }
        self.finish(id, ReportStatus::Interrupted);
        Ok(())
    }

    fn try_event(&mut self) -> Option<VehicleEvent> {
        self.ready.pop_front()
    }

    fn wait_event(&mut self, _timeout: Duration) -> Option<VehicleEvent> {
        self.ready.pop_front()
    }

    fn now_ms(&self) -> u64 {
        self.now_ms
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
        v.now_ms.min(i64::MAX as u64) as Time
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
