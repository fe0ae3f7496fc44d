//! The live page (`--http ADDR`): an axum server on the mission's tokio runtime serving the report page
//! of the mission so far, pushed to the browser as server-sent events.
//!
//! The mission loop never waits for the server: each cycle it hands a [`LiveFeed`] what happened (the
//! cycle's record, the bounds, the plan's next actions, the goals' fates) over an unbounded channel; a task
//! folds those into [`Charts`], renders at most every [`RENDER_EVERY`] and publishes the page body through
//! a `watch` channel that every event stream reads.
//!
//! The goal form and cancel buttons (off unless enabled) are in [`super::form`]; the connections' bounds in
//! [`super::guard`].

use std::collections::BTreeMap;
use std::convert::Infallible;
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use axum::extract::State;
use axum::http::StatusCode;
use axum::response::sse::{Event, KeepAlive, Sse};
use axum::response::{Html, Json};
use axum::routing::{get, post};
use axum::Router;
use tokio::sync::{mpsc, watch};

use super::data::{Charts, CycleView, GoalView, PlaceView, PlannedBar, PointView, SampleView};
pub use super::form::{
    cancel_verdict, parse_goal, verdict_of, CancelError, FormError, GoalAnswer, GoalCancelFn,
    GoalForm, GoalItems, GoalSubmit, PictureGoal,
};
use super::goal_rows::{goal_rows, Sources};
use super::guard::{GuardedListener, PageLimits, Slots};
use super::html;
use crate::exec::executive::Executive;
use crate::exec::mission::{fresh_level, moved_on, places, resource_bounds_now, MissionReport};
use crate::exec::trace::CycleRecord;
use crate::vehicle::intake::GoalIntake;
use crate::vehicle::link::PositionProbe;
use crate::vehicle::status::{StatusProbe, VehicleStatus};

/// How often at most the page is rendered again.
pub const RENDER_EVERY: Duration = Duration::from_millis(250);

/// What the live page shows at one time.
#[derive(Clone, Debug, Default)]
pub struct Snapshot {
    pub charts: Charts,
    pub body: String,
}

pub(super) struct AppState {
    snapshot: watch::Sender<Arc<Snapshot>>,
    pub(super) form: Option<GoalForm>,
    /// Where the page is bound: the Host a POST must name (besides loopback names).
    pub(super) bound: SocketAddr,
    /// How often an event stream with nothing new says it is alive (well within the idle timeout).
    keep_alive: Duration,
}

/// One cycle as the mission loop hands it over.
enum Update {
    Cycle {
        record: Box<CycleRecord>,
        samples: Vec<SampleView>,
        planned: Option<Vec<PlannedBar>>,
        /// The places, looked at with the plan (goals add places).
        places: Option<Vec<PlaceView>>,
        track: Option<PointView>,
        goals: Vec<GoalView>,
        vehicle: Option<Box<VehicleStatus>>,
        counters: BTreeMap<String, serde_json::Value>,
    },
    End(Box<Charts>),
}

/// The mission loop's side: cheap, never blocks.
pub struct LiveFeed {
    tx: mpsc::UnboundedSender<Update>,
    last_reported: Vec<Option<(crate::model::Time, f64)>>,
    position: Option<PositionProbe>,
    last_position: Option<(f64, f64)>,
    status: Option<StatusProbe>,
    intake: Option<Arc<Mutex<GoalIntake>>>,
    sources: Sources,
    /// The page withdraws held goals (its form is on, with a cancel path).
    cancel: bool,
}

impl LiveFeed {
    /// The track is drawn from `probe`'s positions (a point when the vehicle moved 0.5 m or more).
    pub fn with_position(mut self, probe: PositionProbe) -> Self {
        self.position = Some(probe);
        self
    }

    /// The vehicle's mode, arming, battery and link from `status`; which ground station holds which goal
    /// from `intake`.
    pub fn with_vehicle(mut self, status: StatusProbe, intake: Arc<Mutex<GoalIntake>>) -> Self {
        self.status = Some(status);
        self.intake = Some(intake);
        self
    }

