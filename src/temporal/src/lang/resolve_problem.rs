//! Problem semantic checks: syntax tree → [`Problem`] over a resolved [`Domain`].

use std::collections::HashMap;

use crate::model::{
    combinations, AttrId, Bound, DefaultFact, Domain, Fact, Goal, GoalOrigin, NumConstraint,
    Object, ObjectId, Problem, ResourceKind, Term, Time, TimeInterval, TypeId, Value,
};

use super::ast::{
    AttrRef, Expr, ExprKind, GoalAst, Ident, InSet, ProblemAst, ProblemItem, RelOp, Stmt, UsageStmt,
};
use super::diag::Span;
use super::eval::{self, Clock, Ctx, TimeVal};
use super::resolve_domain::{geo, logical_attr, object_type, position, Names};

/// A finite, non-negative time, or a reported error.
fn date(ctx: &mut Ctx<'_>, e: &Expr, clock: Clock) -> Option<Time> {
    match eval::time(ctx, e, clock)? {
        TimeVal::Ms(v) if v >= 0 => Some(v),
        TimeVal::Ms(_) => {
            ctx.err(e.span, "a date cannot be before the problem's origin");
            None
        }
        _ => {
            ctx.err(e.span, "expected a finite time");
            None
        }
    }
}

pub fn resolve(ctx: &mut Ctx<'_>, domain: &Domain, ast: &ProblemAst) -> Problem {
    if ast.domain.name != domain.name {
        ctx.err(
            ast.domain.span,
            format!(
                "this problem is for domain `{}`, but it is checked against domain `{}`",
                ast.domain.name, domain.name
            ),
        );
    }
    // Header items first: they fix how clock times and goal windows are read.
    let mut start_clock = None;
    let mut horizon = None;
    let mut home = None;
    let mut seen: HashMap<&str, Span> = HashMap::new();
    for item in &ast.items {
        let (key, span) = match item {
            ProblemItem::Start(e) => ("start", e.span),
            ProblemItem::Horizon(e) => ("horizon", e.span),
            ProblemItem::Home { span, .. } => ("home", *span),
            _ => continue,
        };
        if seen.insert(key, span).is_some() {
            ctx.err(span, format!("`{key}` is given twice"));
        }
    }
    for item in &ast.items {
        if let ProblemItem::Start(e) = item {
            match e.kind {
                ExprKind::Clock(ms) => start_clock = Some(ms),
                _ => ctx.err(e.span, "expected a clock time such as `08:00`"),
            }
        }
    }
    let clock = Clock(Some(start_clock.unwrap_or(0)));
    for item in &ast.items {
        match item {
            ProblemItem::Horizon(e) => {
                super::lint::unit_less_time(ctx, e, "horizon");
                horizon = date(ctx, e, clock);
                if horizon == Some(0) {
                    ctx.err(e.span, "the horizon must be after the origin");
                }
            }
            ProblemItem::Home { lat, lon, alt, .. } => home = geo(ctx, lat, lon, alt.as_ref()),
            _ => {}
        }
    }
    let horizon_v = horizon.unwrap_or_else(|| {
        if !seen.contains_key("horizon") {
            ctx.err(
                ast.name.span,
                "a problem needs a `horizon` (e.g. `horizon 30min;` or `horizon 20:00;`)",
            );
        }
        0
    });
    let mut p = Problem::new(ast.name.name.clone(), domain, horizon_v);
    p.start_clock = start_clock;
    p.home = home;
    let mut object_spans: HashMap<ObjectId, Span> = HashMap::new();
    objects(ctx, domain, &mut p, ast, &mut object_spans);
    geo_without_home(ctx, &p, &object_spans);
    check_positions(ctx, domain, &p, &object_spans);
    for item in &ast.items {
        if let ProblemItem::Resource { name, items } = item {
            resource(ctx, domain, &mut p, name, items, clock);
        }
    }
    initial(ctx, domain, &mut p, ast, clock);
    super::lint::missing_initial_values(ctx, domain, &p, ast.name.span);
    let mut goal_names = Names::default();
    for item in &ast.items {
        if let ProblemItem::Goal(g) = item {
            if !goal_names.declare(ctx, &g.name, "goal") {
                continue;
            }
            if let Some(goal) = goal(ctx, domain, &p, g) {
                p.goals.push(goal);
            }
        }
    }
    p
}

