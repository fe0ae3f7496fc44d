//! The charts' data, extracted from a mission report (the `--report` JSON of `demo`, `run`, `soak`) or
//! folded cycle by cycle from a live mission: pure functions, no drawing.
//!
//! The report is read through views of the fields the charts need, so reports written before a field
//! existed (no `track`, no `planned_end_ms`) still draw; the cycles' events are the executive's
//! [`TraceEvent`]s read back.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::exec::trace::TraceEvent;
use crate::model::Time;

/// A mission report as the charts read it.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct RunView {
    #[serde(default)]
    pub end: serde_json::Value,
    pub duration_ms: Time,
    pub goals: Vec<GoalView>,
    #[serde(default)]
    pub counters: BTreeMap<String, serde_json::Value>,
    #[serde(default)]
    pub resources: Vec<SampleView>,
    /// The reservoirs (reports before this field: every resource is drawn).
    #[serde(default)]
    pub reservoirs: Vec<String>,
    #[serde(default)]
    pub track: Vec<PointView>,
    #[serde(default)]
    pub places: Vec<PlaceView>,
    pub cycles: Vec<CycleView>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GoalView {
    pub name: String,
    pub fate: String,
    #[serde(default)]
    pub reason: String,
    /// The live page's detail (issue 30): the proposition, e.g. `PICTURE(g6_loc) = true`.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub what: String,
    /// The place it names, with its position from home.
    #[serde(default, rename = "where", skip_serializing_if = "String::is_empty")]
    pub place: String,
    /// Its start window.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub window: String,
    /// `problem`, `ground station S/C` (the station that holds it), or `upload`.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub source: String,
    /// The state an operator reads: `accepted` (held in the plan), `inserting`, `achieved`, `rejected`,
    /// `cancelled`; the fate when empty (a report).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub state: String,
    /// The page offers to withdraw it (its form is on and a ground station holds it).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub cancellable: bool,
}

/// `[lb, ub]` of a resource at a time, with the level the vehicle reported then, if any.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SampleView {
    pub time_ms: Time,
    pub resource: String,
    pub lb: f64,
    pub ub: f64,
    #[serde(default)]
    pub reported: Option<f64>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PointView {
    pub time_ms: Time,
    pub east: f64,
    pub north: f64,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlaceView {
    pub name: String,
    pub east: f64,
    pub north: f64,
    #[serde(default)]
    pub goals: Vec<String>,
}

#[derive(Clone, Debug, Default, Deserialize)]
pub struct CycleView {
    pub time_ms: Time,
    #[serde(default)]
    pub events: Vec<TraceEvent>,
}

/// One executed action: from its start to its report (`end_ms: None`: still running).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bar {
    pub action: String,
    pub start_ms: Time,
    pub end_ms: Option<Time>,
    /// `nominal`, `failed`, `interrupted`, or `running`.
    pub status: String,
    /// The planned window of its end when it started (`None` upper bound: unbounded).
    pub planned_end_ms: Option<(Time, Option<Time>)>,
}

/// An action of the current plan not started yet (live page): its earliest start and end.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlannedBar {
    pub action: String,
    pub start_ms: Time,
    pub end_ms: Time,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MarkKind {
    Repair,
    Replan,
    Abort,
    /// A goal request received (an upload over MAVLink or the page's form).
    GoalArrival,
    GoalAchieved,
    GoalRejected,
}

/// Something marked on the time axis.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Mark {
    pub time_ms: Time,
    pub kind: MarkKind,
    pub label: String,
}

/// A reservoir's bounds over time (steps: each holds until the next) and its reported levels.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Series {
    pub resource: String,
    pub bounds: Vec<(Time, f64, f64)>,
    pub reported: Vec<(Time, f64)>,
}

/// Everything the page draws.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Charts {
    /// Mission time the charts end at (the report's duration, or now on the live page).
    pub now_ms: Time,
    /// How the mission ended (`None` while it runs).
    pub end: Option<String>,
    pub bars: Vec<Bar>,
    pub planned: Vec<PlannedBar>,
    pub marks: Vec<Mark>,
    pub series: Vec<Series>,
    pub track: Vec<PointView>,
    pub places: Vec<PlaceView>,
    pub goals: Vec<GoalView>,
    /// The vehicle as last heard (the live page).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vehicle: Option<crate::vehicle::status::VehicleStatus>,
    pub counters: BTreeMap<String, serde_json::Value>,
    /// The last trace lines, newest last.
    pub events: Vec<String>,
}

