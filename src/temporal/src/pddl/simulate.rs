//! Replays an IPC plan on the PDDL domain and problem themselves (not on the translation): PDDL 2.1
//! durative-action semantics with ε-separation. Each action is a start happening and an end happening;
//! `at start` / `at end` conditions are checked in the state before the happening, `over all` conditions in
//! every state strictly inside the action, goals in the final state; two happenings closer than ε must not
//! interfere (one's effects touching the other's conditions or effects, numeric fluents included).
//! Numeric fluents are simulated: comparisons in the state before the happening, durations in the state at
//! the start, `increase` / `decrease` / `assign` / `scale-up` / `scale-down` with `?duration` the step's.

use std::collections::{BTreeSet, HashMap};

use super::ast::{self, Arg, Atom, Cmp, Effect, Init, Lit, NExpr, NumOp, When};
use super::writer::IpcStep;
use crate::model::Time;

/// The least separation (ms) the simulator demands between interfering happenings: PDDL's ε as most
/// validators take it (0.001 s).
pub const CHECK_EPSILON_MS: Time = 1;

type Ground = (String, Vec<String>);

/// A condition: the atom and whether it must be true.
type Cond = (Ground, bool);

struct Happening {
    at: Time,
    step: usize,
    when: When,
    pre: Vec<(Ground, bool)>,
    add: Vec<Ground>,
    del: Vec<Ground>,
    /// Numeric comparisons (and, at a start, the duration constraints as `(op, ?duration, e)`).
    num_pre: Vec<(Cmp, NExpr, NExpr)>,
    num_eff: Vec<(NumOp, Ground, NExpr)>,
    /// The numeric fluents it reads and those it changes (for ε-interference).
    reads: Vec<Ground>,
    writes: Vec<Ground>,
    env: HashMap<String, String>,
    /// The step's duration (s).
    dur: f64,
}

/// The first reason a plan is not valid on its PDDL (steps are numbered from 1).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimulateError {
    #[error("step {step} ({action}): {fault}")]
    Step {
        step: usize,
        action: String,
        fault: StepFault,
    },
    #[error("`?duration` is not simulated here")]
    DurationInExpression,
    #[error("{0} has no value")]
    NoValue(String),
    #[error("{first} and {second} interfere within ε at {at_ms} ms")]
    Interfere {
        first: String,
        second: String,
        at_ms: Time,
    },
    #[error("step {step}: {end} condition {atom} is not {value} at {at_ms} ms")]
    Condition {
        step: usize,
        /// `start` or `end`.
        end: &'static str,
        atom: String,
        value: bool,
        at_ms: Time,
    },
    #[error("step {step}: a numeric {end} condition is false at {at_ms} ms")]
    Numeric {
        step: usize,
        end: &'static str,
        at_ms: Time,
    },
    #[error("step {step}: its duration {duration} s breaks its constraint ({bound} s, in the state at its start)")]
    StateDuration {
        step: usize,
        duration: f64,
        bound: f64,
    },
    #[error("step {step}: over-all condition {atom} is not {value} at {at_ms} ms")]
    OverAll {
        step: usize,
        atom: String,
        value: bool,
        at_ms: Time,
    },
    #[error("goals other than literals are not simulated")]
    GoalNotLiteral,
    #[error("goal {}{atom} is not reached", if *.positive { "" } else { "not " })]
    GoalNotReached { atom: String, positive: bool },
}

/// What is wrong with one step on its own.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepFault {
    #[error("no such action")]
    NoSuchAction,
    #[error("{expected} arguments, not {given}")]
    Arity { expected: usize, given: usize },
    #[error("unknown object `{0}`")]
    UnknownObject(String),
    #[error("`{0}` is not of the parameter's type")]
    WrongType(String),
    #[error("an instantaneous action with a duration")]
    InstantaneousWithDuration,
    #[error("an (in)equality is false")]
    Equality,
    #[error("a numeric condition is false")]
    NumericCondition,
}

