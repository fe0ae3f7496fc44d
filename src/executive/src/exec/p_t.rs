//! Definition 1: P_t = (RA_t, FA_t, S_t, G_t, C_t, L_t, F_t), the partial plan partially executed up to t.
//!
//! C_t, L_t and F_t are the [`PartialPlan`]'s networks, links and flaws. This file classifies actions
//! (running `RA_t`: `st_ub < t` and `et_ub > t`; future `FA_t`: `st_ub ≥ t`; past: the rest), takes the past
//! ones out of the plan while keeping their effects in S_t, and computes S_t's logical part `LgcS_t` (the
//! last executed event of each attribute instance, footnote 4) and the goals G_t (`et^g_ub ≥ t`, footnote 5).

use std::collections::{BTreeMap, BTreeSet};

use mavtempo_temporal::model::{AttrId, GoalId, ObjectId, Time, Value};
use mavtempo_temporal::plan::{ActionId, EventRec, Owner, PartialPlan};

/// Where an action stands at time t (Definition 1).
#[derive(Copy, Clone, Eq, PartialEq, Debug)]
pub enum Phase {
    Past,
    Running,
    Future,
}

/// Definition 1's membership tests on the action's timepoint bounds.
pub fn phase(plan: &PartialPlan, a: ActionId, t: Time) -> Phase {
    let act = plan.action(a);
    let (st_ub, et_ub) = (plan.latest(act.start), plan.latest(act.end));
    if st_ub >= t {
        Phase::Future
    } else if et_ub > t {
        Phase::Running
    } else {
        Phase::Past
    }
}

/// RA_t and FA_t (actions still in the plan).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Actions {
    pub running: Vec<ActionId>,
    pub future: Vec<ActionId>,
    pub past: Vec<ActionId>,
}

pub fn classify(plan: &PartialPlan, t: Time) -> Actions {
    let mut out = Actions::default();
    for a in plan.live_actions() {
        match phase(plan, a, t) {
            Phase::Past => out.past.push(a),
            Phase::Running => out.running.push(a),
            Phase::Future => out.future.push(a),
        }
    }
    out
}

/// "Past actions do not belong to the plan anymore": removes the actions whose both timepoints are executed
/// at or before t. Their events stay in the plan (the state S_t is read from executed events); their
/// resource usages are folded into `past_levels` with it (`Executive::drop_past`, [`super::resource_bounds`]).
/// Returns the removed actions.
pub fn remove_past(plan: &mut PartialPlan, t: Time) -> Vec<ActionId> {
    let past: Vec<ActionId> = plan
        .live_actions()
        .filter(|&a| {
            let act = plan.action(a);
            plan.is_executed(act.start) && plan.is_executed(act.end) && plan.latest(act.end) <= t
        })
        .collect();
    for &a in &past {
        plan.remove_action(a);
    }
    past
}

/// A ground attribute instance `attr(args)`.
pub type AttrInstance = (AttrId, Vec<ObjectId>);

/// LgcS_t: the value set by the last executed event of each ground attribute instance (footnote 4), or
/// overridden by a value reported by the controlled system ([`State::set`]), which wins over an event
/// executed at the same time (the report says what really happened).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct State {
    pub values: BTreeMap<AttrInstance, (Time, Value)>,
    /// The instances whose value in `values` was reported ([`State::set`]), not set by an event.
    reported: BTreeSet<AttrInstance>,
}

impl State {
    /// Recomputes LgcS_t from the plan's executed events (events of the initial state at the origin and of
    /// executed timepoints), keeping reported values that are more recent.
    pub fn refresh(&mut self, plan: &PartialPlan, t: Time) {
        // Executed events in time order; at one instant an action's end events come after its start
        // events (a move reported done the instant it started — it was within its waypoint radius — leaves
        // the robot at its target, not `+oo` in transit).
        let mut executed: Vec<(Time, bool, &EventRec)> = plan
            .events()
            .iter()
            .filter_map(|e| {
                let at = plan.executed_at(e.at)?;
                let at_end = match e.owner {
                    Owner::Action(a) => plan.action(a).end == e.at,
                    _ => false,
                };
                (at <= t).then_some((at, at_end, e))
            })
            .collect();
        executed.sort_by_key(|&(at, at_end, _)| (at, at_end));
        for (at, at_end, e) in executed {
            let args: Option<Vec<ObjectId>> = e
                .args
                .iter()
                .map(|&a| match plan.bindings().value(a) {
                    Some(Value::Obj(o)) => Some(o),
                    _ => None,
                })
                .collect();
            let (Some(args), Some(value)) = (args, plan.bindings().value(e.to)) else {
                continue;
            };
            let key = (e.attr, args);
            let keep = match self.values.get(&key) {
                // A reported value wins over an event executed at the same time; an action's end event
                // follows another event of the same instant.
                Some(&(old, _)) => {
                    old > at || (old == at && (!at_end || self.reported.contains(&key)))
                }
                None => false,
            };
            if !keep {
                self.reported.remove(&key);
                self.values.insert(key, (at, value));
            }
        }
    }

    /// A value reported by the controlled system at t (a non-nominal report, §3.3 "State variables").
    pub fn set(&mut self, key: AttrInstance, t: Time, value: Value) {
        self.reported.insert(key.clone());
        self.values.insert(key, (t, value));
    }

    pub fn get(&self, key: &AttrInstance) -> Option<Value> {
        self.values.get(key).map(|&(_, v)| v)
    }
}

/// G_t: goals still active whose `et^g_ub ≥ t` (footnote 5).
pub fn goals(plan: &PartialPlan, t: Time) -> Vec<GoalId> {
    plan.goals()
        .iter()
        .filter(|g| g.active && plan.latest(g.et) >= t)
        .map(|g| g.goal)
        .collect()
}
