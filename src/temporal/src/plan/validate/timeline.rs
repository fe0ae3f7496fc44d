//! Logical attributes over time: one timeline per attribute instance from the initial value, the
//! predicted exogenous changes and the actions' events in schedule order; then every event's `from`,
//! every hold, every causal link and every achieved goal is checked against it.

use std::collections::BTreeMap;

use crate::model::{AttrId, Term, Time, Value};
use crate::plan::solution::{CausalLink, Consumer, Establisher, PlanAction, PlanTp};

use super::violation::Lapse;
use super::{Ctx, LinkFault, Violation};

type Instance = (AttrId, Vec<Value>);

/// A change of value at an instant; `from` is required (`None` for exogenous changes).
struct Change {
    time: Time,
    from: Option<Value>,
    to: Value,
    who: String,
}

/// The value of one instance: `(since, value)` steps sorted by time, the first at −∞ (the initial value).
struct Timeline(Vec<(Time, Value)>);

impl Timeline {
    /// The value from `t` on (after the changes at `t`).
    fn at(&self, t: Time) -> Value {
        self.0
            .iter()
            .take_while(|(since, _)| *since <= t)
            .last()
            .map_or(Value::Unknown, |&(_, v)| v)
    }

    /// The first time in `[a, b[` (`[a, b]` when `closed`, `{a}` when `b <= a`) where the value is not
    /// `v`, with the value then.
    fn broken(&self, v: Value, a: Time, b: Time, closed: bool) -> Option<(Time, Value)> {
        let now = self.at(a);
        if now != v {
            return Some((a, now));
        }
        self.0
            .iter()
            .find(|&&(t, x)| t > a && (t < b || (closed && t == b)) && x != v)
            .map(|&(t, x)| (t, x))
    }
}

pub(super) fn check(cx: &Ctx, out: &mut Vec<Violation>) {
    let mut changes: BTreeMap<Instance, Vec<Change>> = BTreeMap::new();
    for f in &cx.p.exogenous {
        let key = (
            f.fact.attr,
            f.fact.args.iter().map(|&o| Value::Obj(o)).collect(),
        );
        changes.entry(key).or_default().push(Change {
            time: f.at,
            from: None,
            to: f.fact.value,
            who: format!("the exogenous change at {} ms", f.at),
        });
    }
    for a in &cx.s.actions {
        for e in &cx.d.task(a.task).events {
            let key = (e.attr, e.args.iter().map(|&t| cx.term(a, t)).collect());
            changes.entry(key).or_default().push(Change {
                time: cx.at(a, e.at),
                from: Some(cx.term(a, e.from)),
                to: cx.term(a, e.to),
                who: cx.label(a),
            });
        }
    }
    let mut timelines: BTreeMap<Instance, Timeline> = BTreeMap::new();
    for (key, mut list) in changes {
        list.sort_by_key(|c| c.time);
        let instance = cx.instance_name(key.0, &key.1);
        let mut cur = cx.p.initial_value(key.0, &args_of(&key.1));
        let mut steps = vec![(Time::MIN, cur)];
        for (i, c) in list.iter().enumerate() {
            if let Some(prev) = i.checked_sub(1).and_then(|j| list.get(j)) {
                if prev.time == c.time {
                    out.push(Violation::SimultaneousEvents {
                        instance: instance.clone(),
                        time: c.time,
                        first: prev.who.clone(),
                        second: c.who.clone(),
                    });
                }
            }
            if let Some(from) = c.from {
                if from != cur {
                    out.push(Violation::EventFrom {
                        action: c.who.clone(),
                        instance: instance.clone(),
                        time: c.time,
                        expected: cx.value_name(from),
                        actual: cx.value_name(cur),
                    });
                }
            }
            cur = c.to;
            steps.push((c.time, cur));
        }
        timelines.insert(key, Timeline(steps));
    }
    // An instance nobody changes keeps its initial value.
    let line = |key: &Instance| -> Timeline {
        timelines.get(key).map_or_else(
            || {
                Timeline(vec![(
                    Time::MIN,
                    cx.p.initial_value(key.0, &args_of(&key.1)),
                )])
            },
            |t| Timeline(t.0.clone()),
        )
    };
    for a in &cx.s.actions {
        for h in &cx.d.task(a.task).holds {
            let key = (
                h.attr,
                h.args.iter().map(|&t| cx.term(a, t)).collect::<Vec<_>>(),
            );
            let v = cx.term(a, h.value);
            let (from, to) = (cx.at(a, h.from), cx.at(a, h.to));
            if let Some(lapse) = lapse(cx, &line(&key), &key, v, (from, to), false) {
                out.push(Violation::HoldBroken {
                    action: cx.label(a),
                    lapse,
                });
            }
        }
    }
    for (i, l) in cx.s.causal_links.iter().enumerate() {
        let label = link_label(cx, i, l);
        if let Err(reason) = link_matches(cx, l) {
            out.push(Violation::LinkMismatch {
                link: label.clone(),
                reason,
            });
        }
        let key = (
            l.attr,
            l.args.iter().map(|&t| cx.value(t)).collect::<Vec<_>>(),
        );
        let v = cx.value(l.value);
        let (from, to) = (cx.time(l.from), cx.time(l.to));
        let closed = matches!(l.consumer, Consumer::Goal { .. });
        if let Some(lapse) = lapse(cx, &line(&key), &key, v, (from, to), closed) {
            out.push(Violation::LinkBroken { link: label, lapse });
        }
    }
    for g in cx.s.goals.iter().filter(|g| g.achieved) {
        let goal = &cx.p.goals[g.goal.index()];
        let (Some(st), Some(et)) = (g.start, g.end) else {
            continue; // reported by the temporal check
        };
        let supported =
            cx.s.causal_links
                .iter()
                .any(|l| l.consumer == Consumer::Goal { goal: g.goal });
        if !supported {
            out.push(Violation::GoalUnsupported {
                goal: goal.name.clone(),
                reason: "no causal link supports it".into(),
            });
        }
        let key = (
            goal.attr,
            goal.args.iter().map(|&o| Value::Obj(o)).collect::<Vec<_>>(),
        );
        let (from, to) = (cx.time(st), cx.time(et));
        if let Some(lapse) = lapse(cx, &line(&key), &key, goal.value, (from, to), true) {
            out.push(Violation::GoalBroken {
                goal: goal.name.clone(),
                lapse,
            });
        }
    }
}