/// Gives each step whose action fixes its duration on static values (`(= ?duration e)`, `e` reading no
/// fluent an action changes) that duration exactly: the planner works in milliseconds, and a validator
/// compares `[0.530]` with a `slew_time` of 0.5297 exactly. Steps whose duration depends on the state keep
/// their milliseconds.
pub fn exact_durations(d: &ast::Domain, p: &ast::Problem, plan: &mut [IpcStep]) {
    let changed: BTreeSet<&str> = d
        .actions
        .iter()
        .flat_map(|a| &a.effects)
        .filter_map(|(_, e)| match e {
            ast::Effect::Num(_, f, _, _) => Some(f.pred.name.as_str()),
            _ => None,
        })
        .collect();
    fn reads_changed(e: &NExpr, changed: &BTreeSet<&str>) -> bool {
        match e {
            NExpr::Num(..) => false,
            NExpr::Duration(_) => true,
            NExpr::Fluent(f) => changed.contains(f.pred.name.as_str()),
            NExpr::Bin(_, a, b, _) => reads_changed(a, changed) || reads_changed(b, changed),
            NExpr::Neg(a, _) => reads_changed(a, changed),
        }
    }
    let values: HashMap<Ground, f64> = p
        .init
        .iter()
        .filter_map(|i| match i {
            Init::Value(f, v) => Some((ground(f, &HashMap::new()), *v)),
            _ => None,
        })
        .collect();
    for s in plan {
        let Some(a) = d.actions.iter().find(|a| a.name.name == s.action) else {
            continue;
        };
        let [(Cmp::Eq, e, _)] = a.duration.as_slice() else {
            continue;
        };
        if !a.durative || reads_changed(e, &changed) || a.params.len() != s.args.len() {
            continue;
        }
        let env: HashMap<String, String> = a
            .params
            .iter()
            .zip(&s.args)
            .map(|(p, v)| (p.name.name.clone(), v.clone()))
            .collect();
        // Only where the plan's milliseconds are that duration rounded: anything else is the replay's to judge.
        if let Ok(v) = eval(e, &env, &values, None) {
            if v.is_finite()
                && !super::writer::whole_ms(v)
                && ((v * 1000.0).round() as Time) == s.duration_ms
            {
                s.exact_s = Some(v);
            }
        }
    }
}

