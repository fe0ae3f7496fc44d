//! Task semantic checks: the body of `task NAME(params) (timepoints) { ... } preemption` → [`Task`].

use std::collections::HashMap;

use crate::model::Bound;
use crate::model::{
    AttrId, Binding, Domain, Event, Hold, NumConstraint, NumInterval, NumTerm, NumVar, NumVarId,
    ObjectId, Preemption, ResourceKind, ResourceUsage, SymVar, SymVarId, Task, TemporalConstraint,
    Term, Time, TimeInterval, TpId, TypeId, UsageKind,
};

use super::ast::{
    AttrRef, BinOp, Expr, ExprKind, Ident, InSet, RelOp, Stmt, TaskAst, UsageAst, UsageStmt,
};
use super::diag::Span;
use super::eval::{self, Clock, Ctx};
use super::resolve_domain::{logical_attr, type_ref, Names};

enum Var {
    Sym(SymVarId),
    Num(NumVarId),
}

struct Scope<'d> {
    domain: &'d Domain,
    vars: HashMap<String, Var>,
    sym: Vec<SymVar>,
    num: Vec<NumVar>,
    tps: Vec<String>,
}

/// `attr(args)`: a logical attribute and its arguments.
type AttrInstance = (AttrId, Vec<Term>);

impl Scope<'_> {
    fn tp(&self, name: &str) -> Option<TpId> {
        self.tps
            .iter()
            .position(|t| t == name)
            .map(TpId::from_index)
    }

    fn type_name(&self, t: TypeId) -> &str {
        self.domain
            .types
            .get(t.index())
            .map_or("?", |t| t.name.as_str())
    }

    fn term_type(&self, t: Term) -> Option<TypeId> {
        match t {
            Term::Var(v) => self.sym.get(v.index()).map(|v| v.ty),
            Term::Obj(o) => self.domain.objects.get(o.index()).map(|o| o.ty),
            Term::Unknown => None,
        }
    }

    fn tp_ref(&self, ctx: &mut Ctx<'_>, id: &Ident) -> Option<TpId> {
        let t = self.tp(&id.name);
        if t.is_none() {
            ctx.err(
                id.span,
                format!(
                    "unknown timepoint `{}` (this task's timepoints: {})",
                    id.name,
                    self.tps.join(", ")
                ),
            );
        }
        t
    }

    /// A symbolic term of type `expected` (if given); `+oo` only where a value is expected.
    fn sym_term(
        &self,
        ctx: &mut Ctx<'_>,
        e: &Expr,
        expected: Option<TypeId>,
        allow_unknown: bool,
    ) -> Option<Term> {
        let term = match &e.kind {
            ExprKind::Var(v) => match self.vars.get(v) {
                Some(Var::Sym(id)) => Term::Var(*id),
                Some(Var::Num(_)) => {
                    ctx.err(
                        e.span,
                        format!("`?{v}` is a numeric variable; a symbolic value is expected here"),
                    );
                    return None;
                }
                None => {
                    ctx.err(e.span, format!("unknown variable `?{v}`"));
                    return None;
                }
            },
            ExprKind::Name(n) => match self.domain.object_id(n) {
                Some(o) => Term::Obj(o),
                None if self.tp(n).is_some() => {
                    ctx.err(e.span, format!("`{n}` is a timepoint, not a value"));
                    return None;
                }
                None => {
                    let hint = expected
                        .map(|t| &self.domain.ty(t).members)
                        .filter(|m| !m.is_empty())
                        .map(|m| {
                            let names: Vec<&str> = m
                                .iter()
                                .map(|o| self.domain.objects[o.index()].name.as_str())
                                .collect();
                            format!(" (expected one of {})", names.join(", "))
                        })
                        .unwrap_or_default();
                    ctx.err(e.span, format!("unknown value `{n}`{hint}"));
                    return None;
                }
            },
            ExprKind::PosInf if allow_unknown => return Some(Term::Unknown),
            ExprKind::PosInf => {
                ctx.err(e.span, "`+oo` (unknown) can be a value but not an argument");
                return None;
            }
            _ => {
                ctx.err(
                    e.span,
                    "expected a value: a constant, a `?variable` or `+oo`",
                );
                return None;
            }
        };
        if let (Some(want), Some(have)) = (expected, self.term_type(term)) {
            if want != have {
                ctx.err(
                    e.span,
                    format!(
                        "value outside its domain: expected a {}, found a {}",
                        self.type_name(want),
                        self.type_name(have)
                    ),
                );
                return None;
            }
        }
        Some(term)
    }

    fn num_term(&self, ctx: &mut Ctx<'_>, e: &Expr) -> Option<NumTerm> {
        match &e.kind {
            ExprKind::Var(v) => {
                match self.vars.get(v) {
                    Some(Var::Num(id)) => Some(NumTerm::Var(*id)),
                    Some(Var::Sym(_)) => {
                        ctx.err(
                            e.span,
                            format!("`?{v}` is a symbolic variable; a number is expected here"),
                        );
                        None
                    }
                    None => {
                        ctx.err(e.span, format!("unknown variable `?{v}` (declare numeric ones with `variable ?{v};`)"));
                        None
                    }
                }
            }
            _ => eval::num(ctx, e, false).map(NumTerm::Const),
        }
    }

    /// `attr(args)` on a logical attribute: lookup, arity and argument types.
    fn attr_ref(&self, ctx: &mut Ctx<'_>, a: &AttrRef) -> Option<AttrInstance> {
        let id = logical_attr(ctx, self.domain, a, "use `use`, `consume` or `produce`")?;
        let attr = self.domain.attr(id);
        let mut args = Vec::new();
        for (e, (_, t)) in a.args.iter().zip(&attr.params) {
            args.push(self.sym_term(ctx, e, Some(*t), false));
        }
        let args: Option<Vec<Term>> = args.into_iter().collect();
        Some((id, args?))
    }

    /// `attr(args)` ([`Self::attr_ref`]) and the values written for it (of its value type) in an event or
    /// a hold; each value is checked even when the attribute is wrong.
    fn attr_values<const N: usize>(
        &self,
        ctx: &mut Ctx<'_>,
        a: &AttrRef,
        values: [&Expr; N],
    ) -> (Option<AttrInstance>, [Option<Term>; N]) {
        let attr = self.attr_ref(ctx, a);
        let vt = attr
            .as_ref()
            .map(|(id, _)| self.domain.attr(*id).value_type);
        (attr, values.map(|e| self.sym_term(ctx, e, vt, true)))
    }

    /// `(a - b)` with two timepoints: `Some((b, a))` (from, to).
    fn tp_diff(&self, e: &Expr) -> Option<(TpId, TpId)> {
        if let ExprKind::Bin(BinOp::Sub, a, b) = &e.kind {
            if let (ExprKind::Name(a), ExprKind::Name(b)) = (&a.kind, &b.kind) {
                return Some((self.tp(b)?, self.tp(a)?));
            }
        }
        None
    }
}

