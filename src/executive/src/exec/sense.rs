//! Sensing (seed 1 §3.2, §3.3): integrating the vehicle's messages into *ExecutingPlan*. Each message kind
//! is delegated to the file holding its rule; this file only routes and records. A goal request is mapped
//! to the domain here and waits for its insertion attempt (goal_insertion: the acceptance test of §3.3,
//! then a bounded plan repair beside the plan).

use super::capacity::{alter, CapacityOutcome};
use super::executable::plan_executable;
use super::executive::Executive;
use super::outcome::AbortReason;
use super::p_t::classify;
use super::report_timing::{integrate, timing};
use super::resource_bounds::level_bounds;
use super::resource_report::{integrate_level, LevelVerdict};
use super::state_update::{integrate_late_state, integrate_state};
use super::trace::TraceEvent;
use crate::mapping::{GoalShape, MappingError};
use mavtempo_temporal::model::{Goal, GoalOrigin, Time, TimeInterval, Value};
use mavtempo_vehicle::{ActionReport, GoalRequest, ReportStatus, ResourceLevel, VehicleEvent};

impl Executive {
    /// Integrates one message received at time `now`.
    pub fn integrate(&mut self, event: VehicleEvent, now: Time) {
        self.plan.message_integrated();
        match event {
            VehicleEvent::Report(r) => self.integrate_report(r, now),
            VehicleEvent::Resource(l) => self.integrate_level(&l, now),
            VehicleEvent::Capacity(c) => {
                let Some(r) = self.resource(&c.resource) else {
                    tracing::warn!(resource = %c.resource, "capacity of an unknown resource ignored");
                    return;
                };
                let running = classify(&self.plan, now).running;
                let outcome = alter(
                    self.plan.edit(),
                    &mut self.ledger,
                    r,
                    c.capacity,
                    now,
                    &running,
                );
                self.trace(TraceEvent::Capacity {
                    resource: c.resource.clone(),
                    capacity: c.capacity,
                    outcome,
                });
                match outcome {
                    CapacityOutcome::Abort => self.abort_with(AbortReason::CapacityAltered {
                        resource: c.resource.clone(),
                    }),
                    CapacityOutcome::Repair => self.repair.request(),
                    CapacityOutcome::Nothing => {}
                }
            }
            VehicleEvent::Goals(batch) => self.receive_goals(batch),
            VehicleEvent::Cancel(cancel) => self.cancel_goals(cancel, now),
            VehicleEvent::Link(status) => tracing::info!(?status, "vehicle link"),
            VehicleEvent::Authority(e) => self.authority_event(e, now),
        }
    }

    /// Report upon an action's completion: its time, then the levels, then (not nominal) the state.
    fn integrate_report(&mut self, r: ActionReport, now: Time) {
        let Some(a) = self.dispatched.action_of(r.id) else {
            tracing::warn!(id = r.id, "report for an unknown action ignored");
            return;
        };
        // The report carries the vehicle time of the completion (a stopped action ended when the END was
        // obeyed, usually a cycle before the report is integrated).
        let t = self.vehicle.mission_time_until(r.time_ms, now);
        // Nor before it started: a move already within its waypoint radius is reported done with the time
        // of the telemetry that showed it there, which may predate the START.
        let t = match self.plan.executed_at(self.plan.action(a).start) {
            Some(st) if st <= now => t.max(st),
            _ => t,
        };
        let when = timing(&self.plan, a, t);
        let name = self.action_text(a);
        self.trace(TraceEvent::Report {
            action: name.clone(),
            status: r.status,
            timing: when,
            reason: r.reason.clone(),
        });
        match r.status {
            ReportStatus::Failed => {
                let why = r.reason.as_deref().unwrap_or("no reason given");
                self.action_failed(a, &format!("failed ({why})"), t);
            }
            ReportStatus::Nominal => self.action_succeeded(a),
            ReportStatus::Interrupted => {}
        }
        match integrate(self.plan.edit(), a, t) {
            Ok(true) => {}
            Ok(false) => {
                integrate_late_state(self, a, &r, t);
                self.abort_with(AbortReason::ReportTooLate { action: name });
                return;
            }
            Err(e) => {
                self.abort_with(AbortReason::ReportInconsistent {
                    action: name,
                    error: e.to_string(),
                });
                return;
            }
        }
        if r.status != ReportStatus::Nominal {
            integrate_state(self, a, &r, t);
        }
        for l in &r.resources {
            self.integrate_level(l, t);
        }
        self.dispatched.reported(a);
        self.drop_past(t);
        self.state.refresh(&self.plan, t);
    }

    /// The actions wholly in the past at `t` leave the plan, their usages folded into the ledger.
    pub(crate) fn drop_past(&mut self, t: Time) {
        self.ledger.drop_past(self.plan.edit(), t);
    }

