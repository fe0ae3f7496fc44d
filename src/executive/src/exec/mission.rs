//! A mission run live: the executive's cycles against a vehicle (seed 1 §3.2 wake-up rule), complete
//! replanning on abort (§3.6), until every goal is settled, then a [`MissionReport`]. Used by `mavtempo run`,
//! `mavtempo demo` and the dispatch experiment. How time passes is the [`Pacer`]'s business (wall clock of a
//! live vehicle, an accelerated SITL, or a manual clock), so the same loop runs far faster than real time.

use std::collections::{BTreeMap, VecDeque};
use std::time::Duration;

use serde::Serialize;

use super::cycle::CycleOutcome;
pub use super::cycle_log::CycleTimes;
use super::executive::{Counters, Executive, Fate, GoalFate};
use super::interrupt::{signal_name, Interrupt};
use super::outcome::FateReason;
use super::p_t::classify;
use super::replan::{ReplanRecord, ReplanResult};
use super::resource_bounds::level_bounds;
use super::trace::{CycleRecord, TraceEvent};
use mavtempo_temporal::model::{ResourceId, Time};
use mavtempo_vehicle::goals::GoalBatch;
use mavtempo_vehicle::safe_stop::SafeStopReport;
use mavtempo_vehicle::{
    ActionStart, GoalRequest, ReportStatus, Vehicle, VehicleActionId, VehicleError, VehicleEvent,
};

/// How mission time passes: the executive's clock and its sleep between cycles.
pub trait Pacer<V: Vehicle> {
    /// The vehicle time (ms) of the plan's origin: report times are converted with it.
    fn origin_ms(&self) -> u64;
    /// The executive's time: ms since the plan's origin.
    fn now(&self, vehicle: &V) -> Time;
    /// Lets time pass until `until` (ms since origin) or until a message arrives, whichever comes first.
    /// A message received while waiting is returned (it is integrated by the next cycle).
    fn wait(&mut self, vehicle: &mut V, until: Time) -> Option<VehicleEvent>;
    /// [`Pacer::wait`] that gives up (returning nothing) once `interrupt` is requested. By default the
    /// same as `wait`: right for pacers whose waits are short in wall time.
    fn wait_or_interrupt(
        &mut self,
        vehicle: &mut V,
        until: Time,
        interrupt: &Interrupt,
    ) -> Option<VehicleEvent> {
        let _ = interrupt;
        self.wait(vehicle, until)
    }
}

/// What the loop needs besides the executive, the vehicle and the pacer.
#[derive(Clone, Debug, Default)]
pub struct MissionOptions {
    /// The mission stops (goals left pending) at this time, ms since origin.
    pub time_limit_ms: Time,
    /// Goals requested at the start (e.g. `--goals FILE`), integrated by the first cycle like an upload.
    pub initial_goals: Vec<GoalRequest>,
    /// The mission stops (goals left pending) after this many cycles: a bound for loops nothing else
    /// catches (a cycle every few ms of mission time). `None`: no bound.
    pub max_cycles: Option<usize>,
    /// Stops the mission before its next cycle when requested (a signal): the end is `Interrupted`.
    pub interrupt: Interrupt,
    /// The vehicle is lost once its autopilot is silent (no HEARTBEAT, [`Vehicle::silence`]) this long: the
    /// end is `VehicleLost`. `None`: never (a vehicle in process cannot vanish).
    pub vehicle_lost_after: Option<Duration>,
}

/// How the mission ended.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MissionEnd {
    /// No action left and every goal settled.
    Finished,
    /// Complete replanning left no goal to pursue.
    NoGoals,
    /// The time limit passed with goals pending.
    TimeLimit,
    /// The cycle limit was reached with goals pending.
    CycleLimit,
    /// Complete replanning could not even extract a problem.
    Error(String),
    /// Stopped from outside (the signal's name, e.g. `SIGTERM`) with goals pending.
    Interrupted(String),
    /// No HEARTBEAT from the autopilot for `silent_s` seconds (the link timeout): the vehicle is lost.
    VehicleLost { silent_s: u64 },
}