/// `Ok(makespan ms)` when the plan is valid, else the first reason it is not.
pub fn simulate(
    d: &ast::Domain,
    p: &ast::Problem,
    plan: &[IpcStep],
) -> Result<Time, SimulateError> {
    let mut state: BTreeSet<Ground> = BTreeSet::new();
    let mut values: HashMap<Ground, f64> = HashMap::new();
    let mut tils: Vec<(Time, Ground, bool)> = Vec::new();
    for i in &p.init {
        match i {
            Init::Atom(a, None) => {
                state.insert(ground(a, &HashMap::new()));
            }
            Init::Atom(a, Some(t)) => tils.push((ms(*t), ground(a, &HashMap::new()), true)),
            Init::NotAtom(a, t) => tils.push((ms(*t), ground(a, &HashMap::new()), false)),
            Init::Value(f, v) => {
                values.insert(ground(f, &HashMap::new()), *v);
            }
        }
    }
    let types: HashMap<&str, &str> = p
        .objects
        .iter()
        .chain(&d.constants)
        .map(|o| {
            (
                o.name.name.as_str(),
                o.types.first().map_or("object", |t| t.name.as_str()),
            )
        })
        .collect();
    let is_sub = subtype_test(d);
    let mut happenings: Vec<Happening> = Vec::new();
    let mut spans: Vec<Span> = Vec::new();
    for (k, s) in plan.iter().enumerate() {
        let who = |fault| SimulateError::Step {
            step: k + 1,
            action: s.action.clone(),
            fault,
        };
        let a = d
            .actions
            .iter()
            .find(|a| a.name.name == s.action)
            .ok_or_else(|| who(StepFault::NoSuchAction))?;
        if a.params.len() != s.args.len() {
            return Err(who(StepFault::Arity {
                expected: a.params.len(),
                given: s.args.len(),
            }));
        }
        let mut env: HashMap<String, String> = HashMap::new();
        for (p, v) in a.params.iter().zip(&s.args) {
            let t = types
                .get(v.as_str())
                .ok_or_else(|| who(StepFault::UnknownObject(v.clone())))?;
            if !p.types.iter().any(|x| is_sub(t, &x.name)) {
                return Err(who(StepFault::WrongType(v.clone())));
            }
            env.insert(p.name.name.clone(), v.clone());
        }
        let dur = s.duration_ms as f64 / 1000.0;
        // Duration constraints are checked in the state at the start (they may read numeric fluents).
        let dur_cons: Vec<(Cmp, NExpr, NExpr)> = a
            .duration
            .iter()
            .map(|(c, e, span)| (*c, NExpr::Duration(*span), e.clone()))
            .collect();
        if !a.durative && s.duration_ms != 0 {
            return Err(who(StepFault::InstantaneousWithDuration));
        }
        let mut pre: [Vec<(Ground, bool)>; 3] = Default::default();
        let mut num_pre: [Vec<(Cmp, NExpr, NExpr)>; 3] = Default::default();
        for (w, l) in &a.conditions {
            let slot = &mut pre[*w as usize];
            match l {
                Lit::Pos(x) => slot.push((ground(x, &env), true)),
                Lit::Neg(x) => slot.push((ground(x, &env), false)),
                Lit::Equal(x, y, eq, _) => {
                    if (name(x, &env) == name(y, &env)) != *eq {
                        return Err(who(StepFault::Equality));
                    }
                }
                Lit::Compare(c, x, y, _) => num_pre[*w as usize].push((*c, x.clone(), y.clone())),
            }
        }
        let mut add: [Vec<Ground>; 2] = Default::default();
        let mut del: [Vec<Ground>; 2] = Default::default();
        let mut num_eff: [Vec<(NumOp, Ground, NExpr)>; 2] = Default::default();
        for (w, e) in &a.effects {
            let i = usize::from(*w == When::End);
            match e {
                Effect::Add(x) => add[i].push(ground(x, &env)),
                Effect::Del(x) => del[i].push(ground(x, &env)),
                Effect::Num(op, f, x, _) => num_eff[i].push((*op, ground(f, &env), x.clone())),
            }
        }
        let [mut ns, no, ne] = num_pre;
        ns.extend(dur_cons);
        let [nes, nee] = num_eff;
        let touched = |pre: &[(Cmp, NExpr, NExpr)], eff: &[(NumOp, Ground, NExpr)]| {
            let mut r = Vec::new();
            for (_, x, y) in pre {
                fluents_of(x, &env, &mut r);
                fluents_of(y, &env, &mut r);
            }
            for (_, _, x) in eff {
                fluents_of(x, &env, &mut r);
            }
            (r, eff.iter().map(|e| e.1.clone()).collect::<Vec<_>>())
        };
        let (reads_s, writes_s) = touched(&ns, &nes);
        let (reads_e, writes_e) = touched(&ne, &nee);
        let [ps, po, pe] = pre;
        let [as_, ae] = add;
        let [ds, de] = del;
        let end = s.start_ms + s.duration_ms;
        happenings.push(Happening {
            at: s.start_ms,
            step: k,
            when: When::Start,
            pre: ps,
            add: as_,
            del: ds,
            num_pre: ns,
            num_eff: nes,
            reads: reads_s,
            writes: writes_s,
            env: env.clone(),
            dur,
        });
        happenings.push(Happening {
            at: end,
            step: k,
            when: When::End,
            pre: pe,
            add: ae,
            del: de,
            num_pre: ne,
            num_eff: nee,
            reads: reads_e,
            writes: writes_e,
            env: env.clone(),
            dur,
        });
        spans.push((s.start_ms, end, po, no, env));
    }
    // Timed initial literals are happenings too (no conditions), subject to the same separation.
    for (at, g, add) in &tils {
        happenings.push(Happening {
            at: *at,
            step: usize::MAX,
            when: When::Start,
            pre: Vec::new(),
            add: if *add { vec![g.clone()] } else { Vec::new() },
            del: if *add { Vec::new() } else { vec![g.clone()] },
            num_pre: Vec::new(),
            num_eff: Vec::new(),
            reads: Vec::new(),
            writes: Vec::new(),
            env: HashMap::new(),
            dur: 0.0,
        });
    }
    for i in 0..happenings.len() {
        for j in i + 1..happenings.len() {
            let (x, y) = (&happenings[i], &happenings[j]);
            if x.step == y.step || (x.at - y.at).abs() >= CHECK_EPSILON_MS {
                continue;
            }
            if interfere(x, y) || interfere(y, x) {
                let name = |h: &Happening| match h.step {
                    usize::MAX => "a timed initial literal".to_string(),
                    k => format!("step {}", k + 1),
                };
                return Err(SimulateError::Interfere {
                    first: name(x),
                    second: name(y),
                    at_ms: x.at.min(y.at),
                });
            }
        }
    }
    happenings.sort_by_key(|h| (h.at, h.when == When::Start));
    let mut times: Vec<Time> = happenings
        .iter()
        .map(|h| h.at)
        .chain(tils.iter().map(|t| t.0))
        .collect();
    times.sort_unstable();
    times.dedup();
    for t in times {
        for (at, g, add) in &tils {
            if *at == t {
                if *add {
                    state.insert(g.clone());
                } else {
                    state.remove(g);
                }
            }
        }
        let now: Vec<&Happening> = happenings
            .iter()
            .filter(|h| h.at == t && h.step != usize::MAX)
            .collect();
        for h in &now {
            let end = if h.when == When::Start {
                "start"
            } else {
                "end"
            };
            for (g, v) in &h.pre {
                if state.contains(g) != *v {
                    return Err(SimulateError::Condition {
                        step: h.step + 1,
                        end,
                        atom: show(g),
                        value: *v,
                        at_ms: t,
                    });
                }
            }
            for (c, x, y) in &h.num_pre {
                let dur = Some(h.dur);
                let (xv, yv) = (
                    eval(x, &h.env, &values, dur)?,
                    eval(y, &h.env, &values, dur)?,
                );
                if matches!(x, NExpr::Duration(_)) {
                    // A duration constraint, with the validators' tolerance on the IPC plan's 3 decimals.
                    let ok = match c {
                        Cmp::Eq => (xv - yv).abs() <= 0.0011,
                        Cmp::Le | Cmp::Lt => xv <= yv + 0.0011,
                        Cmp::Ge | Cmp::Gt => xv + 0.0011 >= yv,
                    };
                    if !ok {
                        return Err(SimulateError::StateDuration {
                            step: h.step + 1,
                            duration: xv,
                            bound: yv,
                        });
                    }
                } else if !c.holds(xv, yv) {
                    return Err(SimulateError::Numeric {
                        step: h.step + 1,
                        end,
                        at_ms: t,
                    });
                }
            }
        }
        // Numeric effects read the state before the happenings.
        let mut updates: Vec<(Ground, NumOp, f64)> = Vec::new();
        for h in &now {
            for (op, g, x) in &h.num_eff {
                updates.push((g.clone(), *op, eval(x, &h.env, &values, Some(h.dur))?));
            }
        }
        for (g, op, v) in updates {
            let old = values.get(&g).copied();
            let new = match (op, old) {
                (NumOp::Assign, _) => v,
                (_, None) => return Err(SimulateError::NoValue(show(&g))),
                (NumOp::Increase, Some(o)) => o + v,
                (NumOp::Decrease, Some(o)) => o - v,
                (NumOp::ScaleUp, Some(o)) => o * v,
                (NumOp::ScaleDown, Some(o)) => o / v,
            };
            values.insert(g, new);
        }
        for h in &now {
            for g in &h.del {
                state.remove(g);
            }
        }
        for h in &now {
            for g in &h.add {
                state.insert(g.clone());
            }
        }
        for (k, (s, e, inv, num, env)) in spans.iter().enumerate() {
            if *s <= t && t < *e {
                for (g, v) in inv {
                    if state.contains(g) != *v {
                        return Err(SimulateError::OverAll {
                            step: k + 1,
                            atom: show(g),
                            value: *v,
                            at_ms: t,
                        });
                    }
                }
                for (c, x, y) in num {
                    if !c.holds(eval(x, env, &values, None)?, eval(y, env, &values, None)?) {
                        return Err(SimulateError::Numeric {
                            step: k + 1,
                            end: "over-all",
                            at_ms: t,
                        });
                    }
                }
            }
        }
    }
    for l in &p.goal {
        let (a, positive) = match l {
            Lit::Pos(a) => (a, true),
            Lit::Neg(a) => (a, false),
            _ => return Err(SimulateError::GoalNotLiteral),
        };
        let g = ground(a, &HashMap::new());
        if state.contains(&g) != positive {
            return Err(SimulateError::GoalNotReached {
                atom: show(&g),
                positive,
            });
        }
    }
    Ok(plan
        .iter()
        .map(|s| s.start_ms + s.duration_ms)
        .max()
        .unwrap_or(0))
}