    /// What one cycle changed (call it from the mission's `observe`).
    pub fn observe(&mut self, ex: &Executive, c: &CycleRecord) {
        let now = c.time_ms;
        let bounds = resource_bounds_now(ex, now);
        self.last_reported.resize(bounds.len(), None);
        let samples = bounds
            .into_iter()
            .enumerate()
            .filter(|(i, _)| {
                let kind = ex.plan().domain().resources.get(*i).map(|r| r.kind);
                kind == Some(crate::model::ResourceKind::Reservoir)
            })
            .map(|(i, (resource, lb, ub))| SampleView {
                time_ms: now,
                resource,
                lb,
                ub,
                reported: fresh_level(ex, i, &mut self.last_reported[i]),
            })
            .collect();
        // The plan only changes with events: its next actions are looked at then.
        let look = !c.events.is_empty() || c.index.is_multiple_of(20);
        let planned = look.then(|| planned_bars(ex));
        let places = look.then(|| {
            places(ex)
                .into_iter()
                .map(|p| PlaceView {
                    name: p.name,
                    east: p.east,
                    north: p.north,
                    goals: p.goals,
                })
                .collect()
        });
        let holders = self
            .intake
            .as_ref()
            .and_then(|i| i.try_lock().ok().map(|i| i.held().holders()))
            .unwrap_or_default();
        let goals = goal_rows(ex, &holders, &mut self.sources, self.cancel);
        let vehicle = self.status.as_ref().map(|s| Box::new(s()));
        let mut counters = counters_of(ex.counters());
        // Who commands the vehicle (issue 30): the page says when the operator has it.
        let control = ex.paused_why().map_or("companion".to_string(), |why| {
            format!("operator (paused: {why})")
        });
        counters.insert("control".into(), serde_json::Value::String(control));
        let at = self.position.as_ref().and_then(|p| p());
        let moved = at.filter(|&p| moved_on(self.last_position, p));
        if moved.is_some() {
            self.last_position = moved;
        }
        let track = moved.map(|(east, north)| PointView {
            time_ms: now,
            east,
            north,
        });
        let _ = self.tx.send(Update::Cycle {
            record: Box::new(c.clone()),
            samples,
            planned,
            places,
            track,
            goals,
            vehicle,
            counters,
        });
    }

    /// The mission's report: the page shows it whole from now on.
    pub fn finish(&self, report: &MissionReport) {
        match super::charts_of(report) {
            Ok(charts) => {
                let _ = self.tx.send(Update::End(Box::new(charts)));
            }
            Err(e) => tracing::warn!("live page: final report: {e}"),
        }
    }
}

fn counters_of(c: &crate::exec::executive::Counters) -> BTreeMap<String, serde_json::Value> {
    match serde_json::to_value(c) {
        Ok(serde_json::Value::Object(m)) => m.into_iter().collect(),
        _ => BTreeMap::new(),
    }
}

/// The actions of *ExecutingPlan* not started yet: earliest start and end.
fn planned_bars(ex: &Executive) -> Vec<PlannedBar> {
    let plan = ex.plan();
    plan.live_actions()
        .filter(|&a| !ex.has_started(a))
        .map(|a| {
            let act = plan.action(a);
            PlannedBar {
                action: ex.action_text(a),
                start_ms: plan.temporal_network().lb(act.start),
                end_ms: plan.temporal_network().lb(act.end),
            }
        })
        .collect()
}

/// A running live page.
pub struct LiveServer {
    pub addr: SocketAddr,
    pub feed: LiveFeed,
    /// Its connections (how many are open, refused, evicted).
    pub slots: Arc<Slots>,
}

/// Binds `addr` and serves the live page on `rt` within the default [`PageLimits`]. `form`: the goal
/// form, enabled.
pub fn start(
    rt: &tokio::runtime::Handle,
    addr: SocketAddr,
    form: Option<GoalForm>,
) -> std::io::Result<LiveServer> {
    start_with(rt, addr, form, PageLimits::default())
}

