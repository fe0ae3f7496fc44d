//! Numeric fluents as reservoirs (issue 32). A function that actions change and something reads becomes one
//! reservoir per ground instance with an initial value (`energy(rover0)`), in the patterns the model's
//! reservoirs express soundly:
//!
//! - `decrease f q` (q static, ≥ 0) guarded by `f >= q` at or before it → `consume q` where the guard is
//!   (a decrease at the end guarded at the start is consumed at the start: the model's level is never above
//!   PDDL's, so every guard the model meets PDDL meets too). The guard makes PDDL's level stay ≥ 0, the
//!   reservoir's lower bound;
//! - `increase f q` (q static) → `produce q`, on a fluent without a capacity (its bound is +∞ then);
//! - `assign f v` (v static), or a recharge at a rate (`increase f (* ?duration r)` with
//!   `(= ?duration (/ (- v f) r))`) → a saturating production of `v`, the instance's capacity (every fill
//!   of one instance fills to one value, and its initial value is at most that);
//! - `f <= v` with v at least the capacity: always true; `f < v` with v the capacity, on an action that
//!   fills `f` at its end: a production of [`STRICT_MARGIN`] at the start (the fill absorbs it);
//! - a duration `(/ (- v f) r)`: the task's duration is left in `[1 ms, v / r]` and fixed once the plan's
//!   changes of `f` are in one order ([`super::finalise`]).
//!
//! An instance that is filled has a lock (a unary resource) that every action reading or changing it holds
//! over the span of its accesses: nothing changes it while a fill runs, so a recharge's rate gives its
//! level exactly and a decrease moved to its action's start cannot cross a fill. A function changed by
//! actions and never read (`total-fuel-used`, only in the metric) cannot make a plan invalid: its effects
//! are left out, with a note. Anything else is refused at its place.

use std::collections::{BTreeSet, HashMap};

use super::ast::{self, Arg, Atom, Cmp, Effect, Init, Lit, NExpr, NumOp, When};
use super::sexpr::Span;
use super::translate::Cx;
use super::PddlError;
use crate::model::{
    Domain, NumTerm, ObjectId, ResourceAttr, ResourceId, ResourceKind, ResourceUsage, Task, TpId,
    UsageKind,
};

const ST: TpId = TpId(0);
const ET: TpId = TpId(1);

/// The capacity of an instance nothing fills: unbounded in PDDL, a large finite number here.
pub const UNBOUNDED: f64 = 1e12;

/// What a strict `f < capacity` asks of the level: at most the capacity less this.
pub const STRICT_MARGIN: f64 = 1e-3;

/// A ground numeric fluent: `(name, arguments)`.
pub(super) type Key = (String, Vec<ObjectId>);

/// One ground instance of a numeric fluent.
#[derive(Debug, Clone)]
pub(super) struct Instance {
    pub resource: ResourceId,
    pub lock: Option<ResourceId>,
    pub capacity: f64,
}

/// A change PDDL makes to an instance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Change {
    Add(f64),
    Sub(f64),
    Set(f64),
    /// A fill at a rate towards this value: the level its fixed duration reaches ([`super::finalise`]).
    Rate(f64),
}

impl Change {
    pub fn apply(self, level: f64) -> f64 {
        match self {
            Change::Add(q) => level + q,
            Change::Sub(q) => level - q,
            Change::Set(v) | Change::Rate(v) => v,
        }
    }
}

/// A read or change of an instance by a task, where PDDL makes it.
#[derive(Debug, Clone, PartialEq)]
pub struct Access {
    pub resource: ResourceId,
    pub at: TpId,
    pub change: Option<Change>,
}

/// A duration `(v - f) / r` that depends on the level of `resource` at the start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateDuration {
    pub resource: ResourceId,
    pub v: f64,
    pub r: f64,
}

/// What a task does to numeric fluents, for [`super::finalise`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TaskNumeric {
    pub accesses: Vec<Access>,
    pub duration: Option<StateDuration>,
}

/// The numeric fluents of a translation: resources and their initial levels.
#[derive(Debug, Clone, Default)]
pub struct Fluents {
    /// Per resource of the model that stands for a fluent instance: its initial level.
    pub initial: HashMap<ResourceId, f64>,
    /// Per task of the model (by index): what it does to them.
    pub tasks: Vec<TaskNumeric>,
}

