//! The operator stays in command (issue 30). While the operator has the vehicle (a mode the companion did
//! not command, a disarm: the vehicle layer's [`AuthorityEvent::Paused`]) the executive launches and stops
//! nothing; mission time goes on, the running actions' reports (a motion interrupted where the vehicle
//! stopped) are integrated as they come, and a goal whose window closes meanwhile is rejected with that
//! reason. When control is handed back, the vehicle is where the operator left it: the plan's place of the
//! vehicle is compared with its reported position and, beyond the acceptance radius, a new place is made
//! there (as for a stopped move, [`super::state_update::location_object`]); then the plan is made again
//! from that state by complete replanning (§3.6: the plan's time bounds passed while paused). The same
//! comparison is made at the mission's start ([`Executive::start_from`]).

use super::executive::{Executive, Fate};
use super::outcome::{AbortReason, FateReason};
use super::trace::TraceEvent;
use mavtempo_temporal::model::{ObjectId, Time, Value};
use mavtempo_vehicle::authority::AuthorityEvent;
use mavtempo_vehicle::Enu;

impl Executive {
    /// Why a requested goal's place is outside the vehicle's limits, if it is (one check:
    /// [`mavtempo_vehicle::limits::Limits::check_local`]).
    pub(crate) fn beyond_limits(&self, g: &mavtempo_vehicle::GoalRequest) -> Option<String> {
        let at = g.location.as_ref()?.at;
        self.vehicle
            .limits()?
            .check_local(at)
            .err()
            .map(|v| v.to_string())
    }

    /// Whether the operator has the vehicle (the executive launches and stops nothing).
    pub fn is_paused(&self) -> bool {
        self.operator.is_held()
    }

    /// Why the operator has the vehicle, while they have it.
    pub fn paused_why(&self) -> Option<&str> {
        self.operator.why()
    }

    pub(crate) fn authority_event(&mut self, e: AuthorityEvent, now: Time) {
        match e {
            AuthorityEvent::Paused { why } => {
                self.trace(TraceEvent::Paused { why: why.clone() });
                self.operator.take_over(why);
                // A repair under way was for a plan the operator's control overtakes.
                self.repair.hold();
            }
            AuthorityEvent::Resumed {
                how,
                position,
                radius_m,
            } => {
                self.operator.hand_back();
                self.trace(TraceEvent::Resumed { how: how.clone() });
                if let Some(p) = position {
                    self.start_from(p, radius_m, now);
                }
                self.abort_with(AbortReason::ControlReturned { how });
            }
        }
    }

    /// A paused cycle: the goals whose latest start passed are rejected (the operator had the vehicle).
    pub(crate) fn while_paused(&mut self, now: Time) {
        let why = self.operator.why().unwrap_or_default().to_string();
        let closed: Vec<_> = self
            .plan
            .goals()
            .iter()
            .filter(|pg| pg.active && !self.plan.is_executed(pg.st))
            .map(|pg| (pg.goal, self.plan.latest(pg.st)))
            .filter(|&(_, ub)| ub < now)
            .collect();
        for (g, ub) in closed {
            if !self.goals.is_pending(g) {
                continue;
            }
            let reason = FateReason::ClosedWhilePaused {
                closed_ms: ub,
                why: why.clone(),
            };
            let goal = self.plan.problem().goals[g.index()].name.clone();
            self.set_fate(g, Fate::Rejected, Some(reason.clone()));
            self.trace(TraceEvent::GoalRejected { goal, reason });
        }
    }

    /// The vehicle is at `at` (metres from home): when that is more than `radius_m` from the plan's place
    /// of the vehicle, the plan starts from a new place there (a warning names the distance) and is made
    /// again (an abort: complete replanning). Returns the distance when it did.
    pub fn start_from(&mut self, at: Enu, radius_m: f64, now: Time) -> Option<f64> {
        let attr = self.vehicle.mapping.position?;
        self.state.refresh(&self.plan, now);
        let key = (attr, Vec::new());
        let planned = self.state.get(&key).or_else(|| {
            self.plan
                .problem()
                .initial
                .iter()
                .find(|f| f.attr == attr && f.args.is_empty())
                .map(|f| f.value)
        });
        let Some(Value::Obj(place)) = planned else {
            return None;
        };
        let home = self.plan.problem().home;
        let (e, n, _) = self.plan.problem().object(place)?.local(home.as_ref())?;
        let distance_m = (e - at.east).hypot(n - at.north);
        if distance_m <= radius_m {
            return None;
        }
        let name = format!("L{}", self.plan.problem().objects.len());
        let new: ObjectId = match super::state_update::location_object(self, &name, at, Some(place))
        {
            Ok(o) => o,
            Err(e) => {
                tracing::warn!("the vehicle's position names no place: {e}");
                return None;
            }
        };
        let place = self.plan.problem().object_name(new).to_string();
        tracing::warn!(
            distance_m,
            %place,
            "the vehicle is not where the plan has it: the plan starts from its position"
        );
        self.state.set(key, now, Value::Obj(new));
        self.trace(TraceEvent::Elsewhere { distance_m, place });
        self.abort_with(AbortReason::VehicleElsewhere { distance_m });
        Some(distance_m)
    }
}