pub fn resolve(ctx: &mut Ctx<'_>, domain: &Domain, ast: &TaskAst) -> Option<Task> {
    let errors_before = ctx.diags.len();
    let mut s = Scope {
        domain,
        vars: HashMap::new(),
        sym: Vec::new(),
        num: Vec::new(),
        tps: Vec::new(),
    };
    let mut names = Names::default();
    for (v, t) in &ast.params {
        if !names.declare(ctx, v, "variable") {
            continue;
        }
        if let Some(ty) = type_ref(ctx, domain, t) {
            s.vars
                .insert(v.name.clone(), Var::Sym(SymVarId::from_index(s.sym.len())));
            s.sym.push(SymVar {
                name: v.name.clone(),
                ty,
            });
        }
    }
    let n_params = s.sym.len();
    let mut tp_names = Names::default();
    for tp in &ast.timepoints {
        if tp_names.declare(ctx, tp, "timepoint") {
            s.tps.push(tp.name.clone());
        }
    }
    // Declarations first, so statements may use variables declared further down (as in Fig. 3a).
    for st in &ast.body {
        if let Stmt::Variables(vs) = st {
            for (v, t) in vs {
                if !names.declare(ctx, v, "variable") {
                    continue;
                }
                match t {
                    Some(t) => {
                        if let Some(ty) = type_ref(ctx, domain, t) {
                            s.vars.insert(
                                v.name.clone(),
                                Var::Sym(SymVarId::from_index(s.sym.len())),
                            );
                            s.sym.push(SymVar {
                                name: v.name.clone(),
                                ty,
                            });
                        }
                    }
                    None => {
                        s.vars
                            .insert(v.name.clone(), Var::Num(NumVarId::from_index(s.num.len())));
                        s.num.push(NumVar {
                            name: v.name.clone(),
                            domain: NumInterval::ANY,
                        });
                    }
                }
            }
        }
    }
    let start = TpId(0);
    let end = TpId::from_index(s.tps.len().saturating_sub(1));
    let mut task = Task::new(
        ast.name.name.clone(),
        n_params,
        s.tps.clone(),
        (start, end),
        Some(ctx.src.line(ast.name.span.start)),
    );
    // Implicit: start <= t <= end for every timepoint (kept explicit for the planner).
    let mut stn = TaskStn::new(s.tps.len());
    for i in 0..s.tps.len() {
        let t = TpId::from_index(i);
        if t != start {
            task.temporal.push(TemporalConstraint {
                from: start,
                to: t,
                interval: TimeInterval::at_least(0),
            });
            stn.add(start, t, TimeInterval::at_least(0));
        }
        if t != end && t != start {
            task.temporal.push(TemporalConstraint {
                from: t,
                to: end,
                interval: TimeInterval::at_least(0),
            });
            stn.add(t, end, TimeInterval::at_least(0));
        }
    }
    let mut numeric_spans: Vec<Span> = Vec::new();
    for st in &ast.body {
        statement(ctx, &mut s, &mut task, &mut stn, st);
        if let Stmt::Rel { span, .. } = st {
            numeric_spans.resize(task.numeric.len(), *span);
        }
    }
    numeric_contradictions(ctx, &s, &task.numeric, &numeric_spans);
    task.preemption = match ast.preemption.as_ref().map(|p| p.name.as_str()) {
        None | Some("nonPreemptive") => Preemption::NonPreemptive,
        Some("earlyPreemptive") => Preemption::EarlyPreemptive,
        _ => Preemption::LatePreemptive,
    };
    task.sym_vars = s.sym;
    task.num_vars = s.num;
    if s.tps.is_empty() {
        ctx.err(
            ast.name.span,
            "a task needs at least one timepoint, e.g. `(st, et)`",
        );
    }
    (ctx.diags.len() == errors_before).then_some(task)
}