/// The first failure of `key = v` over `[from, to[` (closed: `[from, to]`), for a violation.
fn lapse(
    cx: &Ctx,
    line: &Timeline,
    key: &Instance,
    v: Value,
    (from, to): (Time, Time),
    closed: bool,
) -> Option<Lapse> {
    let (time, actual) = line.broken(v, from, to, closed)?;
    Some(Lapse {
        instance: cx.instance_name(key.0, &key.1),
        value: cx.value_name(v),
        from,
        to,
        time,
        actual: cx.value_name(actual),
    })
}

/// Ground arguments (attribute arguments are never `+oo` in a well-formed domain).
fn args_of(vals: &[Value]) -> Vec<crate::model::ObjectId> {
    vals.iter()
        .filter_map(|v| match v {
            Value::Obj(o) => Some(*o),
            Value::Unknown => None,
        })
        .collect()
}

/// `#3 (a1 event #2 → a4 hold #0)`.
fn link_label(cx: &Ctx, i: usize, l: &CausalLink) -> String {
    let act = |id| cx.s.action(id).map_or("?", |a| a.name.as_str());
    let est = match l.establisher {
        Establisher::Initial => "initial state".to_string(),
        Establisher::Timed { index } => format!("exogenous change #{index}"),
        Establisher::Event { action, event } => format!("{} event #{event}", act(action)),
    };
    let con = match l.consumer {
        Consumer::Hold { action, hold } => format!("{} hold #{hold}", act(action)),
        Consumer::EventFrom { action, event } => format!("{} event #{event} (from)", act(action)),
        Consumer::Goal { goal } => format!("goal {}", cx.p.goals[goal.index()].name),
    };
    format!("#{i} ({est} → {con})")
}