fn objects(
    ctx: &mut Ctx<'_>,
    domain: &Domain,
    p: &mut Problem,
    ast: &ProblemAst,
    spans: &mut HashMap<ObjectId, Span>,
) {
    let mut names = Names::default();
    for item in &ast.items {
        let ProblemItem::Object {
            names: ns,
            ty,
            position: pos,
        } = item
        else {
            continue;
        };
        let Some(t) = object_type(ctx, domain, ty, "fixed by the domain") else {
            continue;
        };
        let position = pos.as_ref().and_then(|x| position(ctx, x));
        for n in ns {
            if domain.object_id(&n.name).is_some() {
                ctx.err(
                    n.span,
                    format!("`{}` is already a constant of the domain", n.name),
                );
                continue;
            }
            if names.declare(ctx, n, "object") {
                let id = p.add_object(Object {
                    name: n.name.clone(),
                    ty: t,
                    position,
                });
                spans.insert(id, n.span);
            }
        }
    }
}

/// Places by latitude and longitude beside places in metres need the `home` the metres are from: without
/// one, a geographic place is taken to be at (0, 0) of the others.
fn geo_without_home(ctx: &mut Ctx<'_>, p: &Problem, spans: &HashMap<ObjectId, Span>) {
    use crate::model::Position;
    if p.home.is_some()
        || !p
            .objects
            .iter()
            .any(|o| matches!(o.position, Some(Position::Local { .. })))
    {
        return;
    }
    for (i, o) in p.objects.iter().enumerate() {
        if let (Some(Position::Geo(_)), Some(span)) =
            (o.position, spans.get(&ObjectId::from_index(i)))
        {
            ctx.warn(
                *span,
                format!(
                    "`{}` is placed by latitude and longitude, the other places in metres, and the problem has no `home`: it is taken to be at (0, 0); add `home lat .. lon ..;`",
                    o.name
                ),
            );
        }
    }
}

/// Every object of a type used in some task's `distance()` needs coordinates.
fn check_positions(
    ctx: &mut Ctx<'_>,
    domain: &Domain,
    p: &Problem,
    spans: &HashMap<ObjectId, Span>,
) {
    let mut placed: Vec<(TypeId, &str)> = Vec::new();
    for task in &domain.tasks {
        for c in &task.numeric {
            if let NumConstraint::Distance { a, b, .. } = c {
                for t in [a, b] {
                    let ty = match *t {
                        Term::Var(v) => task.sym_vars.get(v.index()).map(|v| v.ty),
                        Term::Obj(o) => domain.objects.get(o.index()).map(|o| o.ty),
                        Term::Unknown => None,
                    };
                    if let Some(ty) = ty {
                        if !placed.iter().any(|(x, _)| *x == ty) {
                            placed.push((ty, task.name.as_str()));
                        }
                    }
                }
            }
        }
    }
    for (i, o) in p.objects.iter().enumerate() {
        let id = ObjectId::from_index(i);
        if let (Some((_, task)), None, Some(span)) = (
            placed.iter().find(|(t, _)| *t == o.ty),
            o.position,
            spans.get(&id),
        ) {
            ctx.err(
                *span,
                format!(
                    "`{}` needs a position (`at (east, north)` or `at lat .. lon ..`): task `{task}` measures distances between {}s",
                    o.name,
                    domain.ty(o.ty).name
                ),
            );
        }
    }
}