fn statement(ctx: &mut Ctx<'_>, s: &mut Scope<'_>, task: &mut Task, stn: &mut TaskStn, st: &Stmt) {
    match st {
        Stmt::Variables(_) => {}
        Stmt::Event {
            secondary,
            attr,
            from,
            to,
            at,
            ..
        } => {
            let (a, [f, t]) = s.attr_values(ctx, attr, [from, to]);
            let at = s.tp_ref(ctx, at);
            if let (Some((attr_id, args)), Some(from), Some(to), Some(at)) = (a, f, t, at) {
                if from == to && !matches!(from, Term::Var(_)) {
                    ctx.err(
                        attr.span,
                        "an event must change the value: `from` and `to` are the same",
                    );
                }
                task.events.push(Event {
                    attr: attr_id,
                    args,
                    from,
                    to,
                    at,
                    primary: !secondary,
                });
            }
        }
        Stmt::Hold {
            attr,
            value,
            from,
            to,
            ..
        } => {
            let (a, [v]) = s.attr_values(ctx, attr, [value]);
            let f = s.tp_ref(ctx, from);
            let t = match to {
                Some(to) => s.tp_ref(ctx, to),
                None => f,
            };
            if let (Some((attr_id, args)), Some(value), Some(from), Some(to)) = (a, v, f, t) {
                task.holds.push(Hold {
                    attr: attr_id,
                    args,
                    value,
                    from,
                    to,
                });
            }
        }
        Stmt::Usage(u) => usage(ctx, s, task, u),
        Stmt::In { lhs, set, span } => {
            for e in lhs {
                constrain_in(ctx, s, task, stn, e, set, *span);
            }
        }
        Stmt::Rel { lhs, op, rhs, span } => relation(ctx, s, task, lhs, *op, rhs, *span),
        Stmt::Achieve(_, span) => ctx.err(*span, "`achieve` belongs in goals, not in tasks"),
        Stmt::Contingent(inner, span) => {
            statement(ctx, s, task, stn, inner);
            contingent(ctx, s, task, inner, *span);
        }
    }
}