/// The function names an expression reads.
fn reads(e: &NExpr, out: &mut BTreeSet<String>) {
    match e {
        NExpr::Fluent(f) => {
            out.insert(f.pred.name.clone());
        }
        NExpr::Bin(_, x, y, _) => {
            reads(x, out);
            reads(y, out);
        }
        NExpr::Neg(x, _) => reads(x, out),
        NExpr::Num(..) | NExpr::Duration(_) => {}
    }
}

/// Whether `e` reads one of `names`.
pub(super) fn mentions(e: &NExpr, names: &BTreeSet<String>) -> bool {
    let mut r = BTreeSet::new();
    reads(e, &mut r);
    r.iter().any(|n| names.contains(n))
}

/// `(/ (- v f) r)`: the fluent, `v` and `r`.
pub(super) fn state_duration(e: &NExpr) -> Option<(&Atom, &NExpr, &NExpr)> {
    let NExpr::Bin('/', num, r, _) = e else {
        return None;
    };
    let NExpr::Bin('-', v, f, _) = num.as_ref() else {
        return None;
    };
    let NExpr::Fluent(f) = f.as_ref() else {
        return None;
    };
    Some((f, v, r))
}

/// `(* ?duration r)` or `(* r ?duration)`: `r`.
fn times_duration(e: &NExpr) -> Option<&NExpr> {
    match e {
        NExpr::Bin('*', x, y, _) => match (x.as_ref(), y.as_ref()) {
            (NExpr::Duration(_), r) | (r, NExpr::Duration(_)) if !r.uses_duration() => Some(r),
            _ => None,
        },
        _ => None,
    }
}

/// The fill an effect makes, if it is one: its target value expression. `assign f v`, or `increase f (*
/// ?duration r)` in an action whose duration is `(/ (- v f) r)` (the same `r`, checked on values later).
fn fill<'a>(a: &'a ast::Action, op: NumOp, f: &Atom, e: &'a NExpr) -> Option<Fill<'a>> {
    match op {
        NumOp::Assign if !e.uses_duration() => Some(Fill { v: e, rate: None }),
        NumOp::Increase => {
            let r = times_duration(e)?;
            let (df, v, dr) = a
                .duration
                .iter()
                .find_map(|(c, d, _)| (*c == Cmp::Eq).then(|| state_duration(d)).flatten())?;
            (same_atom(df, f)).then_some(Fill {
                v,
                rate: Some((r, dr)),
            })
        }
        _ => None,
    }
}

struct Fill<'a> {
    v: &'a NExpr,
    /// The effect's rate and the duration's (equal values required).
    rate: Option<(&'a NExpr, &'a NExpr)>,
}

fn same_atom(x: &Atom, y: &Atom) -> bool {
    x.pred.name == y.pred.name
        && x.args.len() == y.args.len()
        && x.args
            .iter()
            .zip(&y.args)
            .all(|(a, b)| a.name().name == b.name().name)
}

/// The functions a condition, a duration, a numeric effect's amount or a goal reads.
pub(super) fn read_functions(d: &ast::Domain, p: &ast::Problem) -> BTreeSet<String> {
    let mut read = BTreeSet::new();
    for a in &d.actions {
        for (_, l) in &a.conditions {
            if let Lit::Compare(_, x, y, _) = l {
                reads(x, &mut read);
                reads(y, &mut read);
            }
        }
        for (_, e, _) in &a.duration {
            reads(e, &mut read);
        }
        for (_, e) in &a.effects {
            if let Effect::Num(_, _, x, _) = e {
                reads(x, &mut read);
            }
        }
    }
    for l in &p.goal {
        if let Lit::Compare(_, x, y, _) = l {
            reads(x, &mut read);
            reads(y, &mut read);
        }
    }
    read
}

