//! State values from a non-nominal report (seed 1 §3.3 "State variables"), then causal-link removal.
//!
//! A reported value is not inserted if it threatens a proposition of a running action a_r (the plan would not
//! be executable); then a_r's interruption is requested if it is preemptive. Otherwise the value enters
//! LgcS_t and the causal links that contradict it are broken, as are the links established by the failed
//! action's end effects (they did not happen); the links of the abstraction hierarchy's Att^i follow
//! ([`super::abstraction`]). A reported position that is no known location becomes a new location object
//! (seed 1 §3.4: `move(L_i, L_2)` after an interrupted `move(L_1, L_2)`).

use std::sync::Arc;

use super::abstraction::{flawed_attributes, links_to_break};
use super::executive::Executive;
use super::p_t::classify;
use super::trace::TraceEvent;
use crate::mapping::MappingError;
use mavtempo_temporal::model::{AttrId, Object, ObjectId, Position, Preemption, Time, Value};
use mavtempo_temporal::plan::{ActionId, CondKind, EventId, LinkId, STerm};
use mavtempo_vehicle::{ActionReport, Enu, StateValue};

/// Distance under which a reported position names a known location, m.
pub const SAME_PLACE_M: f64 = 2.0;

/// The location object at `at` (within [`SAME_PLACE_M`]), or a new one named `name` of the mapping's
/// location type; without a location type there is no object to name a new place. A new place met on the
/// way from location `from` (an interrupted move) keeps `from`'s static relations (attributes no task
/// changes, e.g. a route graph), so that the vehicle can go on from there.
pub fn location_object(
    ex: &mut Executive,
    name: &str,
    at: Enu,
    from: Option<ObjectId>,
) -> Result<ObjectId, MappingError> {
    let home = ex.plan.problem().home;
    let ty = ex.vehicle.mapping.location_type;
    let mut best: Option<(f64, ObjectId)> = None;
    for (i, o) in ex.plan.problem().objects.iter().enumerate() {
        if ty.is_some_and(|t| t != o.ty) {
            continue;
        }
        if let Some((e, n, _)) = o.local(home.as_ref()) {
            let d = (e - at.east).hypot(n - at.north);
            if d <= SAME_PLACE_M && best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, ObjectId::from_index(i)));
            }
        }
    }
    if let Some((_, o)) = best {
        return Ok(o);
    }
    let Some(ty) = ty else {
        return Err(MappingError::NoLocationType {
            east: at.east,
            north: at.north,
        });
    };
    let mut problem = (**ex.plan.problem()).clone();
    let mut unique = name.to_string();
    let mut k = 1;
    while problem.object_id(&unique).is_some() {
        k += 1;
        unique = format!("{name}_{k}");
    }
    let d = ex.plan.domain().clone();
    let statics: Vec<AttrId> = (0..d.attrs.len())
        .map(AttrId::from_index)
        .filter(|&a| d.tasks.iter().all(|t| t.events.iter().all(|e| e.attr != a)))
        .collect();
    let id = problem.add_object_like(
        &d,
        Object {
            name: unique,
            ty,
            position: Some(Position::Local {
                east: at.east,
                north: at.north,
                up: at.up,
            }),
        },
        from.map(|f| (f, statics.as_slice())),
    );
    if let Some(f) = from {
        way_back(&mut problem, &statics, id, f);
    }
    ex.plan.edit().set_problem(Arc::new(problem));
    Ok(id)
}

/// A place `new` the vehicle reached from `from` is linked back to it: a static relation `R(new, from)`
/// holds when `R(from, x)` holds for some place (a route graph: the vehicle can go back the way it came;
/// copying `from`'s relations gives `R(new, from)` the value of `R(from, from)`, none).
fn way_back(
    problem: &mut mavtempo_temporal::model::Problem,
    statics: &[AttrId],
    new: ObjectId,
    from: ObjectId,
) {
    let t = Value::Obj(mavtempo_temporal::model::Domain::TRUE);
    for &r in statics {
        let linked = problem
            .initial
            .iter()
            .any(|f| f.attr == r && f.args.len() == 2 && f.args[0] == from && f.value == t);
        if !linked {
            continue;
        }
        match problem
            .initial
            .iter_mut()
            .find(|f| f.attr == r && f.args == [new, from])
        {
            Some(f) => f.value = t,
            None => problem.initial.push(mavtempo_temporal::model::Fact {
                attr: r,
                args: vec![new, from],
                value: t,
            }),
        }
    }
}

