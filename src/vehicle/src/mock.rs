//! MockVehicle: an in-memory, scripted, deterministic vehicle with a manual clock, for executive tests without
//! hardware or sockets. Each task name has a scripted outcome; exogenous events (resource levels, capacity
//! alterations, goal requests, link status) are scheduled at times. Events come out in (time, order) order.

use std::collections::{BTreeMap, HashMap, VecDeque};
use std::time::Duration;

use super::api::{Vehicle, VehicleError, VehicleEvent};
use super::goals::GoalBatch;
use super::types::{
    ActionReport, ActionStart, CapacityChange, GoalRequest, LinkStatus, ReportStatus,
    ResourceLevel, StateValue, VehicleActionId,
};

/// How a started action of a task ends.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Duration from start to the report, ms.
    pub after_ms: u64,
    pub status: ReportStatus,
    /// Levels the resources reach at the end (also applied to the mock's state).
    pub resources: Vec<ResourceLevel>,
    /// State values reported when not nominal.
    pub state: Vec<(String, StateValue)>,
    pub reason: Option<String>,
}

impl Outcome {
    pub fn nominal(after_ms: u64) -> Self {
        Self {
            after_ms,
            status: ReportStatus::Nominal,
            resources: Vec::new(),
            state: Vec::new(),
            reason: None,
        }
    }

    pub fn failed(after_ms: u64, reason: &str) -> Self {
        Self {
            status: ReportStatus::Failed,
            reason: Some(reason.into()),
            ..Self::nominal(after_ms)
        }
    }

    pub fn with_level(mut self, resource: &str, level: f64) -> Self {
        self.resources.push(ResourceLevel {
            resource: resource.into(),
            level,
        });
        self
    }

    pub fn with_state(mut self, variable: &str, value: StateValue) -> Self {
        self.state.push((variable.into(), value));
        self
    }
}

/// Something the script makes happen at a time.
#[derive(Debug, Clone)]
pub enum Scripted {
    Resource(ResourceLevel),
    Capacity(CapacityChange),
    Goals(Vec<GoalRequest>),
    Link(LinkStatus),
}

#[derive(Debug)]
enum Due {
    Report(VehicleActionId),
    Event(Scripted),
}

#[derive(Debug, Default)]
pub struct MockVehicle {
    now_ms: u64,
    order: u64,
    /// Per task: outcomes used in turn; the last one repeats.
    outcomes: HashMap<String, VecDeque<Outcome>>,
    /// State values reported when an action of the task is stopped (e.g. the reached position).
    on_stop: HashMap<String, Vec<(String, StateValue)>>,
    running: BTreeMap<VehicleActionId, (String, Outcome)>,
    /// How long a stopped action takes to report (an autopilot that takes time to stop), ms.
    stop_delay_ms: u64,
    due: BTreeMap<(u64, u64), Due>,
    ready: VecDeque<VehicleEvent>,
    levels: BTreeMap<String, f64>,
    /// From this vehicle time on, the autopilot sends no heartbeat (a vanished vehicle).
    silent_from_ms: Option<u64>,
    /// Every START and END received, for assertions.
    pub log: Vec<String>,
    /// The actions started to end still ([`Vehicle::start_still`]).
    pub still_starts: Vec<VehicleActionId>,
}

impl MockVehicle {
    pub fn new() -> Self {
        Self::default()
    }

    /// Scripts the next outcome of `task` (outcomes queue up; the last one repeats).
    pub fn script(&mut self, task: &str, outcome: Outcome) -> &mut Self {
        self.outcomes
            .entry(task.into())
            .or_default()
            .push_back(outcome);
        self
    }

    pub fn on_stop(&mut self, task: &str, state: Vec<(String, StateValue)>) -> &mut Self {
        self.on_stop.insert(task.into(), state);
        self
    }

    /// A stopped action reports `ms` after its END instead of at once.
    pub fn stops_after(&mut self, ms: u64) -> &mut Self {
        self.stop_delay_ms = ms;
        self
    }

    pub fn set_level(&mut self, resource: &str, level: f64) -> &mut Self {
        self.levels.insert(resource.into(), level);
        self
    }

    /// The autopilot falls silent at vehicle time `at_ms`: no heartbeat from then on ([`Vehicle::silence`]).
    pub fn fall_silent_at(&mut self, at_ms: u64) -> &mut Self {
        self.silent_from_ms = Some(at_ms);
        self
    }

    /// Schedules an exogenous event at vehicle time `at_ms`.
    pub fn at(&mut self, at_ms: u64, what: Scripted) -> &mut Self {
        self.order += 1;
        self.due.insert((at_ms, self.order), Due::Event(what));
        self
    }

    /// Advances the manual clock; what falls due becomes available to `try_event`.
    pub fn advance_to(&mut self, t_ms: u64) {
        self.now_ms = self.now_ms.max(t_ms);
        while let Some(entry) = self.due.first_entry() {
            if entry.key().0 > self.now_ms {
                break;
            }
            let ((t, _), due) = entry.remove_entry();
            match due {
                Due::Report(id) => {
                    if let Some((_, outcome)) = self.running.remove(&id) {
                        let report = self.make_report(
                            id,
                            t,
                            outcome.status,
                            outcome.state,
                            outcome.reason,
                            &outcome.resources,
                        );
                        self.ready.push_back(VehicleEvent::Report(report));
                    }
                }
                Due::Event(Scripted::Resource(r)) => {
                    self.levels.insert(r.resource.clone(), r.level);
                    self.ready.push_back(VehicleEvent::Resource(r));
                }
                Due::Event(Scripted::Capacity(c)) => {
                    self.ready.push_back(VehicleEvent::Capacity(c))
                }
                Due::Event(Scripted::Goals(g)) => self
                    .ready
                    .push_back(VehicleEvent::Goals(GoalBatch::detached(g))),
                Due::Event(Scripted::Link(l)) => self.ready.push_back(VehicleEvent::Link(l)),
            }
        }
    }