/// Whether a type is `anc` or below it in the domain's hierarchy (every type is below `object`).
pub(super) fn subtype_test(d: &ast::Domain) -> impl Fn(&str, &str) -> bool + '_ {
    let parent: HashMap<&str, &str> = d
        .types
        .iter()
        .map(|(c, p)| (c.name.as_str(), p.name.as_str()))
        .collect();
    move |t: &str, anc: &str| {
        let mut t = t;
        for _ in 0..=parent.len() {
            if t == anc || anc == "object" {
                return true;
            }
            match parent.get(t) {
                Some(p) => t = p,
                None => return false,
            }
        }
        false
    }
}

/// Whether `x`'s effects touch `y`'s conditions or effects (deleting what it adds, or changing what it
/// reads; a numeric fluent `x` changes that `y` reads or changes).
fn interfere(x: &Happening, y: &Happening) -> bool {
    let touched = |g: &Ground| y.pre.iter().any(|(p, _)| p == g);
    x.del.iter().any(|g| touched(g) || y.add.contains(g))
        || x.add.iter().any(|g| touched(g) || y.del.contains(g))
        || x.writes
            .iter()
            .any(|g| y.reads.contains(g) || y.writes.contains(g))
}

/// An over-all interval: start, end, its literal and numeric conditions, its parameters' objects.
type Span = (
    Time,
    Time,
    Vec<Cond>,
    Vec<(Cmp, NExpr, NExpr)>,
    HashMap<String, String>,
);