impl MissionEnd {
    /// The verdict for a vanished vehicle, as printed (`None` for the other ends).
    pub fn vehicle_lost(&self) -> Option<String> {
        match self {
            MissionEnd::VehicleLost { silent_s } => Some(
                FateReason::VehicleLost {
                    silent_s: *silent_s,
                }
                .to_string(),
            ),
            _ => None,
        }
    }
}

impl std::fmt::Display for MissionEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MissionEnd::Finished => f.write_str("finished"),
            MissionEnd::NoGoals => f.write_str("no goal left to pursue"),
            MissionEnd::TimeLimit => f.write_str("time limit reached"),
            MissionEnd::CycleLimit => f.write_str("cycle limit reached"),
            MissionEnd::Error(e) => write!(f, "error: {e}"),
            MissionEnd::Interrupted(s) => write!(f, "interrupted by {s}"),
            MissionEnd::VehicleLost { silent_s } => {
                write!(f, "vehicle lost: no heartbeat for {silent_s} s")
            }
        }
    }
}

/// A change of *ExecutingPlan*.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlanChangeRecord {
    pub time_ms: Time,
    /// `repair`, `replan` or `goal_added`.
    pub cause: String,
    /// Actions in the plan afterwards (running and future).
    pub actions: usize,
}

/// `[RscL_lb, RscL_ub]` of a resource at a cycle, with the level the vehicle reported in it, if any.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ResourceSample {
    pub time_ms: Time,
    pub resource: String,
    pub lb: f64,
    pub ub: f64,
    pub reported: Option<f64>,
}

/// Where the vehicle was (metres east and north of home) at a cycle: the report's track.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrackPoint {
    pub time_ms: Time,
    pub east: f64,
    pub north: f64,
}

/// A place of the final plan's problem (a location object with coordinates, metres from home).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Place {
    pub name: String,
    pub east: f64,
    pub north: f64,
    /// The goals whose proposition names this place.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub goals: Vec<String>,
}

/// Everything a mission did: the `--report` JSON.
#[derive(Clone, Debug, Serialize)]
pub struct MissionReport {
    pub end: MissionEnd,
    /// Mission time at the end, ms since origin.
    pub duration_ms: Time,
    pub goals: Vec<GoalFate>,
    pub counters: Counters,
    pub cycle_times: CycleTimes,
    pub plan_changes: Vec<PlanChangeRecord>,
    pub resources: Vec<ResourceSample>,
    /// The resources that are reservoirs (levels produced and consumed, e.g. battery, storage): the ones
    /// whose level against its bounds the report draws.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub reservoirs: Vec<String>,
    /// The vehicle's positions (a point when it moved 0.5 m or more), empty when it reports none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub track: Vec<TrackPoint>,
    /// The places of the final plan's problem (initial ones and those named by goal uploads).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub places: Vec<Place>,
    /// The cycles: busy ones whole, each run of cycles with no event as one record (`idle`); how many
    /// cycles ran is `cycle_times.count`.
    pub cycles: Vec<CycleRecord>,
    /// Every complete replanning: the abort that caused it, its attempts (goals, planning steps, how each
    /// search ended), its outcome, the goals kept and those rejected with their reasons.
    pub replannings: Vec<ReplanRecord>,
    /// What was done to leave the vehicle safe after an interruption (set by the caller that did it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shutdown: Option<SafeStopReport>,
    /// How the vehicle became ready (a fix, arming, the estimator) before the mission (set by the caller
    /// that waited).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ready: Option<mavtempo_vehicle::readiness::ReadyReport>,
}

