//! One PDDL (durative) action as a task of the model: parameters as symbolic variables, the duration
//! constraint as the interval of `et - st`, static conditions as binding constraints or holds on
//! never-changing timelines, and each fluent atom's conditions and effects as events and holds on its
//! timeline at the task's `st` / `et`.
//!
//! Per attribute instance the action touches: the value required at `st` (an `at start` condition, or
//! the atom an `at start` effect deletes), the `at start` effect, the value `over all`, the value required
//! at `et`, the `at end` effect. Where the action changes the instance at one end and reads or changes it
//! at the other, the value in between is held over `[st, et]` (a persistence PDDL leaves to other actions:
//! a stronger, sound requirement). A boolean add or deletion of an atom whose prior value the action does
//! not require gets a fresh `from` variable (any prior value).

use super::ast::{self, Arg, Atom, Cmp, Effect, Lit, When};
use super::fluents::{self, TaskNumeric};
use super::translate::{Cx, PredRep};
use super::PddlError;
use crate::model::{
    AttrId, Binding, Bound, Domain, Event, Hold, NumTerm, ObjectId, ResourceUsage, SymVar,
    SymVarId, Task, TemporalConstraint, Term, Time, TimeInterval, TpId, UsageKind, MS_PER_S,
};

const ST: TpId = TpId(0);
const ET: TpId = TpId(1);

/// The conditions and effects of one action on one attribute instance.
struct Instance {
    attr: AttrId,
    args: Vec<Term>,
    boolean: bool,
    conds: Vec<(When, Term)>,
    /// `(when, new value, deleted value)`: adds carry their value, deletions `+oo` / `false` and, on a
    /// multi-valued variable, the value they remove.
    effects: Vec<(When, Term, Option<Term>, bool)>,
}

/// Why an action can never apply (it is then dropped, with a note saying why).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Inapplicable {
    #[error("no combination of its parameters has a duration")]
    NoDuration,
    #[error("its duration constraints have no solution")]
    DurationUnsatisfiable,
    #[error("an (in)equality between constants is false")]
    ConstantEquality,
    #[error("a numeric condition is never true, or a numeric fluent it needs has no value")]
    NumericNever,
    #[error("its condition on `{0}` is never true")]
    NeverTrue(String),
    #[error("it requires a value and its absence at once")]
    ValueAndAbsence,
    #[error("it requires two different values of one atom at once")]
    TwoValues,
    #[error("its effect on a multi-valued variable does not say the value it replaces")]
    NoReplacedValue,
}

/// The tasks of an action: one, or — when its duration or its numeric fluents depend on some parameters
/// (`(slew_time ?from ?to)`, `(energy ?r)`) — one per combination of those parameters where the functions
/// are defined, each with the parameters bound (`?from in {a}`), its own fixed duration and its own
/// reservoirs. Empty with the reason when the action can never apply.
pub(super) fn tasks(
    cx: &mut Cx,
    a: &ast::Action,
) -> Result<Result<Vec<(Task, TaskNumeric)>, Inapplicable>, PddlError> {
    let mut used: Vec<usize> = Vec::new();
    for (_, e, _) in &a.duration {
        check_duration(cx, e)?;
        fluents::params_of(e, a, &mut used);
    }
    fluents::numeric_params(cx, a, &mut used);
    let mut out = Vec::new();
    let mut last_why = Inapplicable::NoDuration;
    for fixed in fluents::groundings(cx, a, &used, a.span)? {
        // A function without a value for these arguments (a static one the problem does not define, a
        // fluent instance without an initial value): the action does not apply to them.
        let argf = |x: &Arg| fluents::fixed_arg(cx, a, &fixed, x);
        let defined = a
            .duration
            .iter()
            .map(|(_, e, _)| e)
            .chain(a.conditions.iter().flat_map(|(_, l)| match l {
                Lit::Compare(_, x, y, _) => vec![x, y],
                _ => Vec::new(),
            }))
            .chain(a.effects.iter().flat_map(|(_, e)| match e {
                Effect::Num(_, f, x, _) if !cx.metric_only.contains(&f.pred.name) => vec![x],
                _ => Vec::new(),
            }))
            .all(|e| fluents::defined(cx, e, &argf));
        if !defined {
            continue;
        }
        match task(cx, a, &fixed)? {
            Ok(t) => out.push(t),
            Err(why) => last_why = why,
        }
    }
    Ok(if out.is_empty() {
        Err(last_why)
    } else {
        Ok(out)
    })
}