/// The place action `a` started from: the value its start event on the position attribute `attr` changed
/// (a move), else the place it held (a survey, a picture: `hold(AUV_AT(): ?l)`), else the place S_t gives.
fn started_at(ex: &Executive, a: ActionId, attr: AttrId) -> Option<ObjectId> {
    let act = ex.plan.action(a);
    let obj = |v: Value| match v {
        Value::Obj(o) => Some(o),
        _ => None,
    };
    let moved = act
        .events
        .iter()
        .find(|&&e| ex.plan.event(e).attr == attr && ex.plan.event(e).at == act.start)
        .and_then(|&e| before_value(ex, e))
        .and_then(|(_, _, v)| obj(v));
    let held = || {
        act.conds.iter().find_map(|&c| {
            let k = ex.plan.cond(c);
            (k.attr == attr && matches!(k.kind, CondKind::Hold { .. }))
                .then(|| ex.plan.bindings().value(k.value))
                .flatten()
                .and_then(obj)
        })
    };
    moved
        .or_else(held)
        .or_else(|| ex.state.get(&(attr, vec![])).and_then(obj))
}

/// The attribute instance and value a report's state variable stands for, or why it has none.
fn reported_value(
    ex: &mut Executive,
    var: &str,
    v: &StateValue,
    a: ActionId,
) -> Result<(AttrId, Vec<ObjectId>, Value), MappingError> {
    match v {
        StateValue::Position(p) => {
            let attr = ex
                .vehicle
                .mapping
                .position
                .ok_or(MappingError::NoPositionAttribute)?;
            let name = format!("L{}", ex.plan.problem().objects.len());
            let from = started_at(ex, a, attr);
            let o = location_object(ex, &name, *p, from)?;
            Ok((attr, vec![], Value::Obj(o)))
        }
        StateValue::Symbol(s) => {
            let d = &ex.plan.domain();
            let attr = d.attr_id(var).ok_or_else(|| MappingError::NoAttribute {
                name: var.to_string(),
            })?;
            let o = ex
                .plan
                .problem()
                .object_id(s)
                .or_else(|| d.object_id(s))
                .ok_or_else(|| MappingError::NoObject { name: s.clone() })?;
            Ok((attr, vec![], Value::Obj(o)))
        }
        StateValue::Number(_) => Err(MappingError::Number),
    }
}

/// Running actions (other than `except`) holding a value on `attr(args)` that `value` contradicts.
fn threatened(
    ex: &Executive,
    attr: AttrId,
    args: &[ObjectId],
    value: Value,
    t: Time,
    except: ActionId,
) -> Vec<ActionId> {
    let plan = &ex.plan;
    classify(plan, t)
        .running
        .into_iter()
        .filter(|&r| r != except)
        .filter(|&r| {
            plan.action(r).conds.iter().any(|&c| {
                let k = plan.cond(c);
                matches!(k.kind, CondKind::Hold { .. })
                    && k.attr == attr
                    && k.args
                        .iter()
                        .zip(args)
                        .all(|(&x, &o)| plan.bindings().possibly_equal(x, STerm::Obj(o)))
                    && !plan.bindings().possibly_equal(k.value, value.into())
            })
        })
        .collect()
}

/// `attr(args) = from` of an event whose arguments and previous value are known.
fn before_value(ex: &Executive, e: EventId) -> Option<(AttrId, Vec<ObjectId>, Value)> {
    let ev = ex.plan.event(e);
    let from = ex.plan.cond(ev.cond?).value;
    let value = ex.plan.bindings().value(from)?;
    let args = ev
        .args
        .iter()
        .map(|&x| match ex.plan.bindings().value(x) {
            Some(Value::Obj(o)) => Some(o),
            _ => None,
        })
        .collect::<Option<Vec<_>>>()?;
    Some((ev.attr, args, value))
}