impl MissionReport {
    /// For each action instance (task and arguments) launched, the most launches in a row without a
    /// nominal completion between them: its retries. (The same instance done again after a success, e.g. a
    /// pan-and-tilt unit turned down for each picture, is new work and starts a new count.)
    /// An action the executive stopped by the plan (a preemptive action's end, not an abort) and that then
    /// reports `interrupted` ended as planned: that counts as a completion too.
    pub fn launches_in_a_row(&self) -> BTreeMap<String, usize> {
        let mut run: BTreeMap<&str, usize> = BTreeMap::new();
        let mut worst: BTreeMap<String, usize> = BTreeMap::new();
        let mut stopped_by_plan: Vec<&str> = Vec::new();
        for c in &self.cycles {
            let aborted = c
                .events
                .iter()
                .any(|e| matches!(e, TraceEvent::Abort { .. }));
            for e in &c.events {
                match e {
                    TraceEvent::Launch { action, .. } => {
                        let n = run.entry(action).or_default();
                        *n += 1;
                        let w = worst.entry(action.clone()).or_default();
                        *w = (*w).max(*n);
                    }
                    TraceEvent::Stop { action, .. } if !aborted => stopped_by_plan.push(action),
                    TraceEvent::Report { action, status, .. } => {
                        let planned_stop = stopped_by_plan.iter().position(|a| a == action);
                        if let Some(i) = planned_stop {
                            stopped_by_plan.swap_remove(i);
                        }
                        if *status == ReportStatus::Nominal
                            || (*status == ReportStatus::Interrupted && planned_stop.is_some())
                        {
                            run.remove(action.as_str());
                        }
                    }
                    _ => {}
                }
            }
        }
        worst
    }
}

/// The vehicle as the cycle sees it: events the pacer received while waiting come out first.
struct Held<'a, V: Vehicle> {
    inner: &'a mut V,
    held: VecDeque<VehicleEvent>,
}

impl<V: Vehicle> Vehicle for Held<'_, V> {
    fn start(&mut self, action: ActionStart) -> Result<(), VehicleError> {
        self.inner.start(action)
    }
    fn start_still(&mut self, action: ActionStart) -> Result<(), VehicleError> {
        self.inner.start_still(action)
    }
    fn stop(&mut self, id: VehicleActionId) -> Result<(), VehicleError> {
        self.inner.stop(id)
    }
    fn try_event(&mut self) -> Option<VehicleEvent> {
        self.held.pop_front().or_else(|| self.inner.try_event())
    }
    fn wait_event(&mut self, timeout: Duration) -> Option<VehicleEvent> {
        self.held
            .pop_front()
            .or_else(|| self.inner.wait_event(timeout))
    }
    fn now_ms(&self) -> u64 {
        self.inner.now_ms()
    }
    fn position(&self) -> Option<(f64, f64)> {
        self.inner.position()
    }
    fn silence(&self) -> Option<Duration> {
        self.inner.silence()
    }
    fn clock_age(&self) -> Option<Duration> {
        self.inner.clock_age()
    }
}