/// Refuses, at its place, what a duration expression may not use: `?duration`, `total-time`, an unknown
/// function or one with the wrong number of arguments, a numeric fluent that actions change (a
/// state-dependent duration). What is left can only fail for a combination of parameters where a static
/// function has no value (the action does not apply there), so no action is ever dropped for a feature the
/// translation does not support.
fn check_duration(cx: &Cx, e: &ast::NExpr) -> Result<(), PddlError> {
    // A fill at a rate, `(/ (- v f) r)`: `f` is read at the start ([`fluents::translate`]).
    if let Some((f, v, r)) = fluents::state_duration(e) {
        if cx.numeric.contains(&f.pred.name) {
            check_duration(cx, v)?;
            return check_duration(cx, r);
        }
    }
    match e {
        ast::NExpr::Num(..) => Ok(()),
        ast::NExpr::Duration(s) => {
            Err(cx.derr(*s, "`?duration` cannot be used in its own duration"))
        }
        ast::NExpr::Neg(x, _) => check_duration(cx, x),
        ast::NExpr::Bin(_, x, y, _) => {
            check_duration(cx, x)?;
            check_duration(cx, y)
        }
        ast::NExpr::Fluent(f) => {
            let name = &f.pred.name;
            if name == "total-time" {
                return Err(cx.derr(f.span, "`total-time` is only meaningful in the metric"));
            }
            match cx.functions.get(name) {
                None => Err(cx.derr(f.span, format!("unknown function `{name}`"))),
                Some(&n) if n != f.args.len() => {
                    Err(cx.derr(f.span, format!("`{name}` takes {n} arguments")))
                }
                _ if cx.fluent_functions.contains(name) => Err(cx.derr(f.span, format!("a duration that depends on `{name}`, a numeric fluent actions change, is supported only as `(= ?duration (/ (- v f) r))` (a fill at a rate) with `v` and `r` static"))),
                _ => Ok(()),
            }
        }
    }
}