/// Finds the numeric fluents (changed and read), the ones only the metric reads, each instance's capacity
/// (from its fills) and makes their resources. Returns notes.
pub(super) fn analyse(
    cx: &mut Cx,
    d: &ast::Domain,
    p: &ast::Problem,
    model: &mut Domain,
) -> Result<Vec<String>, PddlError> {
    let read = read_functions(d, p);
    let changed = cx.fluent_functions.clone();
    cx.numeric = changed.intersection(&read).cloned().collect();
    cx.metric_only = changed.difference(&read).cloned().collect();
    let mut notes = Vec::new();
    if !cx.metric_only.is_empty() {
        let names: Vec<&str> = cx.metric_only.iter().map(String::as_str).collect();
        notes.push(format!(
            "numeric fluent(s) {} changed by actions but read by no condition, duration or effect: their effects are left out (only the metric reads them, and it is not optimised)",
            names.join(", ")
        ));
    }
    // Capacities from the fills, per instance.
    let mut capacity: HashMap<Key, f64> = HashMap::new();
    for a in &d.actions {
        for (_, e) in &a.effects {
            let Effect::Num(op, f, x, span) = e else {
                continue;
            };
            if !cx.numeric.contains(&f.pred.name) {
                continue;
            }
            let Some(fl) = fill(a, *op, f, x) else {
                continue;
            };
            let mut exprs = vec![fl.v];
            exprs.extend(fl.rate.iter().flat_map(|(r, dr)| [*r, *dr]));
            let mut used = Vec::new();
            params_of_atom(f, a, &mut used);
            for e in &exprs {
                params_of(e, a, &mut used);
            }
            for fixed in groundings(cx, a, &used, *span)? {
                let argf = |x: &Arg| fixed_arg(cx, a, &fixed, x);
                let Some(key) = ground_key(cx, f, &argf) else {
                    continue;
                };
                let Ok(v) = cx.eval(fl.v, cx.ds, &argf) else {
                    continue;
                };
                match capacity.get(&key) {
                    Some(c) if (c - v).abs() > crate::model::LEVEL_TOLERANCE => {
                        return Err(cx.derr(*span, format!("`{}` is filled to {c} by one action and to {v} by another: a fluent filled to several values is not supported (its reservoir has one capacity)", show(&key, cx))));
                    }
                    _ => {
                        capacity.insert(key, v);
                    }
                }
            }
        }
    }
    for i in &p.init {
        let Init::Value(f, v) = i else { continue };
        if !cx.numeric.contains(&f.pred.name) {
            continue;
        }
        let args = cx.ground(f)?;
        let key = (f.pred.name.clone(), args);
        let cap = capacity.get(&key).copied();
        if *v < 0.0 {
            return Err(cx.perr(f.span, format!("`{}` starts below 0: the translation maps numeric fluents on reservoirs, whose levels are at least 0", show(&key, cx))));
        }
        if cap.is_some_and(|c| *v > c + crate::model::LEVEL_TOLERANCE) {
            return Err(cx.perr(f.span, format!("`{}` starts above the value actions fill it to ({}): its reservoir's capacity would not bound it", show(&key, cx), cap.unwrap_or(0.0))));
        }
        let name = show(&key, cx);
        let line = Some(srctext::locate(&cx.ps.file, &cx.ps.text, f.span.start, "").line);
        let resource = model.add_resource(ResourceAttr {
            name: name.clone(),
            kind: ResourceKind::Reservoir,
            capacity: cap.unwrap_or(UNBOUNDED),
            line,
        });
        let lock = cap.map(|_| {
            model.add_resource(ResourceAttr {
                name: format!("{name}-lock"),
                kind: ResourceKind::Unary,
                capacity: 1.0,
                line,
            })
        });
        cx.fluent_initial.insert(resource, *v);
        cx.instances.insert(
            key,
            Instance {
                resource,
                lock,
                capacity: cap.unwrap_or(UNBOUNDED),
            },
        );
    }
    Ok(notes)
}

fn show(key: &Key, cx: &Cx) -> String {
    let names: Vec<&str> = key
        .1
        .iter()
        .map(|o| {
            cx.objs
                .iter()
                .find(|(_, id)| *id == o)
                .map_or("?", |(n, _)| n.as_str())
        })
        .collect();
    format!("{}({})", key.0, names.join(", "))
}

/// The ground instance an atom names under `argf`; `None` when an argument is not fixed.
fn ground_key(cx: &Cx, f: &Atom, argf: &dyn Fn(&Arg) -> Option<ObjectId>) -> Option<Key> {
    let _ = cx;
    let args: Option<Vec<ObjectId>> = f.args.iter().map(argf).collect();
    Some((f.pred.name.clone(), args?))
}