    /// The vehicle time of the next scripted event or report, if any (a pacer jumps to it).
    pub fn next_due_ms(&self) -> Option<u64> {
        self.due.keys().next().map(|k| k.0)
    }

    pub fn advance(&mut self, ms: u64) {
        self.advance_to(self.now_ms + ms);
    }

    pub fn is_running(&self, id: VehicleActionId) -> bool {
        self.running.contains_key(&id)
    }

    /// The events ready to be taken, oldest first.
    pub fn ready(&self) -> impl Iterator<Item = &VehicleEvent> {
        self.ready.iter()
    }

    /// Starts an action with an outcome the caller computed (a travel time from the action's arguments)
    /// instead of the one scripted for its task.
    pub fn start_with(
        &mut self,
        action: ActionStart,
        outcome: Outcome,
    ) -> Result<(), VehicleError> {
        if self.running.contains_key(&action.id) {
            return Err(VehicleError::AlreadyRunning(action.id));
        }
        self.log.push(format!(
            "{} START {} {}",
            self.now_ms, action.task, action.id
        ));
        self.order += 1;
        self.due.insert(
            (self.now_ms + outcome.after_ms, self.order),
            Due::Report(action.id),
        );
        self.running.insert(action.id, (action.task, outcome));
        Ok(())
    }

    /// Stops an action now; its report carries `state` (e.g. where a stopped motion is).
    pub fn stop_with(
        &mut self,
        id: VehicleActionId,
        state: Vec<(String, StateValue)>,
    ) -> Result<(), VehicleError> {
        self.running
            .remove(&id)
            .ok_or(VehicleError::NotRunning(id))?;
        self.log.push(format!("{} END {id}", self.now_ms));
        let report = self.make_report(
            id,
            self.now_ms,
            ReportStatus::Interrupted,
            state,
            Some("stopped (END)".into()),
            &[],
        );
        self.ready.push_back(VehicleEvent::Report(report));
        Ok(())
    }

    fn make_report(
        &mut self,
        id: VehicleActionId,
        t: u64,
        status: ReportStatus,
        state: Vec<(String, StateValue)>,
        reason: Option<String>,
        resources: &[ResourceLevel],
    ) -> ActionReport {
        for r in resources {
            self.levels.insert(r.resource.clone(), r.level);
        }
        ActionReport {
            id,
            status,
            time_ms: t,
            resources: self
                .levels
                .iter()
                .map(|(k, v)| ResourceLevel {
                    resource: k.clone(),
                    level: *v,
                })
                .collect(),
            state: if status == ReportStatus::Nominal {
                Vec::new()
            } else {
                state
            },
            reason,
        }
    }
}

impl Vehicle for MockVehicle {
    fn start_still(&mut self, action: ActionStart) -> Result<(), VehicleError> {
        let id = action.id;
        self.start(action)?;
        self.still_starts.push(id);
        Ok(())
    }

    fn start(&mut self, action: ActionStart) -> Result<(), VehicleError> {
        if self.running.contains_key(&action.id) {
            return Err(VehicleError::AlreadyRunning(action.id));
        }
        let queue = self
            .outcomes
            .get_mut(&action.task)
            .ok_or_else(|| VehicleError::UnknownTask(action.task.clone()))?;
        let outcome = if queue.len() > 1 {
            queue.pop_front()
        } else {
            queue.front().cloned()
        }
        .ok_or_else(|| VehicleError::UnknownTask(action.task.clone()))?;
        self.start_with(action, outcome)
    }

    fn stop(&mut self, id: VehicleActionId) -> Result<(), VehicleError> {
        let (task, _) = self.running.get(&id).ok_or(VehicleError::NotRunning(id))?;
        let state = self.on_stop.get(task).cloned().unwrap_or_default();
        if self.stop_delay_ms == 0 {
            return self.stop_with(id, state);
        }
        // The report of the stop replaces the scripted one, `stop_delay_ms` later.
        self.log.push(format!("{} END {id}", self.now_ms));
        let task = task.clone();
        let outcome = Outcome {
            status: ReportStatus::Interrupted,
            state,
            reason: Some("stopped (END)".into()),
            ..Outcome::nominal(0)
        };
        self.running.insert(id, (task, outcome));
        self.order += 1;
        self.due.insert(
            (self.now_ms + self.stop_delay_ms, self.order),
            Due::Report(id),
        );
        Ok(())
    }

    fn try_event(&mut self) -> Option<VehicleEvent> {
        self.ready.pop_front()
    }

    fn wait_event(&mut self, _timeout: Duration) -> Option<VehicleEvent> {
        // A manual clock: waiting would never make time pass.
        self.ready.pop_front()
    }

    fn now_ms(&self) -> u64 {
        self.now_ms
    }

    fn silence(&self) -> Option<Duration> {
        // Heard at every instant of its manual clock until it falls silent.
        let from = self.silent_from_ms?;
        Some(Duration::from_millis(self.now_ms.saturating_sub(from)))
    }
}