/// The link's proposition and interval are those of its establisher and consumer (instantiated).
fn link_matches(cx: &Ctx, l: &CausalLink) -> Result<(), LinkFault> {
    let args: Vec<Value> = l.args.iter().map(|&t| cx.value(t)).collect();
    let value = cx.value(l.value);
    let same = |attr: AttrId, a: &[Value], v: Value, role: &'static str| {
        if attr != l.attr || a != args.as_slice() || v != value {
            Err(LinkFault::Proposition {
                instance: cx.instance_name(l.attr, &args),
                value: cx.value_name(value),
                role,
                role_instance: cx.instance_name(attr, a),
                role_value: cx.value_name(v),
            })
        } else {
            Ok(())
        }
    };
    // `same` for an event or a hold of the action `a`, instantiated.
    let same_in = |a: &PlanAction, attr: AttrId, terms: &[Term], v: Term, role: &'static str| {
        let args: Vec<Value> = terms.iter().map(|&t| cx.term(a, t)).collect();
        same(attr, &args, cx.term(a, v), role)
    };
    let at = |tp: PlanTp, want: Option<PlanTp>, role: &'static str| match want {
        Some(w) if w == tp => Ok(()),
        _ => Err(LinkFault::NotAtBound {
            tp: cx.s.tp_name(tp).to_string(),
            role,
        }),
    };
    match l.establisher {
        Establisher::Initial => {
            let v = cx.p.initial_value(l.attr, &args_of(&args));
            same(l.attr, &args, v, "initial state")?;
            at(l.from, Some(PlanTp::ORIGIN), "establisher (the origin)")?;
        }
        Establisher::Timed { index } => {
            let f = &cx.p.exogenous[index];
            let fa: Vec<Value> = f.fact.args.iter().map(|&o| Value::Obj(o)).collect();
            same(f.fact.attr, &fa, f.fact.value, "exogenous change")?;
            if cx.time(l.from) != f.at {
                return Err(LinkFault::NotAtExogenousChange {
                    start: cx.time(l.from),
                    change: f.at,
                });
            }
        }
        Establisher::Event { action, event } => {
            let a = cx.s.action(action).ok_or(LinkFault::UnknownEstablisher)?;
            let e = &cx.d.task(a.task).events[event];
            same_in(a, e.attr, &e.args, e.to, "establishing event")?;
            at(l.from, a.tp(e.at), "establishing event")?;
        }
    }
    match l.consumer {
        Consumer::Hold { action, hold } => {
            let a = cx.s.action(action).ok_or(LinkFault::UnknownConsumer)?;
            let h = &cx.d.task(a.task).holds[hold];
            same_in(a, h.attr, &h.args, h.value, "supported hold")?;
            supported(cx, l, a, (h.from, h.to), "hold")?;
        }
        Consumer::EventFrom { action, event } => {
            let a = cx.s.action(action).ok_or(LinkFault::UnknownConsumer)?;
            let e = &cx.d.task(a.task).events[event];
            same_in(a, e.attr, &e.args, e.from, "supported event")?;
            supported(cx, l, a, (e.at, e.at), "event")?;
        }
        Consumer::Goal { goal } => {
            let g = &cx.p.goals[goal.index()];
            let ga: Vec<Value> = g.args.iter().map(|&o| Value::Obj(o)).collect();
            same(g.attr, &ga, g.value, "goal")?;
            let end =
                cx.s.goals
                    .iter()
                    .find(|pg| pg.goal == goal)
                    .and_then(|pg| pg.end);
            at(l.to, end, "goal's end")?;
        }
    }
    Ok(())
}

/// The link ends at the supported hold's / event's end and its establisher precedes its start.
fn supported(
    cx: &Ctx,
    l: &CausalLink,
    a: &crate::plan::solution::PlanAction,
    (start, end): (crate::model::TpId, crate::model::TpId),
    what: &'static str,
) -> Result<(), LinkFault> {
    if a.tp(end) != Some(l.to) {
        return Err(LinkFault::NotAtSupportedEnd {
            tp: cx.s.tp_name(l.to).to_string(),
            what,
        });
    }
    precedes(cx, l, cx.at(a, start), what)
}

/// Footnote 3 of seed 1: the establisher precedes what it supports (it may not start after it).
fn precedes(cx: &Ctx, l: &CausalLink, start: Time, what: &'static str) -> Result<(), LinkFault> {
    let from = cx.time(l.from);
    if from > start {
        return Err(LinkFault::EstablisherAfter { from, what, start });
    }
    Ok(())
}