/// The object of an argument: a constant, or a parameter fixed for this task.
pub(super) fn fixed_arg(
    cx: &Cx,
    a: &ast::Action,
    fixed: &[(usize, ObjectId)],
    x: &Arg,
) -> Option<ObjectId> {
    match x {
        Arg::Const(n) => cx.objs.get(&n.name).copied(),
        Arg::Var(n) => a
            .params
            .iter()
            .position(|p| p.name.name == n.name)
            .and_then(|i| fixed.iter().find(|f| f.0 == i))
            .map(|f| f.1),
    }
}

/// Every combination of the parameters `used` (by position) may take.
pub(super) fn groundings(
    cx: &Cx,
    a: &ast::Action,
    used: &[usize],
    span: Span,
) -> Result<Vec<Vec<(usize, ObjectId)>>, PddlError> {
    let mut used = used.to_vec();
    used.sort_unstable();
    used.dedup();
    let choices: Vec<Vec<ObjectId>> = used
        .iter()
        .map(|&i| {
            a.params
                .get(i)
                .map_or_else(Vec::new, |p| cx.objects_of(&p.types))
        })
        .collect();
    let n = choices
        .iter()
        .try_fold(1usize, |acc, c| acc.checked_mul(c.len()));
    if n.is_none_or(|n| n > MAX_GROUNDINGS) {
        return Err(cx.derr(span, format!("`{}` depends, through its duration or numeric fluents, on parameters with more than {MAX_GROUNDINGS} combinations", a.name.name)));
    }
    let mut combos: Vec<Vec<(usize, ObjectId)>> = vec![Vec::new()];
    for (&i, c) in used.iter().zip(&choices) {
        combos = combos
            .into_iter()
            .flat_map(|p| c.iter().map(move |o| [p.as_slice(), &[(i, *o)]].concat()))
            .collect();
    }
    Ok(combos)
}

/// Ground combinations of an action's parameters beyond which the translation refuses (a duration or a
/// numeric fluent that depends on parameters makes one task per combination).
pub(super) const MAX_GROUNDINGS: usize = 20_000;

/// Parameters (by position) an expression's functions take.
pub(super) fn params_of(e: &NExpr, a: &ast::Action, out: &mut Vec<usize>) {
    match e {
        NExpr::Fluent(f) => params_of_atom(f, a, out),
        NExpr::Bin(_, x, y, _) => {
            params_of(x, a, out);
            params_of(y, a, out);
        }
        NExpr::Neg(x, _) => params_of(x, a, out),
        NExpr::Num(..) | NExpr::Duration(_) => {}
    }
}

fn params_of_atom(f: &Atom, a: &ast::Action, out: &mut Vec<usize>) {
    for x in &f.args {
        if let Arg::Var(n) = x {
            if let Some(i) = a.params.iter().position(|p| p.name.name == n.name) {
                out.push(i);
            }
        }
    }
}

/// Parameters the numeric part of an action depends on: every comparison's and every numeric effect's
/// (metric-only fluents aside).
pub(super) fn numeric_params(cx: &Cx, a: &ast::Action, out: &mut Vec<usize>) {
    for (_, l) in &a.conditions {
        if let Lit::Compare(_, x, y, _) = l {
            params_of(x, a, out);
            params_of(y, a, out);
        }
    }
    for (_, e) in &a.effects {
        if let Effect::Num(_, f, x, _) = e {
            if cx.metric_only.contains(&f.pred.name) {
                continue;
            }
            params_of_atom(f, a, out);
            params_of(x, a, out);
        }
    }
}

/// Whether every function an expression reads has a value for these parameters (a static one in the
/// problem, a numeric fluent an instance): else the action does not apply to them.
pub(super) fn defined(cx: &Cx, e: &NExpr, argf: &dyn Fn(&Arg) -> Option<ObjectId>) -> bool {
    match e {
        NExpr::Fluent(f) => {
            let Some(key) = ground_key(cx, f, argf) else {
                return true;
            };
            if cx.numeric.contains(&f.pred.name) {
                cx.instances.contains_key(&key)
            } else if cx.functions.contains_key(&f.pred.name)
                && !cx.fluent_functions.contains(&f.pred.name)
            {
                cx.values.contains_key(&key)
            } else {
                true
            }
        }
        NExpr::Bin(_, x, y, _) => defined(cx, x, argf) && defined(cx, y, argf),
        NExpr::Neg(x, _) => defined(cx, x, argf),
        NExpr::Num(..) | NExpr::Duration(_) => true,
    }
}