    /// A resource level: compared with `[RscL_lb, RscL_ub]` and adjusted (resource_report).
    fn integrate_level(&mut self, l: &ResourceLevel, t: Time) {
        let Some(r) = self.resource(&l.resource) else {
            return;
        };
        self.ledger.reported(r, t, l.level);
        self.drop_past(t);
        let running = classify(&self.plan, t).running;
        let b = level_bounds(&self.plan, r, t, &running, self.ledger.past(r));
        let kind = self.plan.domain().resource(r).kind;
        let u = integrate_level(&b, l.level, kind, self.ledger.tolerance(r));
        // The constraint on the level is posted on the past part: every still-counted usage is subtracted
        // back out so that eq. (1) gives the new level.
        let past = self.ledger.past(r);
        let counted = (b.past_lb - past.0, b.past_ub - past.1);
        let problem = self.ledger.post_level(&self.plan, r, u.past, counted);
        if u.verdict == LevelVerdict::Consistent {
            // In bounds: the plan's resource conflicts stand as they were.
            self.plan.edit().set_problem(problem);
        } else {
            self.plan.edit().set_resource_problem(problem);
            self.trace(TraceEvent::Level {
                resource: l.resource.clone(),
                level: l.level,
                lb: b.lb,
                ub: b.ub,
                verdict: u.verdict,
            });
        }
        if u.check_executable {
            let flawed = self.plan.flawed_actions();
            if !plan_executable(&running, &flawed) {
                self.abort_with(AbortReason::LevelOutOfBounds {
                    resource: l.resource.clone(),
                    level: l.level,
                });
                return;
            }
        }
        if u.repair {
            self.repair.request();
        }
    }

    /// The object a goal location names when the intake recognised it (`new` false) and it is of the location
    /// type.
    fn known_location(
        &self,
        l: &mavtempo_vehicle::GoalLocation,
    ) -> Option<mavtempo_temporal::model::ObjectId> {
        if l.new {
            return None;
        }
        let o = self.plan.problem().object_id(&l.name)?;
        let ty = self.plan.problem().object(o)?.ty;
        (Some(ty) == self.vehicle.mapping.location_type).then_some(o)
    }

    /// The domain goal for a request, as the config's `[mapping.goals]` says: `attr(L) = true` or
    /// `attr() = L`; a new location object when the request names a place no object is at.
    pub fn goal_from_request(&mut self, g: &GoalRequest) -> Result<Goal, MappingError> {
        let what = g.kind.key();
        // A return home with no return-home mapping or no home object in the config is a "be at" the
        // problem's home position (the place there, or a new one named `home`).
        let home_as_waypoint = g.kind == mavtempo_vehicle::GoalKind::ReturnHome
            && (self.vehicle.mapping.home_object.is_none()
                || !self.vehicle.mapping.goals.contains_key(&g.kind));
        let kind = if home_as_waypoint {
            mavtempo_vehicle::GoalKind::BeAt
        } else {
            g.kind
        };
        let target =
            *self
                .vehicle
                .mapping
                .goals
                .get(&kind)
                .ok_or_else(|| MappingError::NoGoalMapping {
                    kind: what.to_string(),
                })?;
        let loc = match (&g.location, g.kind) {
            (_, mavtempo_vehicle::GoalKind::ReturnHome) => match self.vehicle.mapping.home_object {
                Some(o) if !home_as_waypoint => o,
                _ => super::state_update::location_object(
                    self,
                    "home",
                    mavtempo_vehicle::Enu::new(0.0, 0.0, 0.0),
                    None,
                )?,
            },
            // A place the intake already named (a known object of the location type) is that object.
            (Some(l), _) => match self.known_location(l) {
                Some(o) => o,
                None => super::state_update::location_object(self, &l.name, l.at, None)?,
            },
            (None, _) => {
                return Err(MappingError::NoGoalLocation {
                    kind: what.to_string(),
                })
            }
        };
        let (attr, args, value) = match target.shape {
            GoalShape::LocationIsTrue => (
                target.attr,
                vec![loc],
                Value::Obj(mavtempo_temporal::model::Domain::TRUE),
            ),
            GoalShape::ValueIsLocation => (target.attr, vec![], Value::Obj(loc)),
        };
        let ms = |s: f64| (s * 1000.0).round() as Time;
        let window_hi = if g.start_window_s.1.is_finite() {
            ms(g.start_window_s.1)
        } else {
            self.plan.horizon()
        };
        let dur_hi = if g.duration_s.1.is_finite() {
            ms(g.duration_s.1)
        } else {
            self.plan.horizon()
        };
        Ok(Goal {
            name: g.name.clone(),
            kind: GoalOrigin::External,
            priority: i64::from(g.priority),
            attr,
            args,
            value,
            start_window: TimeInterval::closed(
                ms(g.start_window_s.0),
                window_hi.min(self.plan.horizon()),
            ),
            duration: TimeInterval::closed(ms(g.duration_s.0), dur_hi),
            achieve: ms(g.d_achiev_s),
        })
    }
}