/// One task of `a`, the parameters of `fixed` bound to their objects.
fn task(
    cx: &mut Cx,
    a: &ast::Action,
    fixed: &[(usize, ObjectId)],
) -> Result<Result<(Task, TaskNumeric), Inapplicable>, PddlError> {
    let src = cx.ds;
    let mut t = Task::new(
        a.name.name.clone(),
        a.params.len(),
        vec!["st".into(), "et".into()],
        (ST, ET),
        Some(srctext::locate(&src.file, &src.text, a.span.start, "").line),
    );
    for p in &a.params {
        if t.sym_vars
            .iter()
            .any(|v| format!("?{}", v.name) == p.name.name)
        {
            return Err(cx.derr(
                p.name.span,
                format!("parameter `{}` is declared twice", p.name.name),
            ));
        }
        let v = SymVarId::from_index(t.sym_vars.len());
        t.sym_vars.push(SymVar {
            name: p.name.name.trim_start_matches('?').to_string(),
            ty: cx.model_type(&p.types),
        });
        if let Some(&(_, o)) = fixed.iter().find(|f| f.0 == v.index()) {
            t.bindings.push(Binding::In(v, vec![o]));
        } else if cx.restricts(&p.types) {
            t.bindings.push(Binding::In(v, cx.objects_of(&p.types)));
        }
    }
    let term = |cx: &Cx, arg: &Arg| -> Result<Term, PddlError> {
        match arg {
            Arg::Var(n) => a
                .params
                .iter()
                .position(|p| p.name.name == n.name)
                .map(|i| Term::Var(SymVarId::from_index(i)))
                .ok_or_else(|| {
                    cx.derr(
                        n.span,
                        format!("`{}` is not a parameter of `{}`", n.name, a.name.name),
                    )
                }),
            Arg::Const(n) => cx.constant(n, cx.ds).map(Term::Obj),
        }
    };
    let terms = |cx: &Cx, atom: &Atom| -> Result<Vec<Term>, PddlError> {
        atom.args.iter().map(|x| term(cx, x)).collect()
    };
    // Duration.
    let (mut lb, mut ub): (Time, Option<Time>) = (0, None);
    if a.durative {
        for (c, e, _) in &a.duration {
            let argf = |x: &Arg| fluents::fixed_arg(cx, a, fixed, x);
            // A fill at a rate lasts `(v - f) / r` with `f` its level at the start: between 1 ms and
            // `v / r` here, fixed once the plan's changes of `f` are in one order (`super::finalise`).
            if let Some((_, v, r)) =
                fluents::state_duration(e).filter(|(f, _, _)| cx.numeric.contains(&f.pred.name))
            {
                let full = cx.eval(v, src, &argf)? / cx.eval(r, src, &argf)?;
                let ms = (full * MS_PER_S as f64).ceil().max(1.0) as Time;
                lb = lb.max(1);
                ub = Some(ub.map_or(ms, |u| u.min(ms)));
                continue;
            }
            let v = cx.eval(e, src, &argf)?;
            let ms = (v * MS_PER_S as f64).round() as Time;
            match c {
                Cmp::Eq => {
                    lb = lb.max(ms);
                    ub = Some(ub.map_or(ms, |u| u.min(ms)));
                }
                Cmp::Le | Cmp::Lt => ub = Some(ub.map_or(ms, |u| u.min(ms))),
                Cmp::Ge | Cmp::Gt => lb = lb.max(ms),
            }
        }
    } else {
        ub = Some(0);
    }
    if ub.is_some_and(|u| u < lb) {
        return Ok(Err(Inapplicable::DurationUnsatisfiable));
    }
    t.temporal.push(TemporalConstraint {
        from: ST,
        to: ET,
        interval: TimeInterval {
            lb: Bound::Closed(lb),
            ub: ub.map_or(Bound::Inf, Bound::Closed),
        },
    });
    let mut insts: Vec<Instance> = Vec::new();
    let mut locks: Vec<crate::model::ResourceId> = Vec::new();
    let mut static_holds: Vec<(AttrId, Vec<Term>, bool, When)> = Vec::new();
    for (w, l) in &a.conditions {
        match l {
            Lit::Equal(x, y, eq, _) => {
                let (x, y) = (term(cx, x)?, term(cx, y)?);
                match (x, y) {
                    (Term::Obj(p), Term::Obj(q)) if (p == q) != *eq => {
                        return Ok(Err(Inapplicable::ConstantEquality))
                    }
                    (Term::Obj(_), Term::Obj(_)) => {}
                    _ => t.bindings.push(if *eq {
                        Binding::Eq(x, y)
                    } else {
                        Binding::Ne(x, y)
                    }),
                }
            }
            // Numeric conditions: `fluents::translate`, below.
            Lit::Compare(..) => {}
            Lit::Pos(atom) | Lit::Neg(atom) => {
                let positive = matches!(l, Lit::Pos(_));
                let (rep, params) = cx.pred(atom, src)?.clone();
                let args = terms(cx, atom)?;
                match rep {
                    PredRep::Bool {
                        attr,
                        fluent: false,
                    } => match static_condition(cx, atom, &args, &params, positive, &mut t) {
                        Some(true) => {}
                        Some(false) => {
                            return Ok(Err(Inapplicable::NeverTrue(atom.pred.name.clone())))
                        }
                        None => static_holds.push((attr, args, positive, *w)),
                    },
                    PredRep::Bool { attr, fluent: true } => {
                        let v = Term::Obj(Domain::truth(positive));
                        instance(&mut insts, attr, args, true).conds.push((*w, v));
                    }
                    PredRep::Group(g) => {
                        let (key, value) = g.split_terms(&args);
                        instance(&mut insts, g.attr, key, false)
                            .conds
                            .push((*w, value));
                    }
                    PredRep::Lock { resource } => {
                        if !locks.contains(&resource) {
                            locks.push(resource);
                        }
                    }
                }
            }
        }
    }
    for (w, e) in &a.effects {
        let (atom, add) = match e {
            Effect::Add(x) => (x, true),
            Effect::Del(x) => (x, false),
            // Numeric effects: `fluents::translate`, below.
            Effect::Num(..) => continue,
        };
        let (rep, _) = cx.pred(atom, src)?.clone();
        let args = terms(cx, atom)?;
        match rep {
            PredRep::Bool { attr, .. } => {
                let v = Term::Obj(Domain::truth(add));
                instance(&mut insts, attr, args, true)
                    .effects
                    .push((*w, v, None, add));
            }
            PredRep::Group(g) => {
                let (key, value) = g.split_terms(&args);
                let eff = if add {
                    (*w, value, None, true)
                } else {
                    (*w, Term::Unknown, Some(value), false)
                };
                instance(&mut insts, g.attr, key, false).effects.push(eff);
            }
            // The lock's use covers its deletion at `st` and its return at `et`.
            PredRep::Lock { .. } => {}
        }
    }
    for resource in locks {
        t.usages.push(ResourceUsage {
            resource,
            kind: UsageKind::Use { from: ST, to: ET },
            quantity: NumTerm::Const(1.0),
            primary: false,
            saturating: false,
        });
    }
    for (attr, args, positive, w) in static_holds {
        let at = if w == When::End { ET } else { ST };
        t.holds.push(Hold {
            attr,
            args,
            value: Term::Obj(Domain::truth(positive)),
            from: at,
            to: at,
        });
    }
    for inst in insts {
        if let Err(why) = emit(cx, &mut t, inst) {
            return Ok(Err(why));
        }
    }
    match fluents::translate(cx, a, fixed, &mut t)? {
        Ok(numeric) => Ok(Ok((t, numeric))),
        Err(fluents::Never::Unmeetable) => Ok(Err(Inapplicable::NumericNever)),
    }
}