/// An end event of action `a` that only undoes `a`'s own start event on the same instance (the move's
/// `ROBOT_STATUS: MOVING → STILL` after its `STILL → MOVING`): the value it restores. That value was the
/// action's while it ran; once the action has ended — failed too — it holds again (a rover whose move
/// failed stands still; it is not left MOVING for every later plan).
fn restored_value(
    ex: &Executive,
    a: ActionId,
    e: EventId,
) -> Option<(AttrId, Vec<ObjectId>, Value)> {
    let plan = &ex.plan;
    let ev = plan.event(e);
    let b = &plan.bindings();
    let from = plan.cond(ev.cond?).value;
    let st = plan.action(a).start;
    let undone = plan.action(a).events.iter().any(|&s| {
        let se = plan.event(s);
        se.at == st
            && se.attr == ev.attr
            && se.args.len() == ev.args.len()
            && se
                .args
                .iter()
                .zip(&ev.args)
                .all(|(&x, &y)| b.necessarily_equal(x, y))
            && b.necessarily_equal(se.to, from)
            && se
                .cond
                .is_some_and(|c| b.necessarily_equal(plan.cond(c).value, ev.to))
    });
    if !undone {
        return None;
    }
    let value = b.value(ev.to)?;
    let (attr, args, _) = before_value(ex, e)?;
    Some((attr, args, value))
}

/// S_t after a report that came too late to be integrated into the plan (its end timepoint past its upper
/// bound: execution is aborted, the end is never executed): the state the report says the action left —
/// its reported values (a stopped move's position, a new place if need be), its end effects that happened
/// (all of them when nominal, the unreported ones of an interrupted preemptive action), and the values
/// before the others. Without it S_ti would keep the action's start values (`+oo`: in transit), from
/// which no plan starts (§3.6: S_ti = S_ts).
pub fn integrate_late_state(ex: &mut Executive, a: ActionId, r: &ActionReport, t: Time) {
    let reported: Vec<(AttrId, Vec<ObjectId>, Value)> = r
        .state
        .iter()
        .filter(|_| r.status != mavtempo_vehicle::ReportStatus::Nominal)
        .filter_map(|(var, v)| reported_value(ex, var, v, a).ok())
        .collect();
    let et = ex.plan.action(a).end;
    let preemptive =
        ex.plan.domain().task(ex.plan.action(a).task).preemption != Preemption::NonPreemptive;
    let happened = match r.status {
        mavtempo_vehicle::ReportStatus::Nominal => true,
        mavtempo_vehicle::ReportStatus::Interrupted => preemptive,
        mavtempo_vehicle::ReportStatus::Failed => false,
    };
    let mut values = Vec::new();
    for &e in &ex.plan.action(a).events.clone() {
        if ex.plan.event(e).at != et {
            continue;
        }
        let Some((attr, args, before)) = before_value(ex, e) else {
            continue;
        };
        if reported
            .iter()
            .any(|(ra, rargs, _)| *ra == attr && *rargs == args)
        {
            continue;
        }
        let after = ex.plan.bindings().value(ex.plan.event(e).to);
        let value = match (happened, after) {
            (true, Some(v)) => v,
            _ => restored_value(ex, a, e).map_or(before, |(_, _, v)| v),
        };
        values.push((attr, args, value));
    }
    for (attr, args, value) in reported.into_iter().chain(values) {
        ex.state.set((attr, args), t, value);
    }
}