/// Why a numeric part of an action keeps it from ever applying.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Never {
    /// A guard or an amount that can never be met.
    Unmeetable,
}

/// What one task does to numeric fluents, normalised.
struct Work {
    guards: Vec<(Key, f64, When, Span)>,
    /// `(instance, value, strict, when, span)`: `f <= v` or `f < v`.
    uppers: Vec<(Key, f64, bool, When, Span)>,
    decs: Vec<(Key, f64, When, Span)>,
    incs: Vec<(Key, f64, When, Span)>,
    /// `(instance, value, when, span, at a rate)`.
    fills: Vec<(Key, f64, When, Span, bool)>,
}

/// The numeric conditions, effects and state-dependent duration of one task (its parameters in `fixed`),
/// as usages of `t`. `Ok(Err(_))`: the task can never apply.
pub(super) fn translate(
    cx: &Cx,
    a: &ast::Action,
    fixed: &[(usize, ObjectId)],
    t: &mut Task,
) -> Result<Result<TaskNumeric, Never>, PddlError> {
    let src = cx.ds;
    let argf = |x: &Arg| fixed_arg(cx, a, fixed, x);
    let key_of = |f: &Atom| -> Result<Key, PddlError> {
        ground_key(cx, f, &argf).ok_or_else(|| {
            cx.derr(
                f.span,
                "internal: a numeric fluent's parameter is not fixed for its task",
            )
        })
    };
    let mut w = Work {
        guards: Vec::new(),
        uppers: Vec::new(),
        decs: Vec::new(),
        incs: Vec::new(),
        fills: Vec::new(),
    };
    for (when, l) in &a.conditions {
        let Lit::Compare(c, x, y, span) = l else {
            continue;
        };
        let (lx, ly) = (mentions(x, &cx.numeric), mentions(y, &cx.numeric));
        if !lx && !ly {
            let ok = c.holds(cx.eval(x, src, &argf)?, cx.eval(y, src, &argf)?);
            if !ok {
                return Ok(Err(Never::Unmeetable));
            }
            continue;
        }
        // `f op e` with `e` static: the other way round flips the operator.
        let (f, e, op) = match (x, y) {
            (NExpr::Fluent(f), e) if !ly && cx.numeric.contains(&f.pred.name) => (f, e, *c),
            (e, NExpr::Fluent(f)) if !lx && cx.numeric.contains(&f.pred.name) => (f, e, flip(*c)),
            _ => return Err(cx.derr(*span, "this numeric condition is not supported: the translation reads `f >= e`, `f <= e` and `f < e` with `f` a numeric fluent and `e` static (numbers and functions no action changes)")),
        };
        let key = key_of(f)?;
        let v = cx.eval(e, src, &argf)?;
        match op {
            Cmp::Ge => w.guards.push((key, v, *when, *span)),
            Cmp::Le => w.uppers.push((key, v, false, *when, *span)),
            Cmp::Lt => w.uppers.push((key, v, true, *when, *span)),
            Cmp::Gt | Cmp::Eq => return Err(cx.derr(*span, "a numeric fluent compared with `>` or `=` is not supported: a reservoir's level can be asked to cover an amount (`>=`, with a decrease of it) or to stay under its capacity")),
        }
    }
    for (when, e) in &a.effects {
        let Effect::Num(op, f, x, span) = e else {
            continue;
        };
        if cx.metric_only.contains(&f.pred.name) {
            continue;
        }
        if !cx.numeric.contains(&f.pred.name) {
            return Err(cx.derr(
                *span,
                "internal: a numeric effect on an unclassified function",
            ));
        }
        let key = key_of(f)?;
        if let Some(fl) = fill(a, *op, f, x) {
            if let Some((r, dr)) = fl.rate {
                let (r, dr) = (cx.eval(r, src, &argf)?, cx.eval(dr, src, &argf)?);
                if (r - dr).abs() > 1e-9 {
                    return Err(cx.derr(*span, "a rate in the effect other than the duration's: the effect is not a fill to a fixed value"));
                }
            }
            let v = cx.eval(fl.v, src, &argf)?;
            w.fills.push((key, v, *when, *span, fl.rate.is_some()));
            continue;
        }
        if x.uses_duration() || mentions(x, &cx.numeric) {
            return Err(cx.derr(*span, "a numeric effect by an amount that depends on `?duration` or on a numeric fluent is not supported (only a recharge `(increase f (* ?duration r))` whose duration is `(/ (- v f) r)`, which fills `f` to `v`)"));
        }
        let q = cx.eval(x, src, &argf)?;
        match op {
            NumOp::Decrease if q >= 0.0 => w.decs.push((key, q, *when, *span)),
            NumOp::Increase if q >= 0.0 => w.incs.push((key, q, *when, *span)),
            NumOp::Decrease | NumOp::Increase => return Err(cx.derr(*span, "a negative amount is not supported (a reservoir's consumption or production is at least 0)")),
            NumOp::Assign | NumOp::ScaleUp | NumOp::ScaleDown => return Err(cx.derr(*span, "`assign` to a value that is not the fluent's one fill value, `scale-up` and `scale-down` are not supported: a reservoir changes by amounts or fills to its capacity")),
        }
    }
    let mut out = TaskNumeric::default();
    let tp = |w: When| if w == When::End { ET } else { ST };
    let inst = |key: &Key| cx.instances.get(key);
    // Every instance named must exist (an undefined fluent makes PDDL's conditions false).
    for key in w
        .guards
        .iter()
        .map(|g| &g.0)
        .chain(w.uppers.iter().map(|u| &u.0))
        .chain(w.decs.iter().map(|x| &x.0))
        .chain(w.incs.iter().map(|x| &x.0))
        .chain(w.fills.iter().map(|x| &x.0))
    {
        if inst(key).is_none() {
            return Ok(Err(Never::Unmeetable));
        }
    }
    let mut guards_left: Vec<bool> = vec![true; w.guards.len()];
    let usage = |t: &mut Task, r: ResourceId, kind: UsageKind, q: f64, primary, saturating| {
        t.usages.push(ResourceUsage {
            resource: r,
            kind,
            quantity: NumTerm::Const(q),
            primary,
            saturating,
        })
    };
    for (key, q, when, span) in &w.decs {
        let Some(i) = inst(key) else { continue };
        // A guard `f >= q` at or before the decrease.
        let g = w
            .guards
            .iter()
            .enumerate()
            .position(|(k, (gk, gv, gw, _))| {
                guards_left[k]
                    && gk == key
                    && (gv - q).abs() <= crate::model::LEVEL_TOLERANCE
                    && (*gw == When::Start || *gw == *when)
            });
        let Some(g) = g else {
            return Err(cx.derr(*span, "a decrease that no `>=` condition on the same amount guards (at the same end or at the start) may take the fluent below 0, which the model's reservoirs cannot"));
        };
        guards_left[g] = false;
        let at = tp(w.guards[g].2);
        usage(t, i.resource, UsageKind::Consume { at }, *q, false, false);
        out.accesses.push(Access {
            resource: i.resource,
            at,
            change: None,
        });
        out.accesses.push(Access {
            resource: i.resource,
            at: tp(*when),
            change: Some(Change::Sub(*q)),
        });
    }
    for (k, (key, v, when, span)) in w.guards.iter().enumerate() {
        if !guards_left[k] {
            continue;
        }
        if *v > 0.0 {
            return Err(cx.derr(*span, "a `>=` condition without a decrease of the same amount at or after it is not supported: a reservoir checks a level only where it is consumed"));
        }
        if let Some(i) = inst(key) {
            out.accesses.push(Access {
                resource: i.resource,
                at: tp(*when),
                change: None,
            });
        }
    }
    // Increases (an error where the instance has a capacity: `Some(span)`) and fills (saturating).
    let productions = w
        .incs
        .iter()
        .map(|(k, q, wh, sp)| (k, *q, *wh, Some(*sp), Change::Add(*q)))
        .chain(w.fills.iter().map(|(k, v, wh, _, rate)| {
            let c = if *rate {
                Change::Rate(*v)
            } else {
                Change::Set(*v)
            };
            (k, *v, *wh, None, c)
        }));
    for (key, q, when, increase, change) in productions {
        let Some(i) = inst(key) else { continue };
        if let Some(span) = increase.filter(|_| i.capacity < UNBOUNDED) {
            return Err(cx.derr(span, "an increase of a fluent that actions also fill is not supported (its reservoir's capacity is the fill value, which an increase could pass)"));
        }
        let at = tp(when);
        usage(
            t,
            i.resource,
            UsageKind::Produce { at },
            q,
            true,
            increase.is_none(),
        );
        out.accesses.push(Access {
            resource: i.resource,
            at,
            change: Some(change),
        });
    }
    for (key, v, strict, when, span) in &w.uppers {
        let Some(i) = inst(key) else { continue };
        let fills_at_end = w
            .fills
            .iter()
            .any(|(fk, _, fw, _, _)| fk == key && *fw == When::End);
        if !strict && *v >= i.capacity - crate::model::LEVEL_TOLERANCE {
            // Always true: the level never exceeds the capacity.
        } else if *strict
            && (*v - i.capacity).abs() <= crate::model::LEVEL_TOLERANCE
            && *when == When::Start
            && fills_at_end
        {
            usage(
                t,
                i.resource,
                UsageKind::Produce { at: ST },
                STRICT_MARGIN,
                false,
                false,
            );
        } else {
            return Err(cx.derr(*span, "an upper bound on a numeric fluent is supported only as its capacity (`f <= v` with `v` at least the value actions fill it to, or `f < v` at the start of an action that fills it to `v` at its end)"));
        }
        out.accesses.push(Access {
            resource: i.resource,
            at: tp(*when),
            change: None,
        });
    }
    // A duration that depends on a numeric fluent: `(/ (- v f) r)`.
    for (c, e, span) in &a.duration {
        if !mentions(e, &cx.numeric) {
            continue;
        }
        let sd = state_duration(e).filter(|(f, v, r)| {
            *c == Cmp::Eq
                && cx.numeric.contains(&f.pred.name)
                && !mentions(v, &cx.numeric)
                && !mentions(r, &cx.numeric)
        });
        let Some((f, v, r)) = sd else {
            return Err(cx.derr(*span, "a duration that depends on a numeric fluent is supported only as `(= ?duration (/ (- v f) r))` (a fill at a rate), with `v` and `r` static"));
        };
        let key = key_of(f)?;
        let Some(i) = inst(&key) else {
            return Ok(Err(Never::Unmeetable));
        };
        let (v, r) = (cx.eval(v, src, &argf)?, cx.eval(r, src, &argf)?);
        if r <= 0.0 {
            return Err(cx.derr(*span, "a rate of 0 or less makes this duration undefined"));
        }
        out.duration = Some(StateDuration {
            resource: i.resource,
            v,
            r,
        });
        out.accesses.push(Access {
            resource: i.resource,
            at: ST,
            change: None,
        });
    }
    // The lock of every filled instance touched, over the span of the task's accesses to it.
    let mut locked: Vec<ResourceId> = out.accesses.iter().map(|x| x.resource).collect();
    locked.sort();
    locked.dedup();
    for r in locked {
        let Some(lock) = cx
            .instances
            .values()
            .find(|i| i.resource == r)
            .and_then(|i| i.lock)
        else {
            continue;
        };
        let ats: Vec<TpId> = out
            .accesses
            .iter()
            .filter(|x| x.resource == r)
            .map(|x| x.at)
            .collect();
        let from = if ats.contains(&ST) { ST } else { ET };
        let to = if ats.contains(&ET) { ET } else { ST };
        usage(t, lock, UsageKind::Use { from, to }, 1.0, false, false);
    }
    Ok(Ok(out))
}

fn flip(c: Cmp) -> Cmp {
    match c {
        Cmp::Lt => Cmp::Gt,
        Cmp::Le => Cmp::Ge,
        Cmp::Ge => Cmp::Le,
        Cmp::Gt => Cmp::Lt,
        Cmp::Eq => Cmp::Eq,
    }
}