/// [`start`] within `limits`.
pub fn start_with(
    rt: &tokio::runtime::Handle,
    addr: SocketAddr,
    form: Option<GoalForm>,
    limits: PageLimits,
) -> std::io::Result<LiveServer> {
    let listener = rt.block_on(tokio::net::TcpListener::bind(addr))?;
    let addr = listener.local_addr()?;
    let listener = GuardedListener::new(listener, limits);
    let slots = listener.slots();
    let first = Charts::default();
    let body = html::body(&first, true).unwrap_or_default();
    let (snapshot, _) = watch::channel(Arc::new(Snapshot {
        charts: first,
        body,
    }));
    let state = Arc::new(AppState {
        snapshot,
        form,
        bound: addr,
        keep_alive: (limits.idle_timeout / 3)
            .clamp(Duration::from_millis(100), Duration::from_secs(15)),
    });
    let cancel = state.form.as_ref().is_some_and(|f| f.cancel.is_some());
    let (tx, rx) = mpsc::unbounded_channel();
    rt.spawn(fold(rx, state.clone()));
    let app = router(state);
    rt.spawn(async move {
        if let Err(e) = axum::serve(listener, app).await {
            tracing::warn!("live page server: {e}");
        }
    });
    Ok(LiveServer {
        addr,
        feed: LiveFeed {
            tx,
            last_reported: Vec::new(),
            position: None,
            last_position: None,
            status: None,
            intake: None,
            sources: Sources::default(),
            cancel,
        },
        slots,
    })
}

/// Folds the mission's updates into the charts and publishes the page, at most every RENDER_EVERY.
async fn fold(mut rx: mpsc::UnboundedReceiver<Update>, state: Arc<AppState>) {
    let mut charts = Charts::default();
    let mut dirty = false;
    let mut tick = tokio::time::interval(RENDER_EVERY);
    let publish = |charts: &Charts, live: bool| match html::body(charts, live) {
        Ok(body) => {
            state.snapshot.send_replace(Arc::new(Snapshot {
                charts: charts.clone(),
                body,
            }));
        }
        Err(e) => tracing::warn!("live page: {e}"),
    };
    loop {
        tokio::select! {
            u = rx.recv() => match u {
                Some(Update::Cycle { record, samples, planned, places, track, goals, vehicle, counters }) => {
                    match serde_json::to_value(&*record).and_then(serde_json::from_value::<CycleView>) {
                        Ok(view) => charts.push_cycle(&view),
                        Err(e) => tracing::warn!("live page: cycle {}: {e}", record.index),
                    }
                    for s in &samples {
                        charts.push_sample(s);
                    }
                    if let Some(p) = planned {
                        charts.planned = p;
                    }
                    if let Some(p) = places {
                        charts.places = p;
                    }
                    charts.track.extend(track);
                    charts.goals = goals;
                    if let Some(v) = vehicle {
                        charts.vehicle = Some(*v);
                    }
                    charts.counters = counters;
                    dirty = true;
                }
                Some(Update::End(last)) => {
                    charts = *last;
                    charts.planned.clear();
                    publish(&charts, false);
                    dirty = false;
                }
                None => {
                    if dirty {
                        publish(&charts, true);
                    }
                    return;
                }
            },
            _ = tick.tick() => {
                if dirty {
                    publish(&charts, true);
                    dirty = false;
                }
            }
        }
    }
}

fn router(state: Arc<AppState>) -> Router {
    Router::new()
        .route("/", get(index))
        .route("/events", get(events))
        .route("/snapshot.json", get(snapshot))
        .route("/goal", post(super::form::goal))
        .route("/cancel", post(super::form::cancel))
        .route("/favicon.ico", get(|| async { StatusCode::NO_CONTENT }))
        .with_state(state)
}

async fn index(State(s): State<Arc<AppState>>) -> Html<String> {
    let snap = s.snapshot.borrow().clone();
    Html(html::live_page(&snap.body, s.form.is_some()))
}

async fn snapshot(State(s): State<Arc<AppState>>) -> Json<Charts> {
    Json(s.snapshot.borrow().charts.clone())
}

/// Each published body as one event, the current one first.
async fn events(
    State(s): State<Arc<AppState>>,
) -> Sse<impl futures_util::Stream<Item = Result<Event, Infallible>>> {
    let rx = s.snapshot.subscribe();
    let stream = futures_util::stream::unfold((rx, true), |(mut rx, first)| async move {
        if !first && rx.changed().await.is_err() {
            return None;
        }
        let body = rx.borrow_and_update().body.clone();
        Some((Ok(Event::default().data(body)), (rx, false)))
    });
    Sse::new(stream).keep_alive(KeepAlive::new().interval(s.keep_alive))
}