pub fn integrate_state(ex: &mut Executive, a: ActionId, r: &ActionReport, t: Time) {
    let mut broken: Vec<LinkId> = Vec::new();
    // Values that enter the plan as observed facts just after t, when the action ended, so that the effect
    // they replace cannot support anything later (§3.3: the state values are inserted).
    let mut observed: Vec<(AttrId, Vec<ObjectId>, Value)> = Vec::new();
    let reported: Vec<(AttrId, Vec<ObjectId>, Value)> = r
        .state
        .iter()
        .filter_map(|(var, v)| reported_value(ex, var, v, a).ok())
        .collect();
    // The action's end effects: a reported value replaces the expected one (links established by an
    // effect the report contradicts are broken); a failed action's unreported end effects did not happen;
    // an interrupted preemptive action did end (what it achieved is what preemption means), its unreported
    // end effects hold; a non-preemptive action cut off (a picture that hung until the abort) did not
    // complete, its unreported end effects did not happen.
    let et = ex.plan.action(a).end;
    let preemptive =
        ex.plan.domain().task(ex.plan.action(a).task).preemption != Preemption::NonPreemptive;
    for &e in &ex.plan.action(a).events.clone() {
        let ev = ex.plan.event(e);
        if ev.at != et {
            continue;
        }
        let attr = ev.attr;
        let same_instance = |args: &[ObjectId]| {
            ev.args
                .iter()
                .zip(args)
                .all(|(&x, &o)| ex.plan.bindings().necessarily_equal(x, STerm::Obj(o)))
        };
        let report = reported
            .iter()
            .find(|(at, args, _)| *at == attr && same_instance(args));
        let happened = match report {
            Some((_, _, v)) => ex.plan.bindings().necessarily_equal(ev.to, (*v).into()),
            None => preemptive && r.status == mavtempo_vehicle::ReportStatus::Interrupted,
        };
        if happened {
            continue;
        }
        // The value did not change: the value before the event holds on (when it is known) — unless the
        // event only undoes the action's own start event, which the action's end ends all the same.
        if report.is_none() {
            if let Some((attr, args, value)) =
                restored_value(ex, a, e).or_else(|| before_value(ex, e))
            {
                ex.state.set((attr, args.clone()), t, value);
                observed.push((attr, args, value));
            }
        }
        for &l in ex.plan.links_on(attr) {
            if ex.plan.link(l).event == e && ex.plan.link(l).active {
                broken.push(l);
            }
        }
    }
    for (var, v) in &r.state {
        let (attr, args, value) = match reported_value(ex, var, v, a) {
            Ok(x) => x,
            Err(reason) => {
                tracing::warn!(%var, "reported state value ignored: {reason}");
                continue;
            }
        };
        let threats = threatened(ex, attr, &args, value, t, a);
        if !threats.is_empty() {
            for ra in threats {
                let pre = ex.plan.domain().task(ex.plan.action(ra).task).preemption;
                let name = ex.action_text(ra);
                if pre != Preemption::NonPreemptive && !ex.dispatched.is_stopping(ra) {
                    ex.trace(TraceEvent::Interrupt {
                        action: name,
                        reason: format!("reported {var} threatens it"),
                    });
                    ex.dispatched.request_stop(ra);
                }
            }
            continue;
        }
        ex.state.set((attr, args.clone()), t, value);
        observed.push((attr, args.clone(), value));
        // Links that protect another value of this attribute instance across t.
        for &l in ex.plan.links_on(attr) {
            let link = ex.plan.link(l);
            if !link.active || !ex.plan.cond_live(link.cond) {
                continue;
            }
            let c = ex.plan.cond(link.cond);
            let same = c
                .args
                .iter()
                .zip(&args)
                .all(|(&x, &o)| ex.plan.bindings().necessarily_equal(x, STerm::Obj(o)));
            let est_done = ex.plan.latest(ex.plan.event(link.event).at) <= t;
            let open_after = ex.plan.latest(c.to) >= t;
            if same
                && est_done
                && open_after
                && !ex.plan.bindings().possibly_equal(c.value, value.into())
            {
                broken.push(l);
            }
        }
    }
    let running = classify(&ex.plan, t).running;
    broken.retain(
        |&l| match ex.plan.cond(ex.plan.link(l).cond).owner.action() {
            Some(owner) => !running.contains(&owner),
            None => true,
        },
    );
    broken.sort();
    broken.dedup();
    for e in ex
        .plan
        .edit()
        .integrate_observations(&broken, observed, t + 1)
    {
        tracing::warn!("observed value not inserted: {e}");
    }
    // Causal-link removal via the abstraction hierarchy.
    let att_f = flawed_attributes(ex.plan.edit());
    let att_i = ex.hierarchy.closure(&att_f);
    let more = links_to_break(&ex.plan, &att_i, &running);
    let n = broken.len() + more.len();
    ex.plan.edit().break_links(&more);
    if n > 0 {
        ex.trace(TraceEvent::LinksBroken { count: n });
    }
    ex.repair.request();
}