/// Runs `ex` against `vehicle` until every goal is settled, no goal is left, or the time limit passes.
/// `observe` sees each cycle as it ends (the CLI prints the trace from it).
pub fn run_mission<V: Vehicle>(
    ex: &mut Executive,
    vehicle: &mut V,
    pacer: &mut dyn Pacer<V>,
    opts: &MissionOptions,
    observe: &mut dyn FnMut(&Executive, &CycleRecord),
) -> MissionReport {
    let mut v = Held {
        inner: vehicle,
        held: VecDeque::new(),
    };
    ex.vehicle.set_origin(pacer.origin_ms());
    if !opts.initial_goals.is_empty() {
        v.held.push_back(VehicleEvent::Goals(GoalBatch::detached(
            opts.initial_goals.clone(),
        )));
    }
    let mut log = Log::default();
    let end = loop {
        if let Some(signal) = opts.interrupt.requested() {
            break MissionEnd::Interrupted(signal_name(signal));
        }
        if let Some(silent) = lost(v.inner, opts) {
            break MissionEnd::VehicleLost {
                silent_s: silent.as_secs(),
            };
        }
        let now = pacer.now(v.inner);
        let outcome = ex.cycle(&mut v, now);
        log.after_cycle(ex, now);
        log.position(now, v.inner.position());
        if let Some(c) = ex.journal.cycles().last() {
            observe(ex, c);
        }
        let wake = match outcome {
            CycleOutcome::Finished => break MissionEnd::Finished,
            CycleOutcome::Aborted(_) => {
                let result = replan(ex, &mut v, pacer);
                let t = pacer.now(v.inner);
                // The replanning's attempts, its outcome and its rejections: a record of their own.
                if let Some(c) = ex.flush_trace(t) {
                    observe(ex, &c);
                }
                match result {
                    Ok(()) => {
                        log.change(t, "replan", ex.plan.num_actions());
                        // The new plan's first cycle right away.
                        continue;
                    }
                    Err(end) => break end,
                }
            }
            CycleOutcome::Continue { next, repairing } => {
                // §3.2: wake on a message, a due timepoint, or the next cycle while repairing; at the latest
                // one timestep later (timeouts are checked every cycle).
                let ts = ex.cfg.timestep_ms;
                let stopped = ex.journal.cycles().last().is_some_and(|c| {
                    c.events
                        .iter()
                        .any(|e| matches!(e, TraceEvent::Stop { .. }))
                });
                if repairing {
                    // The repair had its μ·ts this cycle; the next cycle goes on with it.
                    now + ex.cfg.repair_budget_ms().max(1)
                } else if stopped {
                    now + 1
                } else {
                    next.map_or(now + ts, |n| n.clamp(now + 1, now + ts))
                }
            }
        };
        if now >= opts.time_limit_ms {
            break MissionEnd::TimeLimit;
        }
        if opts
            .max_cycles
            .is_some_and(|m| ex.journal.cycles().count() >= m as u64)
        {
            break MissionEnd::CycleLimit;
        }
        let until = wake.min(opts.time_limit_ms.max(now + 1));
        if let Some(e) = pacer.wait_or_interrupt(v.inner, until, &opts.interrupt) {
            v.held.push_back(e);
        }
    };
    let duration_ms = pacer.now(v.inner);
    if let Some(c) = ex.flush_trace(duration_ms) {
        // The last abort and the replanning that ended the mission (its rejections) are in the report.
        observe(ex, &c);
    }
    log.report(ex, end, duration_ms)
}

/// The link timeout, once the vehicle has been silent that long (`opts.vehicle_lost_after`).
fn lost<V: Vehicle>(v: &V, opts: &MissionOptions) -> Option<Duration> {
    let limit = opts.vehicle_lost_after?;
    v.silence().filter(|s| *s >= limit).map(|_| limit)
}

/// §3.6: complete replanning at the current time; S_t refreshed from the vehicle between attempts (the
/// paper's suggested improvement). Goals left pending by a failed replanning are rejected by it.
fn replan<V: Vehicle>(
    ex: &mut Executive,
    v: &mut Held<'_, V>,
    pacer: &mut dyn Pacer<V>,
) -> Result<(), MissionEnd> {
    collect_stop_reports(ex, v, pacer);
    let cell = std::cell::RefCell::new(v);
    let now = || pacer.now(cell.borrow().inner);
    let result = ex.replan(&now, &mut |ex: &mut Executive| {
        let t = now();
        let mut v = cell.borrow_mut();
        // Only what the vehicle sent since: the held events stay held.
        while let Some(e) = v.inner.try_event() {
            if matches!(e, VehicleEvent::Resource(_) | VehicleEvent::Capacity(_)) {
                ex.integrate(e, t);
            } else {
                // Reports and goals wait for the new plan's first cycle.
                v.held.push_back(e);
            }
        }
    });
    match result {
        ReplanResult::Plan(plan) => {
            ex.adopt(plan);
            let t = pacer.now(cell.borrow().inner);
            ex.plan_changed(t, super::failures::PlanChangeKind::Replan);
            Ok(())
        }
        ReplanResult::NoGoals(plan) => {
            ex.adopt(plan);
            // A new goal waiting for its insertion attempt still gets it, on the plan left.
            if !ex.goals.is_inserting() {
                Err(MissionEnd::NoGoals)
            } else {
                Ok(())
            }
        }
        ReplanResult::Error(e) => Err(MissionEnd::Error(e)),
    }
}