fn usage(ctx: &mut Ctx<'_>, s: &Scope<'_>, task: &mut Task, u: &UsageStmt) {
    let (resource, quantity) = (&u.resource, &u.quantity);
    let Some(r) = s.domain.resource_id(&resource.name) else {
        let msg = if s.domain.attr_id(&resource.name).is_some() {
            format!(
                "`{}` is a logical attribute: use `event` or `hold`",
                resource.name
            )
        } else {
            format!("unknown resource `{}`", resource.name)
        };
        ctx.err(resource.span, msg);
        return;
    };
    let rk = s.domain.resource(r).kind;
    let q = s.num_term(ctx, quantity);
    if let Some(NumTerm::Const(c)) = q {
        if c < 0.0 {
            ctx.err(quantity.span, "a resource quantity cannot be negative");
            return;
        }
        if rk == ResourceKind::Unary && c > 1.0 {
            ctx.err(quantity.span, "a unary resource is used with quantity 1");
            return;
        }
    }
    let f = s.tp_ref(ctx, &u.from);
    let t = u.to.as_ref().and_then(|t| s.tp_ref(ctx, t));
    let uk = match (u.kind, u.to.is_some()) {
        (UsageAst::Use, true) => t.and_then(|t| f.map(|f| UsageKind::Use { from: f, to: t })),
        (UsageAst::Use, false) => {
            ctx.err(
                u.span,
                "`use` borrows over an interval: `use(r: q, (from, to))`",
            );
            None
        }
        (_, true) => {
            ctx.err(
                u.span,
                "`consume` / `produce` happen at one timepoint: `consume(r: q, t)`",
            );
            None
        }
        (UsageAst::Consume, false) => f.map(|at| UsageKind::Consume { at }),
        (UsageAst::Produce, false) => f.map(|at| UsageKind::Produce { at }),
    };
    if rk == ResourceKind::Unary && u.kind != UsageAst::Use {
        ctx.err(
            u.span,
            format!(
                "`{}` is a unary resource: it can only be borrowed with `use`",
                resource.name
            ),
        );
        return;
    }
    if let (Some(kind), Some(quantity)) = (uk, q) {
        task.usages.push(ResourceUsage {
            resource: r,
            kind,
            quantity,
            primary: matches!(kind, UsageKind::Produce { .. }) && !u.secondary,
            saturating: u.saturating,
        });
    }
}