fn instance(
    insts: &mut Vec<Instance>,
    attr: AttrId,
    args: Vec<Term>,
    boolean: bool,
) -> &mut Instance {
    let i = match insts.iter().position(|x| x.attr == attr && x.args == args) {
        Some(i) => i,
        None => {
            insts.push(Instance {
                attr,
                args,
                boolean,
                conds: Vec::new(),
                effects: Vec::new(),
            });
            insts.len() - 1
        }
    };
    &mut insts[i]
}

/// A static atom in a condition: `Some(truth)` when decided here (constants, or one parameter restricted
/// by a binding `?v in {...}`), `None` when it must be a hold on its (never-changing) timeline.
fn static_condition(
    cx: &mut Cx,
    atom: &Atom,
    args: &[Term],
    params: &[ast::Typed],
    positive: bool,
    t: &mut Task,
) -> Option<bool> {
    let trues = cx.init_true.get(&atom.pred.name);
    let vars: Vec<usize> = args
        .iter()
        .enumerate()
        .filter(|(_, x)| matches!(x, Term::Var(_)))
        .map(|(i, _)| i)
        .collect();
    match vars.as_slice() {
        [] => {
            let ground: Vec<_> = args
                .iter()
                .filter_map(|x| if let Term::Obj(o) = x { Some(*o) } else { None })
                .collect();
            Some(trues.is_some_and(|s| s.contains(&ground)) == positive)
        }
        [i] => {
            let Term::Var(v) = args[*i] else { return None };
            let candidates = params
                .get(*i)
                .map_or_else(Vec::new, |p| cx.objects_of(&p.types));
            let allowed: Vec<_> = candidates
                .into_iter()
                .filter(|o| {
                    let ground: Vec<_> = args
                        .iter()
                        .map(|x| match x {
                            Term::Obj(c) => *c,
                            _ => *o,
                        })
                        .collect();
                    trues.is_some_and(|s| s.contains(&ground)) == positive
                })
                .collect();
            if allowed.is_empty() {
                return Some(false);
            }
            t.bindings.push(Binding::In(v, allowed));
            Some(true)
        }
        _ => {
            if !positive {
                cx.needs_false.insert(atom.pred.name.clone());
            }
            None
        }
    }
}

/// Merges a required value into `slot`: a binding when two variables (or a variable and a constant) must
/// be equal; `Err` when two constants differ.
fn unify(slot: &mut Option<Term>, v: Term, t: &mut Task) -> Result<(), Inapplicable> {
    match *slot {
        None => *slot = Some(v),
        Some(x) if x == v => {}
        Some(x @ Term::Var(_)) | Some(x @ Term::Obj(_))
            if matches!(v, Term::Var(_)) || matches!(x, Term::Var(_)) =>
        {
            if matches!(v, Term::Unknown) {
                return Err(Inapplicable::ValueAndAbsence);
            }
            t.bindings.push(Binding::Eq(x, v));
        }
        Some(_) => return Err(Inapplicable::TwoValues),
    }
    Ok(())
}