fn resource(
    ctx: &mut Ctx<'_>,
    domain: &Domain,
    p: &mut Problem,
    name: &Ident,
    items: &[super::ast::ResourceItemAst],
    clock: Clock,
) {
    let Some(r) = domain.resource_id(&name.name) else {
        ctx.err(name.span, format!("unknown resource `{}`", name.name));
        return;
    };
    let kind = domain.resource(r).kind;
    let mut level = None;
    let mut steps: Vec<(Time, f64, Span)> = Vec::new();
    for it in items {
        let Some(v) = eval::num(ctx, &it.value, false) else {
            continue;
        };
        match it.key.name.as_str() {
            "level" => {
                if it.from.is_some() {
                    ctx.err(
                        it.key.span,
                        "`level` is the level at the origin; it takes no `from`",
                    );
                }
                level = Some((v, it.value.span));
            }
            "capacity" => {
                if kind == ResourceKind::Unary {
                    ctx.err(it.key.span, "a unary resource has capacity 1");
                    continue;
                }
                if v < 0.0 {
                    ctx.err(it.value.span, "a capacity cannot be negative");
                    continue;
                }
                let from = match &it.from {
                    Some(e) => date(ctx, e, clock),
                    None => Some(0),
                };
                if let Some(from) = from {
                    if steps.iter().any(|(t, _, _)| *t == from) {
                        ctx.err(it.value.span, "two capacities at the same time");
                        continue;
                    }
                    steps.push((from, v, it.value.span));
                }
            }
            other => ctx.err(
                it.key.span,
                format!("expected `level` or `capacity`, found `{other}`"),
            ),
        }
    }
    let Some(setup) = p.resources.get_mut(r.index()) else {
        return;
    };
    steps.sort_by_key(|(t, _, _)| *t);
    if !steps.is_empty() {
        if steps[0].0 != 0 {
            steps.insert(0, (0, domain.resource(r).capacity, name.span));
        }
        setup.profile = steps.iter().map(|(t, c, _)| (*t, *c)).collect();
        if level.is_none() {
            setup.level = steps[0].1;
        }
    }
    if let Some((l, span)) = level {
        let cap0 = setup.capacity_at(0);
        if l < 0.0 || l > cap0 {
            ctx.err(
                span,
                format!("level {l} is outside [0, {cap0}] (the capacity at the origin)"),
            );
        }
        setup.level = l;
    }
}

/// Ground arguments of `attr(args)`; `*` expands to every object of the parameter's type.
fn ground_instances(
    ctx: &mut Ctx<'_>,
    domain: &Domain,
    p: &Problem,
    a: &AttrRef,
    wildcard_ok: bool,
) -> Option<(AttrId, Vec<Vec<ObjectId>>, bool)> {
    let id = logical_attr(ctx, domain, a, "give its level in a `resource` line")?;
    let attr = domain.attr(id);
    let mut choices = Vec::new();
    let mut wild = false;
    for (e, (_, t)) in a.args.iter().zip(&attr.params) {
        choices.push(match &e.kind {
            ExprKind::Wildcard if wildcard_ok => {
                wild = true;
                p.objects_of(*t)
            }
            _ => vec![object(ctx, domain, p, e, *t)?],
        });
    }
    Some((id, combinations(&choices), wild))
}

/// An object of type `ty` named by `e`.
fn object(
    ctx: &mut Ctx<'_>,
    domain: &Domain,
    p: &Problem,
    e: &Expr,
    ty: TypeId,
) -> Option<ObjectId> {
    let ExprKind::Name(n) = &e.kind else {
        let msg = match e.kind {
            ExprKind::Var(_) => {
                "goals and initial values are ground: use an object, not a `?variable`"
            }
            ExprKind::PosInf => "`+oo` can be a value but not an argument",
            ExprKind::Wildcard => "`*` is only allowed in `initial` arguments",
            _ => "expected an object name",
        };
        ctx.err(e.span, msg);
        return None;
    };
    let Some(o) = p.object_id(n) else {
        let hint = super::lint::did_you_mean(n, p.objects.iter().map(|o| o.name.as_str()));
        ctx.err(e.span, format!("unknown object `{n}`{hint}"));
        return None;
    };
    let have = p.objects[o.index()].ty;
    if have != ty {
        ctx.err(
            e.span,
            format!(
                "value outside its domain: expected a {}, `{n}` is a {}",
                domain.ty(ty).name,
                domain.ty(have).name
            ),
        );
        return None;
    }
    Some(o)
}

/// A ground value of type `ty`, or `+oo`.
fn value(ctx: &mut Ctx<'_>, domain: &Domain, p: &Problem, e: &Expr, ty: TypeId) -> Option<Value> {
    if e.kind == ExprKind::PosInf {
        return Some(Value::Unknown);
    }
    object(ctx, domain, p, e, ty).map(Value::Obj)
}