/// The ground functions an expression reads.
fn fluents_of(e: &NExpr, env: &HashMap<String, String>, out: &mut Vec<Ground>) {
    match e {
        NExpr::Fluent(f) => out.push(ground(f, env)),
        NExpr::Bin(_, x, y, _) => {
            fluents_of(x, env, out);
            fluents_of(y, env, out);
        }
        NExpr::Neg(x, _) => fluents_of(x, env, out),
        NExpr::Num(..) | NExpr::Duration(_) => {}
    }
}

fn ms(s: f64) -> Time {
    (s * 1000.0).round() as Time
}

fn name(a: &Arg, env: &HashMap<String, String>) -> String {
    match a {
        Arg::Var(n) => env.get(&n.name).cloned().unwrap_or_else(|| n.name.clone()),
        Arg::Const(n) => n.name.clone(),
    }
}

fn ground(a: &Atom, env: &HashMap<String, String>) -> Ground {
    (
        a.pred.name.clone(),
        a.args.iter().map(|x| name(x, env)).collect(),
    )
}

fn show(g: &Ground) -> String {
    format!("({} {})", g.0, g.1.join(" "))
}

fn eval(
    e: &NExpr,
    env: &HashMap<String, String>,
    values: &HashMap<Ground, f64>,
    dur: Option<f64>,
) -> Result<f64, SimulateError> {
    Ok(match e {
        NExpr::Num(v, _) => *v,
        NExpr::Duration(_) => dur.ok_or(SimulateError::DurationInExpression)?,
        NExpr::Neg(a, _) => -eval(a, env, values, dur)?,
        NExpr::Bin(op, a, b, _) => {
            ast::arithmetic(*op, eval(a, env, values, dur)?, eval(b, env, values, dur)?)
        }
        NExpr::Fluent(f) => {
            let g = ground(f, env);
            *values
                .get(&g)
                .ok_or_else(|| SimulateError::NoValue(show(&g)))?
        }
    })
}