/// A fresh symbolic variable of type bool (any prior value of a boolean atom).
fn any_bool(t: &mut Task) -> Term {
    let v = SymVarId::from_index(t.sym_vars.len());
    t.sym_vars.push(SymVar {
        name: format!("prior{}", v.0),
        ty: Domain::BOOL,
    });
    Term::Var(v)
}

fn emit(_cx: &Cx, t: &mut Task, inst: Instance) -> Result<(), Inapplicable> {
    let mut s_req = None;
    let mut mid = None;
    let mut e_req = None;
    for (w, v) in &inst.conds {
        let slot = match w {
            When::Start => &mut s_req,
            When::OverAll => &mut mid,
            When::End => &mut e_req,
        };
        unify(slot, *v, t)?;
    }
    let eff =
        |when: When, t: &mut Task, req: &mut Option<Term>| -> Result<Option<Term>, Inapplicable> {
            let mut added: Option<Term> = None;
            let mut deleted = false;
            for (w, v, removed, add) in &inst.effects {
                if *w != when {
                    continue;
                }
                if let Some(r) = removed {
                    unify(req, *r, t)?;
                }
                if *add {
                    unify(&mut added, *v, t)?;
                } else {
                    deleted = true;
                }
            }
            // PDDL applies deletions before additions at one instant.
            let removed = if inst.boolean {
                Term::Obj(Domain::FALSE)
            } else {
                Term::Unknown
            };
            Ok(added.or(deleted.then_some(removed)))
        };
    let e_s = eff(When::Start, t, &mut s_req)?;
    let e_e = eff(When::End, t, &mut e_req)?;
    let from_or_any = |req: Option<Term>, t: &mut Task| -> Result<Term, Inapplicable> {
        match req {
            Some(v) => Ok(v),
            // An add or a deletion the action does not require a value for takes any prior value: asking
            // an add for a false atom would forbid the plans where the atom is already true (and no action
            // deletes it), a false "no plan" (issue 32).
            None if inst.boolean => Ok(any_bool(t)),
            None => Err(Inapplicable::NoReplacedValue),
        }
    };
    if let Some(v) = e_s {
        let from = from_or_any(s_req, t)?;
        t.events.push(Event {
            attr: inst.attr,
            args: inst.args.clone(),
            from,
            to: v,
            at: ST,
            primary: primary(v),
        });
    }
    let after_s = e_s.or(s_req);
    let end_stuff = e_req.is_some() || e_e.is_some();
    let mut m = mid;
    if let Some(v) = e_s {
        if m.is_some() {
            unify(&mut m, v, t)?;
        }
    }
    if m.is_none() && end_stuff && (e_s.is_some() || e_e.is_some()) {
        m = after_s;
    }
    if let (Some(_), Some(a)) = (m, after_s) {
        unify(&mut m, a, t)?;
    }
    if let Some(v) = m {
        t.holds.push(Hold {
            attr: inst.attr,
            args: inst.args.clone(),
            value: v,
            from: ST,
            to: ET,
        });
    } else if let (Some(v), None) = (s_req, e_s) {
        t.holds.push(Hold {
            attr: inst.attr,
            args: inst.args.clone(),
            value: v,
            from: ST,
            to: ST,
        });
    }
    let mut pre_end = e_req;
    if let Some(v) = m {
        if pre_end.is_some() {
            unify(&mut pre_end, v, t)?;
        }
    }
    match e_e {
        Some(v) => {
            let from = match pre_end.or(m) {
                Some(x) => x,
                None => from_or_any(None, t)?,
            };
            t.events.push(Event {
                attr: inst.attr,
                args: inst.args.clone(),
                from,
                to: v,
                at: ET,
                primary: primary(v),
            });
        }
        None => {
            if let Some(r) = pre_end {
                if m != Some(r) {
                    t.holds.push(Hold {
                        attr: inst.attr,
                        args: inst.args.clone(),
                        value: r,
                        from: ET,
                        to: ET,
                    });
                }
            }
        }
    }
    Ok(())
}

/// Deletions are side effects: nothing is inserted to make an atom false or a variable `+oo`
/// (negative conditions aside, which the initial closed world or a deleting action already serve).
fn primary(to: Term) -> bool {
    !matches!(to, Term::Unknown)
}