/// How long (mission time, and wall time on the companion's clock) to wait for the reports of the actions
/// stopped by an abort, ms.
const STOP_REPORT_WAIT_MS: Time = 2_000;

/// §3.6: S_ti = S_ts, the state once the running actions are stopped: their reports (e.g. the position a
/// stopped move reached) are integrated into the aborted plan before P_ti is extracted, or the state would
/// keep the values they left unknown (a position of +oo from which nothing can be planned). Other events
/// wait for the new plan's first cycle.
fn collect_stop_reports<V: Vehicle>(
    ex: &mut Executive,
    v: &mut Held<'_, V>,
    pacer: &mut dyn Pacer<V>,
) {
    // Bounded in mission time (the pacer lets it pass, a stepped simulator's too) and in wall time.
    let wall = ex.wall.clone();
    let wall_until = wall.now().saturating_add(STOP_REPORT_WAIT_MS);
    let until = pacer.now(v.inner).saturating_add(STOP_REPORT_WAIT_MS);
    let waiting = |pacer: &dyn Pacer<V>, v: &V| wall.now() < wall_until && pacer.now(v) < until;
    let mut kept = VecDeque::new();
    let outstanding = |ex: &Executive| {
        ex.dispatched
            .stopping()
            .any(|a| !ex.plan.is_executed(ex.plan.action(a).end))
    };
    let mut held = std::mem::take(&mut v.held);
    loop {
        let next = match held.pop_front() {
            Some(e) => Some(e),
            None if outstanding(ex) && waiting(pacer, v.inner) => pacer.wait(v.inner, until),
            None => v.inner.try_event(),
        };
        let Some(e) = next else {
            if !outstanding(ex) || !waiting(pacer, v.inner) {
                break;
            }
            continue;
        };
        match e {
            VehicleEvent::Report(r) if ex.dispatched.action_of(r.id).is_some() => {
                let t = pacer.now(v.inner);
                ex.integrate(VehicleEvent::Report(r), t);
            }
            other => kept.push_back(other),
        }
    }
    v.held = kept;
}

/// What the report collects beyond the executive's own trace.
#[derive(Default)]
struct Log {
    changes: Vec<PlanChangeRecord>,
    resources: Vec<ResourceSample>,
    last_bounds: Vec<Option<(f64, f64)>>,
    /// The reported level of each resource already in `resources`.
    last_reported: Vec<Option<(Time, f64)>>,
    track: Vec<TrackPoint>,
}

impl Log {
    fn change(&mut self, time_ms: Time, cause: &str, actions: usize) {
        self.changes.push(PlanChangeRecord {
            time_ms,
            cause: cause.into(),
            actions,
        });
    }

    /// Adds `at` to the track when the vehicle moved at least 0.5 m since the last point.
    fn position(&mut self, now: Time, at: Option<(f64, f64)>) {
        let Some((east, north)) = at else { return };
        if moved_on(self.track.last().map(|p| (p.east, p.north)), (east, north)) {
            self.track.push(TrackPoint {
                time_ms: now,
                east,
                north,
            });
        }
    }

    fn after_cycle(&mut self, ex: &Executive, now: Time) {
        let Some(c) = ex.journal.cycles().last() else {
            return;
        };
        for e in &c.events {
            match e {
                TraceEvent::RepairDone { .. } => self.change(now, "repair", ex.plan.num_actions()),
                TraceEvent::GoalAccepted { .. } => {
                    self.change(now, "goal_added", ex.plan.num_actions())
                }
                _ => {}
            }
        }
        let bounds = resource_bounds_now(ex, now);
        self.last_bounds.resize(bounds.len(), None);
        self.last_reported.resize(bounds.len(), None);
        for (i, (name, lb, ub)) in bounds.into_iter().enumerate() {
            let reported = fresh_level(ex, i, &mut self.last_reported[i]);
            // Only changes (and reports) make it into the report: a mission has thousands of cycles.
            if reported.is_some() || self.last_bounds[i] != Some((lb, ub)) {
                self.last_bounds[i] = Some((lb, ub));
                self.resources.push(ResourceSample {
                    time_ms: now,
                    resource: name,
                    lb,
                    ub,
                    reported,
                });
            }
        }
    }