fn initial(ctx: &mut Ctx<'_>, domain: &Domain, p: &mut Problem, ast: &ProblemAst, clock: Clock) {
    // (attr, args, time) -> (line of the assignment, from a wildcard?)
    let mut given: HashMap<(AttrId, Vec<ObjectId>, Time), (Span, bool)> = HashMap::new();
    let mut facts: Vec<(Time, Fact)> = Vec::new();
    for item in &ast.items {
        let ProblemItem::Initial(inits) = item else {
            continue;
        };
        for init in inits {
            let g = ground_instances(ctx, domain, p, &init.attr, true);
            let at = match &init.at {
                Some(e) => date(ctx, e, clock),
                None => Some(0),
            };
            let (Some((attr, instances, wild)), Some(at)) = (g, at) else {
                continue;
            };
            if at > p.horizon {
                if let Some(e) = &init.at {
                    ctx.err(e.span, "this change is predicted after the horizon");
                }
                continue;
            }
            let Some(v) = value(ctx, domain, p, &init.value, domain.attr(attr).value_type) else {
                continue;
            };
            if wild {
                let pattern = init
                    .attr
                    .args
                    .iter()
                    .map(|e| match &e.kind {
                        ExprKind::Name(n) => p.object_id(n),
                        _ => None,
                    })
                    .collect();
                p.defaults.push(DefaultFact {
                    at,
                    attr,
                    args: pattern,
                    value: v,
                });
            }
            for args in instances {
                let key = (attr, args.clone(), at);
                match given.get(&key) {
                    Some((prev, prev_wild)) if !*prev_wild || wild => {
                        let line = ctx.src.error(*prev, "").line;
                        ctx.err(
                            init.span,
                            format!("contradictory initial scenario: this value of `{}` at this time is already given (line {line})", domain.attr(attr).name),
                        );
                        break;
                    }
                    Some(_) => {
                        // A specific value overrides a wildcard default.
                        facts.retain(|(t, f)| !(*t == at && f.attr == attr && f.args == args));
                    }
                    None => {}
                }
                given.insert(key, (init.span, wild));
                facts.push((
                    at,
                    Fact {
                        attr,
                        args,
                        value: v,
                    },
                ));
            }
        }
    }
    p.add_facts(facts);
}