fn constrain_in(
    ctx: &mut Ctx<'_>,
    s: &mut Scope<'_>,
    task: &mut Task,
    stn: &mut TaskStn,
    e: &Expr,
    set: &InSet,
    span: Span,
) {
    if let Some((from, to)) = s.tp_diff(e) {
        let InSet::Interval(i) = set else {
            ctx.err(
                span,
                "a duration is constrained by an interval such as `[2, 60]`",
            );
            return;
        };
        if let Some(iv) = eval::time_interval(ctx, i, Clock(None)) {
            // A task that may last 0 ms is scheduled so by the planner, and its holds over an empty
            // (st, et) then meet the next change at the same instant, which the plan checker refuses.
            if (from, to) == (task.start, task.end) && iv.min_ms().is_none_or(|lb| lb <= 0) {
                ctx.err(
                    span,
                    "a task's duration needs a lower bound above 0 (e.g. `(et - st) in ]0, 60]` or `[1, +oo[`)",
                );
                return;
            }
            if !stn.add(from, to, iv) {
                ctx.err(span, "contradictory temporal constraints: no schedule satisfies this with the task's other constraints");
            }
            task.temporal.push(TemporalConstraint {
                from,
                to,
                interval: iv,
            });
        }
        return;
    }
    match (
        &e.kind,
        s.vars.get(match &e.kind {
            ExprKind::Var(v) => v.as_str(),
            _ => "",
        }),
    ) {
        (ExprKind::Var(_), Some(Var::Num(id))) => {
            let id = *id;
            let InSet::Interval(i) = set else {
                ctx.err(
                    span,
                    "a numeric variable's domain is an interval such as `[0.3, 0.6]`",
                );
                return;
            };
            if let Some(iv) = eval::num_interval(ctx, i) {
                let var = &mut s.num[id.index()];
                var.domain = eval::intersect_num(var.domain, iv);
                if var.domain.is_empty() {
                    ctx.err(
                        span,
                        format!("contradictory: the domain of `?{}` becomes empty", var.name),
                    );
                }
            }
        }
        (ExprKind::Var(_), Some(Var::Sym(id))) => {
            let id = *id;
            let InSet::Set(values) = set else {
                ctx.err(
                    span,
                    "a symbolic variable's domain is a set such as `{W1, W2}`",
                );
                return;
            };
            let ty = s.sym[id.index()].ty;
            let mut objs: Vec<ObjectId> = Vec::new();
            for v in values {
                let ve = Expr {
                    kind: ExprKind::Name(v.name.clone()),
                    span: v.span,
                };
                if let Some(Term::Obj(o)) = s.sym_term(ctx, &ve, Some(ty), false) {
                    objs.push(o);
                }
            }
            if objs.len() == values.len() {
                task.bindings.push(Binding::In(id, objs));
            }
        }
        (ExprKind::Var(v), None) => ctx.err(e.span, format!("unknown variable `?{v}`")),
        _ => ctx.err(
            e.span,
            "expected a `?variable` or a duration `(t2 - t1)` of two timepoints before `in`",
        ),
    }
}

/// `contingent` before the task's whole duration (`(et - st) in [..]` or `?d = et - st`) marks it
/// decided by the world; any other statement is refused.
fn contingent(ctx: &mut Ctx<'_>, s: &Scope<'_>, task: &mut Task, inner: &Stmt, span: Span) {
    let whole = Some((task.start, task.end));
    let ok = match inner {
        Stmt::In { lhs, .. } => lhs.len() == 1 && s.tp_diff(&lhs[0]) == whole,
        Stmt::Rel {
            op: RelOp::Eq, rhs, ..
        } => s.tp_diff(rhs) == whole,
        _ => false,
    };
    if !ok {
        let (st, et) = (task.timepoints.first(), task.timepoints.last());
        let (st, et) = (
            st.map_or("st", |t| t.as_str()),
            et.map_or("et", |t| t.as_str()),
        );
        ctx.err(
            span,
            format!(
                "only the task's whole duration can be contingent: `contingent ({et} - {st}) in [a, b];` or `contingent ?d = {et} - {st};`"
            ),
        );
    } else if task.contingent {
        ctx.err(span, "the task's duration is already marked contingent");
    } else {
        task.contingent = true;
    }
}

fn is_symbolic(s: &Scope<'_>, e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Var(v) => matches!(s.vars.get(v), Some(Var::Sym(_))),
        ExprKind::Name(n) => s.domain.object_id(n).is_some(),
        _ => false,
    }
}