/// How many trace lines the page keeps.
pub const LAST_EVENTS: usize = 40;

impl Charts {
    /// The charts of a whole mission report.
    pub fn from_report(r: &RunView) -> Charts {
        let mut c = Charts::default();
        for cycle in &r.cycles {
            c.push_cycle(cycle);
        }
        let drawn = |s: &&SampleView| r.reservoirs.is_empty() || r.reservoirs.contains(&s.resource);
        for s in r.resources.iter().filter(drawn) {
            c.push_sample(s);
        }
        c.now_ms = r.duration_ms;
        c.end = Some(end_text(&r.end));
        c.track = r.track.clone();
        c.places = r.places.clone();
        c.goals = r.goals.clone();
        c.counters = r.counters.clone();
        c
    }

    /// Folds one cycle's events into the bars, the marks and the last events.
    pub fn push_cycle(&mut self, cycle: &CycleView) {
        let t = cycle.time_ms;
        self.now_ms = self.now_ms.max(t);
        for e in &cycle.events {
            if let Some(line) = event_line(e) {
                self.events
                    .push(format!("[{:>7.1} s] {line}", t as f64 / 1000.0));
            }
            match e {
                TraceEvent::Launch {
                    action,
                    planned_end_ms,
                    ..
                } => self.bars.push(Bar {
                    action: action.clone(),
                    start_ms: t,
                    end_ms: None,
                    status: "running".into(),
                    planned_end_ms: *planned_end_ms,
                }),
                TraceEvent::Report { action, status, .. } => {
                    // The report closes the latest bar of that action still open.
                    if let Some(b) = self
                        .bars
                        .iter_mut()
                        .rev()
                        .find(|b| &b.action == action && b.end_ms.is_none())
                    {
                        b.end_ms = Some(t.max(b.start_ms));
                        b.status = status.to_string();
                    }
                }
                TraceEvent::GoalReceived { goal } => self.mark(t, MarkKind::GoalArrival, goal),
                TraceEvent::GoalAchieved { goal } => self.mark(t, MarkKind::GoalAchieved, goal),
                TraceEvent::GoalRejected { goal, .. } => self.mark(t, MarkKind::GoalRejected, goal),
                TraceEvent::RepairDone { .. } => self.mark(t, MarkKind::Repair, "repair"),
                TraceEvent::Abort { .. } => self.mark(t, MarkKind::Abort, "abort"),
                TraceEvent::ReplanDone { .. } => self.mark(t, MarkKind::Replan, "replan"),
                _ => {}
            }
        }
        let excess = self.events.len().saturating_sub(LAST_EVENTS);
        self.events.drain(..excess);
    }

    /// Adds one resource sample to its series (series in order of first appearance).
    pub fn push_sample(&mut self, s: &SampleView) {
        let i = match self.series.iter().position(|x| x.resource == s.resource) {
            Some(i) => i,
            None => {
                self.series.push(Series {
                    resource: s.resource.clone(),
                    ..Series::default()
                });
                self.series.len() - 1
            }
        };
        let series = &mut self.series[i];
        if series.bounds.last().map(|b| (b.1, b.2)) != Some((s.lb, s.ub)) {
            series.bounds.push((s.time_ms, s.lb, s.ub));
        }
        if let Some(level) = s.reported {
            series.reported.push((s.time_ms, level));
        }
        self.now_ms = self.now_ms.max(s.time_ms);
    }

    fn mark(&mut self, time_ms: Time, kind: MarkKind, label: &str) {
        self.marks.push(Mark {
            time_ms,
            kind,
            label: label.to_string(),
        });
    }

    /// The Gantt chart's rows: each action text once, in the order it first starts (then planned ones).
    pub fn rows(&self) -> Vec<String> {
        let mut rows: Vec<String> = Vec::new();
        let names = self.bars.iter().map(|b| &b.action);
        for a in names.chain(self.planned.iter().map(|p| &p.action)) {
            if !rows.contains(a) {
                rows.push(a.clone());
            }
        }
        rows
    }

    /// The bounds of `series` at time `t` (the last sample at or before it).
    pub fn bounds_at(series: &Series, t: Time) -> Option<(f64, f64)> {
        series
            .bounds
            .iter()
            .take_while(|b| b.0 <= t)
            .last()
            .map(|b| (b.1, b.2))
    }
}