    fn report(self, ex: &Executive, end: MissionEnd, duration_ms: Time) -> MissionReport {
        let mut goals = ex.goal_fates();
        if end == MissionEnd::CycleLimit {
            for g in goals.iter_mut().filter(|g| g.fate == Fate::Pending) {
                g.reason = Some(FateReason::CycleLimit);
            }
        }
        if end == MissionEnd::TimeLimit {
            for g in goals.iter_mut().filter(|g| g.fate == Fate::Pending) {
                g.reason = Some(FateReason::TimeLimit);
            }
        }
        if let MissionEnd::Interrupted(signal) = &end {
            for g in goals.iter_mut().filter(|g| g.fate == Fate::Pending) {
                g.reason = Some(FateReason::Interrupted {
                    signal: signal.to_string(),
                });
            }
        }
        if let MissionEnd::VehicleLost { silent_s } = end {
            for g in goals.iter_mut().filter(|g| g.fate == Fate::Pending) {
                g.reason = Some(FateReason::VehicleLost { silent_s });
            }
        }
        MissionReport {
            end,
            duration_ms,
            goals,
            counters: ex.journal.counters().clone(),
            cycle_times: ex.journal.cycles().times(),
            plan_changes: self.changes,
            resources: self.resources,
            reservoirs: ex
                .plan
                .domain()
                .resources
                .iter()
                .filter(|r| r.kind == mavtempo_temporal::model::ResourceKind::Reservoir)
                .map(|r| r.name.clone())
                .collect(),
            track: self.track,
            places: places(ex),
            cycles: ex.journal.cycles().records().to_vec(),
            replannings: ex.journal.replannings().to_vec(),
            shutdown: None,
            ready: None,
        }
    }
}

/// Whether a position `at` is a new point of the track after `last` (0.5 m or more away).
pub fn moved_on(last: Option<(f64, f64)>, at: (f64, f64)) -> bool {
    last.is_none_or(|(e, n)| (e - at.0).hypot(n - at.1) >= 0.5)
}

/// The level the vehicle reported for resource `i` (telemetry or an action's report) if it is newer than
/// `seen`, which then becomes it.
pub fn fresh_level(ex: &Executive, i: usize, seen: &mut Option<(Time, f64)>) -> Option<f64> {
    let last = ex.ledger.last_reported(ResourceId::from_index(i))?;
    (*seen != Some(last)).then(|| {
        *seen = Some(last);
        last.1
    })
}

/// `[RscL_lb, RscL_ub]` of every resource at `now`, by resource index, with its name.
pub fn resource_bounds_now(ex: &Executive, now: Time) -> Vec<(String, f64, f64)> {
    let running = classify(&ex.plan, now).running;
    ex.plan
        .domain()
        .resources
        .iter()
        .enumerate()
        .map(|(i, res)| {
            let r = ResourceId::from_index(i);
            let b = level_bounds(&ex.plan, r, now, &running, ex.ledger.past(r));
            (res.name.clone(), b.lb, b.ub)
        })
        .collect()
}

/// The final problem's location objects with coordinates (metres from the problem's home).
pub fn places(ex: &Executive) -> Vec<Place> {
    let problem = &ex.plan.problem();
    let home = problem.home.as_ref();
    problem
        .objects
        .iter()
        .enumerate()
        .filter_map(|(i, o)| {
            let (east, north, _) = o.local(home)?;
            let id = mavtempo_temporal::model::ObjectId::from_index(i);
            let goals = problem
                .goals
                .iter()
                .filter(|g| {
                    g.args.contains(&id) || g.value == mavtempo_temporal::model::Value::Obj(id)
                })
                .map(|g| g.name.clone())
                .collect();
            Some(Place {
                name: o.name.clone(),
                east,
                north,
                goals,
            })
        })
        .collect()
}