fn relation(
    ctx: &mut Ctx<'_>,
    s: &Scope<'_>,
    task: &mut Task,
    lhs: &Expr,
    op: RelOp,
    rhs: &Expr,
    span: Span,
) {
    if is_symbolic(s, lhs) || is_symbolic(s, rhs) {
        let eq = match op {
            RelOp::Eq => true,
            RelOp::Ne => false,
            _ => {
                ctx.err(span, "symbolic values are compared with `=` or `!=`");
                return;
            }
        };
        let a = s.sym_term(ctx, lhs, None, false);
        let b = s.sym_term(ctx, rhs, None, false);
        let (Some(a), Some(b)) = (a, b) else { return };
        if s.term_type(a) != s.term_type(b) {
            ctx.err(span, "compares values of different types");
            return;
        }
        let contradictory = match (a, b) {
            (Term::Obj(x), Term::Obj(y)) => (x == y) != eq,
            (x, y) => x == y && !eq,
        };
        if contradictory {
            ctx.err(span, "contradictory binding constraint: it can never hold");
            return;
        }
        task.bindings.push(if eq {
            Binding::Eq(a, b)
        } else {
            Binding::Ne(a, b)
        });
        return;
    }
    if s.tp_diff(lhs).is_some() {
        ctx.err(
            span,
            "constrain a duration with an interval: `(et - st) in [a, b]`",
        );
        return;
    }
    match op {
        RelOp::Eq => {
            let var = match s.num_term(ctx, lhs) {
                Some(NumTerm::Var(var)) => var,
                Some(NumTerm::Const(_)) => {
                    ctx.err(
                        lhs.span,
                        "the left side of a numeric `=` must be a numeric `?variable`",
                    );
                    return;
                }
                None => return,
            };
            numeric_definition(ctx, s, task, var, rhs);
        }
        RelOp::Le | RelOp::Ge => {
            let a = s.num_term(ctx, lhs);
            let b = s.num_term(ctx, rhs);
            if let (Some(a), Some(b)) = (a, b) {
                task.numeric.push(if op == RelOp::Le {
                    NumConstraint::Le(a, b)
                } else {
                    NumConstraint::Le(b, a)
                });
            }
        }
        RelOp::Lt | RelOp::Gt => ctx.err(
            span,
            "strict comparisons are not supported: use `<=` or `>=`",
        ),
        RelOp::Ne => ctx.err(span, "`!=` compares symbolic values, not numbers"),
    }
}

/// `?var = distance(a, b) | t2 - t1 | x * y | x + y | x`.
fn numeric_definition(
    ctx: &mut Ctx<'_>,
    s: &Scope<'_>,
    task: &mut Task,
    var: NumVarId,
    rhs: &Expr,
) {
    if let Some((from, to)) = s.tp_diff(rhs) {
        task.numeric.push(NumConstraint::Duration { var, from, to });
        return;
    }
    match &rhs.kind {
        ExprKind::Call(f, args) if f.name == "distance" => {
            if args.len() != 2 {
                ctx.err(rhs.span, format!("wrong number of arguments: `distance` takes 2, found {}", args.len()));
                return;
            }
            let a = s.sym_term(ctx, &args[0], None, false);
            let b = s.sym_term(ctx, &args[1], None, false);
            let (Some(a), Some(b)) = (a, b) else { return };
            for (t, e) in [(a, &args[0]), (b, &args[1])] {
                let ty = s.term_type(t);
                if ty.is_some_and(|ty| s.domain.ty(ty).kind != crate::model::TypeKind::Object) {
                    ctx.err(e.span, "distance() needs places: objects of a type declared without values (e.g. `type location;`)");
                    return;
                }
            }
            if s.term_type(a) != s.term_type(b) {
                ctx.err(rhs.span, "distance() between values of different types");
                return;
            }
            task.numeric.push(NumConstraint::Distance { var, a, b });
        }
        ExprKind::Call(f, _) => ctx.err(f.span, format!("unknown function `{}` (known: distance)", f.name)),
        ExprKind::Bin(op @ (BinOp::Mul | BinOp::Add), a, b) => {
            let a = s.num_term(ctx, a);
            let b = s.num_term(ctx, b);
            if let (Some(a), Some(b)) = (a, b) {
                task.numeric.push(if *op == BinOp::Mul {
                    NumConstraint::Product { var, a, b }
                } else {
                    NumConstraint::Sum { var, a, b }
                });
            }
        }
        ExprKind::Bin(_, a, b) if is_const(a) && is_const(b) => {
            if let Some(c) = eval::num(ctx, rhs, false) {
                task.numeric.push(NumConstraint::Equal(NumTerm::Var(var), NumTerm::Const(c)));
            }
        }
        ExprKind::Bin(..) => ctx.err(
            rhs.span,
            "supported numeric forms: `?x = distance(?a, ?b)`, `?x = t2 - t1`, `?x = a * b`, `?x = a + b`, `?x = a`",
        ),
        _ => {
            if let Some(t) = s.num_term(ctx, rhs) {
                task.numeric.push(NumConstraint::Equal(NumTerm::Var(var), t));
            }
        }
    }
}