/// `finished`, `time_limit`, `interrupted (SIGTERM)`...
pub fn end_text(end: &serde_json::Value) -> String {
    match end {
        serde_json::Value::String(s) => s.clone(),
        serde_json::Value::Object(m) => m
            .iter()
            .map(|(k, v)| match v.as_str() {
                Some(s) => format!("{k} ({s})"),
                None => k.clone(),
            })
            .collect::<Vec<_>>()
            .join(", "),
        serde_json::Value::Null => "unknown".into(),
        other => other.to_string(),
    }
}

/// The trace line of an event the page lists (the others stay in the JSON): the executive's own wording.
fn event_line(e: &TraceEvent) -> Option<String> {
    matches!(
        e,
        TraceEvent::Launch { .. }
            | TraceEvent::Report { .. }
            | TraceEvent::GoalReceived { .. }
            | TraceEvent::GoalAccepted { .. }
            | TraceEvent::GoalRejected { .. }
            | TraceEvent::GoalAchieved { .. }
            | TraceEvent::RepairDone { .. }
            | TraceEvent::Abort { .. }
            | TraceEvent::ReplanDone { .. }
    )
    .then(|| e.line())
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::exec::report_timing::Timing;
    use crate::vehicle::ReportStatus;

    fn cycle(time_ms: Time, events: Vec<TraceEvent>) -> CycleView {
        CycleView { time_ms, events }
    }

    fn launch(a: &str) -> TraceEvent {
        TraceEvent::Launch {
            action: a.into(),
            vid: 1,
            planned_end_ms: Some((4_000, None)),
        }
    }

    fn report(a: &str, status: ReportStatus) -> TraceEvent {
        TraceEvent::Report {
            action: a.into(),
            status,
            timing: Timing::InBounds,
            reason: None,
        }
    }

    #[test]
    fn a_bar_spans_launch_to_report_and_a_relaunch_is_a_new_bar() {
        let mut c = Charts::default();
        c.push_cycle(&cycle(1_000, vec![launch("a"), launch("b")]));
        c.push_cycle(&cycle(3_000, vec![report("a", ReportStatus::Failed)]));
        c.push_cycle(&cycle(
            4_000,
            vec![launch("a"), report("zz", ReportStatus::Nominal)],
        ));
        c.push_cycle(&cycle(6_000, vec![report("a", ReportStatus::Nominal)]));
        let spans: Vec<_> = c
            .bars
            .iter()
            .map(|b| (b.action.as_str(), b.start_ms, b.end_ms, b.status.as_str()))
            .collect();
        assert_eq!(
            spans,
            [
                ("a", 1_000, Some(3_000), "failed"),
                ("b", 1_000, None, "running"),
                ("a", 4_000, Some(6_000), "nominal"),
            ]
        );
        assert_eq!(c.rows(), ["a", "b"]);
        assert_eq!(c.now_ms, 6_000);
    }

    #[test]
    fn bounds_hold_until_the_next_change_and_only_reports_are_points() {
        let mut c = Charts::default();
        let s = |t, lb, ub, reported| SampleView {
            time_ms: t,
            resource: "STORAGE".into(),
            lb,
            ub,
            reported,
        };
        c.push_sample(&s(0, 3.0, 3.0, None));
        c.push_sample(&s(500, 3.0, 3.0, Some(3.0)));
        c.push_sample(&s(900, 1.0, 2.0, None));
        let st = &c.series[0];
        assert_eq!(st.bounds, [(0, 3.0, 3.0), (900, 1.0, 2.0)]);
        assert_eq!(st.reported, [(500, 3.0)]);
        assert_eq!(Charts::bounds_at(st, 899), Some((3.0, 3.0)));
        assert_eq!(Charts::bounds_at(st, 900), Some((1.0, 2.0)));
        assert_eq!(Charts::bounds_at(st, -1), None);
    }

    #[test]
    fn the_last_events_are_bounded() {
        let mut c = Charts::default();
        for i in 0..(LAST_EVENTS as i64 + 5) {
            c.push_cycle(&cycle(
                i,
                vec![TraceEvent::GoalAchieved {
                    goal: format!("g{i}"),
                }],
            ));
        }
        assert_eq!(c.events.len(), LAST_EVENTS);
        assert!(c.events[LAST_EVENTS - 1].ends_with(&format!("g{} achieved", LAST_EVENTS + 4)));
    }
}