/// Resolves a goal declaration against a problem (also used for goals sent at run time).
pub fn goal(ctx: &mut Ctx<'_>, domain: &Domain, p: &Problem, g: &GoalAst) -> Option<Goal> {
    let errors_before = ctx.diags.len();
    let clock = Clock(Some(p.start_clock.unwrap_or(0)));
    let kind = match g.kind.as_ref().map(|k| k.name.as_str()) {
        Some("internal") => GoalOrigin::Internal,
        _ => GoalOrigin::External,
    };
    let priority = match &g.priority {
        Some(e) => match eval::num(ctx, e, false) {
            Some(v) if v.fract() == 0.0 && v.abs() < 1e9 => v as i64,
            Some(_) => {
                ctx.err(e.span, "a priority is a whole number");
                0
            }
            None => 0,
        },
        None => 1,
    };
    let mut prop: Option<(AttrId, Vec<ObjectId>, Value, bool)> = None;
    let mut start_window: Option<TimeInterval> = None;
    let mut duration: Option<(TimeInterval, Span)> = None;
    let mut achieve = 0;
    let is_tp = |e: &Expr, name: &str| matches!(&e.kind, ExprKind::Name(n) if n == name);
    for st in &g.body {
        match st {
            Stmt::Hold {
                attr,
                value: v,
                from,
                to,
                span,
            } => {
                if prop.is_some() {
                    ctx.err(
                        *span,
                        "a goal has exactly one `hold` (declare several goals instead)",
                    );
                    continue;
                }
                if from.name != "st" || to.as_ref().is_some_and(|t| t.name != "et") {
                    ctx.err(from.span, "a goal holds over `(st, et)` (or at `st`)");
                    continue;
                }
                let Some((a, mut inst, _)) = ground_instances(ctx, domain, p, attr, false) else {
                    continue;
                };
                let Some(val) = value(ctx, domain, p, v, domain.attr(a).value_type) else {
                    continue;
                };
                if val == Value::Unknown {
                    ctx.err(v.span, "a goal value must be a constant, not `+oo`");
                    continue;
                }
                prop = Some((a, inst.pop().unwrap_or_default(), val, to.is_none()));
            }
            Stmt::In {
                lhs,
                set: InSet::Interval(i),
                span,
            } if lhs.len() == 1 => {
                let e = &lhs[0];
                let diff = matches!(&e.kind, ExprKind::Bin(super::ast::BinOp::Sub, a, b) if is_tp(a, "et") && is_tp(b, "st"));
                if is_tp(e, "st") {
                    start_window = eval::time_interval(ctx, i, clock).or(Some(TimeInterval::ANY));
                } else if diff {
                    if let Some(iv) = eval::time_interval(ctx, i, Clock(None)) {
                        duration = Some((iv, *span));
                    }
                } else {
                    ctx.err(e.span, "a goal constrains `st in [..]` (its start window I^g) or `(et - st) in [..]` (its duration I^d)");
                }
            }
            Stmt::Achieve(e, _) => {
                if let Some(TimeVal::Ms(v)) = eval::time(ctx, e, Clock(None)) {
                    if v < 0 {
                        ctx.err(e.span, "d_achiev cannot be negative");
                    }
                    achieve = v;
                }
            }
            Stmt::In { span, .. }
            | Stmt::Rel { span, .. }
            | Stmt::Event { span, .. }
            | Stmt::Usage(UsageStmt { span, .. }) => {
                let hint = match st {
                    Stmt::Rel { op: RelOp::Eq, .. } => {
                        " (write `hold(attr(args): value, (st, et));`)"
                    }
                    _ => "",
                };
                ctx.err(*span, format!("a goal contains `hold(...)`, `st in [..]`, `(et - st) in [..]` and `achieve ..;`{hint}"));
            }
            Stmt::Contingent(_, span) => ctx.err(
                *span,
                "`contingent` marks a task's duration (the world decides it), not a goal's",
            ),
            Stmt::Variables(vs) => {
                if let Some((v, _)) = vs.first() {
                    ctx.err(v.span, "goals are ground: no variables");
                }
            }
        }
    }
    let Some((attr, args, value, instant)) = prop else {
        if ctx.diags.len() == errors_before {
            ctx.err(
                g.name.span,
                "a goal needs a proposition: `hold(attr(args): value, (st, et));`",
            );
        }
        return None;
    };
    let duration = match (instant, duration) {
        (true, Some((_, span))) => {
            ctx.err(
                span,
                "this goal holds at the instant `st`: it has no duration",
            );
            TimeInterval::exactly(0)
        }
        (_, Some((iv, span))) => {
            if iv.max_ms().is_some_and(|m| m < 0) {
                ctx.err(span, "a goal's duration cannot be negative");
            }
            iv
        }
        (_, None) => TimeInterval::exactly(0),
    };
    let horizon = TimeInterval::closed(0, p.horizon);
    let start_window = start_window.unwrap_or(horizon);
    let lo = start_window.min_ms().unwrap_or(0).max(0).max(achieve);
    let hi = start_window.max_ms().unwrap_or(p.horizon).min(p.horizon);
    if lo > hi {
        ctx.err(
            g.name.span,
            "this goal can never start: its start window (after d_achiev) lies outside [origin, horizon]",
        );
    }
    // I^g within [origin, horizon]: a goal cannot start before the origin nor after the horizon.
    let start_window = TimeInterval {
        lb: match start_window.lb {
            Bound::Closed(v) | Bound::Open(v) if v >= 0 => start_window.lb,
            _ => Bound::Closed(0),
        },
        ub: match start_window.ub {
            Bound::Closed(v) | Bound::Open(v) if v <= p.horizon => start_window.ub,
            _ => Bound::Closed(p.horizon),
        },
    };
    (ctx.diags.len() == errors_before).then(|| Goal {
        name: g.name.name.clone(),
        kind,
        priority,
        attr,
        args,
        value,
        start_window,
        duration,
        achieve,
    })
}