/// Constant numeric constraints that can never hold, once every domain is known (declarations may follow
/// their uses): `?x = c` with `c` outside the domain of `?x`, `a <= b` between constants with `a > b`;
/// and a duration defined as a quotient (`?dist = ?speed * ?duration`) by a factor that may be 0 or is
/// unbounded, for which the planner finds durations near 0 that its checker then refuses.
fn numeric_contradictions(ctx: &mut Ctx<'_>, s: &Scope<'_>, cs: &[NumConstraint], spans: &[Span]) {
    let durations: Vec<NumVarId> = cs
        .iter()
        .filter_map(|c| match c {
            NumConstraint::Duration { var, .. } => Some(*var),
            _ => None,
        })
        .collect();
    for (c, span) in cs.iter().zip(spans) {
        let NumConstraint::Product { a, b, .. } = c else {
            continue;
        };
        let factor = match (a, b) {
            (NumTerm::Var(d), f) | (f, NumTerm::Var(d)) if durations.contains(d) => f,
            _ => continue,
        };
        let (name, domain) = match factor {
            NumTerm::Var(v) => match s.num.get(v.index()) {
                Some(v) => (format!("`?{}`", v.name), v.domain),
                None => continue,
            },
            NumTerm::Const(k) => (k.to_string(), NumInterval::closed(*k, *k)),
        };
        let unbounded = matches!(domain.lb, Bound::Inf) || matches!(domain.ub, Bound::Inf);
        if unbounded || domain.contains(0.0) {
            ctx.err(
                *span,
                format!(
                    "{name} divides the duration here, so its domain must be bounded and exclude 0 (e.g. `[0.3, 1.5]`), found {}",
                    crate::model::show_bounds(&domain.lb, &domain.ub)
                ),
            );
        }
    }
    for (c, span) in cs.iter().zip(spans) {
        let bad = match *c {
            NumConstraint::Equal(NumTerm::Var(v), NumTerm::Const(k))
            | NumConstraint::Equal(NumTerm::Const(k), NumTerm::Var(v)) => {
                s.num.get(v.index()).is_some_and(|v| !v.domain.contains(k))
            }
            NumConstraint::Equal(NumTerm::Const(a), NumTerm::Const(b)) => a != b,
            NumConstraint::Le(NumTerm::Const(a), NumTerm::Const(b)) => a > b,
            _ => false,
        };
        if bad {
            ctx.err(
                *span,
                "contradictory numeric constraint: it can never hold with the declared domains",
            );
        }
    }
}

fn is_const(e: &Expr) -> bool {
    match &e.kind {
        ExprKind::Num(..) => true,
        ExprKind::Neg(i) => is_const(i),
        ExprKind::Bin(_, a, b) => is_const(a) && is_const(b),
        _ => false,
    }
}

/// A tiny all-pairs STN over one task's timepoints, to reject contradictory durations at load time.
struct TaskStn {
    n: usize,
    /// d[i][j] = max of (t_j - t_i), in ms; None = +oo.
    d: Vec<Vec<Option<Time>>>,
}

impl TaskStn {
    fn new(n: usize) -> Self {
        let mut d = vec![vec![None; n]; n];
        for (i, row) in d.iter_mut().enumerate() {
            row[i] = Some(0);
        }
        TaskStn { n, d }
    }

    /// Adds `to - from in iv`; false if the network becomes inconsistent.
    fn add(&mut self, from: TpId, to: TpId, iv: TimeInterval) -> bool {
        let (f, t) = (from.index(), to.index());
        if f >= self.n || t >= self.n {
            return true;
        }
        if let Some(ub) = iv.max_ms() {
            self.tighten(f, t, ub);
        }
        if let Some(lb) = iv.min_ms() {
            self.tighten(t, f, lb.saturating_neg());
        }
        // Floyd–Warshall: n is a handful of timepoints.
        for k in 0..self.n {
            for i in 0..self.n {
                for j in 0..self.n {
                    if let (Some(a), Some(b)) = (self.d[i][k], self.d[k][j]) {
                        self.tighten(i, j, a.saturating_add(b));
                    }
                }
            }
        }
        (0..self.n).all(|i| self.d[i][i].is_none_or(|v| v >= 0))
    }

    fn tighten(&mut self, i: usize, j: usize, v: Time) {
        if self.d[i][j].is_none_or(|old| v < old) {
            self.d[i][j] = Some(v);
        }
    }
}
