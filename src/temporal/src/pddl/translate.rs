//! From the PDDL syntax trees to the [`crate::model`] the planner works on: types, objects, predicates as
//! timelines (mutex groups as multi-valued state variables, the rest as boolean ones), actions as tasks
//! ([`super::task`]), the initial state, timed initial literals (exogenous changes) and goals. What the
//! model cannot express is refused at its place in the file.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::sync::Arc;

use super::ast::{self, Arg, Atom, Effect, Init, Lit, NExpr};
use super::fluents;
use super::invariants::{self, Group};
use super::sexpr::Span;
use super::task;
use super::{PddlError, Src};
use crate::model::{
    AttrId, Domain, Fact, Goal, GoalOrigin, LogicalAttr, Object, ObjectId, Problem, ResourceAttr,
    ResourceId, ResourceKind, Term, Time, TimeInterval, TypeId, TypeKind, Value, MS_PER_S,
};

/// The horizon given to PDDL problems, which have none: every action ends before it (seconds).
pub const HORIZON_S: Time = 1_000_000;

/// Ground atoms of one boolean predicate beyond which the translation refuses (closed world: every false
/// instance of a fluent predicate is an initial fact of the model).
const MAX_GROUND_ATOMS: usize = 500_000;

/// A translated PDDL domain and problem.
#[derive(Debug, Clone)]
pub struct Translated {
    pub domain: Arc<Domain>,
    pub problem: Arc<Problem>,
    /// The multi-valued state variables recovered from predicates, e.g. `at(?x: rover) = waypoint`.
    pub multi_valued: Vec<String>,
    /// What was dropped or ignored (actions that can never apply, the metric).
    pub notes: Vec<String>,
    /// The reservoirs that stand for numeric fluents, and what each task does to them.
    pub fluents: fluents::Fluents,
}

/// How a predicate is represented.
#[derive(Debug, Clone)]
pub(super) enum PredRep {
    /// One boolean timeline per ground atom.
    Bool { attr: AttrId, fluent: bool },
    /// A lock: a predicate over one object per parameter, true initially, that every action using it
    /// requires and deletes at its start and adds back at its end (Rovers' `channel_free ?l` with one
    /// lander) — a unary resource each such action borrows over `[st, et]`.
    Lock { resource: ResourceId },
    /// A member of a mutex group: `attr(key) = value` (the value argument, or the member's constant).
    Group(GroupMember),
}

/// A predicate of a mutex group, as one value (or one value argument) of the group's attribute.
#[derive(Debug, Clone, Copy)]
pub(super) struct GroupMember {
    pub attr: AttrId,
    /// The position of the value argument (see [`Group::value_pos`]).
    pub value_pos: Option<usize>,
    /// The value the predicate stands for, when it has no value argument.
    pub member: Option<ObjectId>,
}

impl GroupMember {
    /// The key and value of a ground atom of this predicate.
    pub fn split_ground(&self, args: &[ObjectId]) -> (Vec<ObjectId>, Value) {
        let (key, value) =
            invariants::split_member(args.iter().copied(), self.value_pos, self.member);
        (key, value.map_or(Value::Unknown, Value::Obj))
    }

    /// The key and value of an atom of this predicate in a task (`+oo` for a missing value).
    pub fn split_terms(&self, args: &[Term]) -> (Vec<Term>, Term) {
        let (key, value) = invariants::split_member(
            args.iter().copied(),
            self.value_pos,
            self.member.map(Term::Obj),
        );
        (key, value.unwrap_or(Term::Unknown))
    }
}

/// What the task translation needs to know about the whole domain and problem.
pub(super) struct Cx<'a> {
    pub ds: &'a Src,
    pub ps: &'a Src,
    pub objs: HashMap<String, ObjectId>,
    /// The PDDL type of every object (domain constants and problem objects).
    pub obj_type: BTreeMap<ObjectId, String>,
    pub parent: HashMap<String, String>,
    pub flat: bool,
    pub type_ids: HashMap<String, TypeId>,
    pub preds: HashMap<String, (PredRep, Vec<ast::Typed>)>,
    /// True ground atoms at the origin, per predicate.
    pub init_true: HashMap<String, BTreeSet<Vec<ObjectId>>>,
    /// Static function values.
    pub values: HashMap<(String, Vec<ObjectId>), f64>,
    pub fluent_functions: BTreeSet<String>,
    pub functions: HashMap<String, usize>,
    /// Boolean predicates whose `false` instances some condition or goal asks for.
    pub needs_false: BTreeSet<String>,
    /// Functions actions change and something reads: reservoirs ([`super::fluents`]).
    pub numeric: BTreeSet<String>,
    /// Functions actions change and nothing but the metric reads: their effects are left out.
    pub metric_only: BTreeSet<String>,
    /// The ground instances of [`Cx::numeric`] with an initial value.
    pub instances: HashMap<fluents::Key, fluents::Instance>,
    /// The initial level of each of their reservoirs.
    pub fluent_initial: HashMap<ResourceId, f64>,
}

impl Cx<'_> {
    pub fn derr(&self, span: Span, msg: impl Into<String>) -> PddlError {
        self.ds.error(span.start, msg)
    }

    pub fn perr(&self, span: Span, msg: impl Into<String>) -> PddlError {
        self.ps.error(span.start, msg)
    }

    /// The root of a PDDL type (its ancestor just below `object`), or `object`.
    fn root<'s>(&'s self, t: &'s str) -> &'s str {
        let mut t = t;
        for _ in 0..=self.parent.len() {
            match self.parent.get(t) {
                Some(p) if p != "object" => t = p,
                _ => return t,
            }
        }
        t
    }

    /// Whether PDDL type `t` is `ancestor` or below it.
    pub fn is_sub(&self, t: &str, ancestor: &str) -> bool {
        if ancestor == "object" {
            return true;
        }
        let mut t = t;
        for _ in 0..=self.parent.len() {
            if t == ancestor {
                return true;
            }
            match self.parent.get(t) {
                Some(p) => t = p,
                None => return false,
            }
        }
        false
    }

    /// The model type of a (possibly `either`) PDDL type list.
    pub fn model_type(&self, types: &[ast::Name]) -> TypeId {
        let name = if self.flat {
            "object"
        } else {
            types.first().map_or("object", |t| self.root(&t.name))
        };
        self.type_ids.get(name).copied().unwrap_or(Domain::BOOL)
    }

    /// The objects a typed parameter may take.
    pub fn objects_of(&self, types: &[ast::Name]) -> Vec<ObjectId> {
        self.obj_type
            .iter()
            .filter(|(_, t)| types.iter().any(|a| self.is_sub(t, &a.name)))
            .map(|(o, _)| *o)
            .collect()
    }

    /// Whether the typed list restricts its model type (then a binding `?v in {...}` says which objects).
    pub fn restricts(&self, types: &[ast::Name]) -> bool {
        let ty = self.model_type(types);
        let all = self
            .obj_type
            .iter()
            .filter(|(_, t)| {
                let n = if self.flat { "object" } else { self.root(t) };
                self.type_ids.get(n) == Some(&ty)
            })
            .count();
        self.objects_of(types).len() != all
    }

    /// Evaluates a numeric expression of numbers and static functions; `arg` gives the object of an
    /// argument (`None`: a parameter not known here).
    pub fn eval(
        &self,
        e: &NExpr,
        src: &Src,
        arg: &dyn Fn(&Arg) -> Option<ObjectId>,
    ) -> Result<f64, PddlError> {
        match e {
            NExpr::Num(v, _) => Ok(*v),
            NExpr::Duration(s) => Err(src.error(s.start, "`?duration` cannot be used here")),
            NExpr::Neg(a, _) => Ok(-self.eval(a, src, arg)?),
            NExpr::Bin(op, a, b, _) => {
                let (x, y) = (self.eval(a, src, arg)?, self.eval(b, src, arg)?);
                Ok(match op {
                    '+' => x + y,
                    '-' => x - y,
                    '*' => x * y,
                    _ => x / y,
                })
            }
            NExpr::Fluent(f) => {
                if f.pred.name == "total-time" {
                    return Err(src.error(
                        f.span.start,
                        "`total-time` is only meaningful in the metric",
                    ));
                }
                let Some(&arity) = self.functions.get(&f.pred.name) else {
                    return Err(
                        src.error(f.span.start, format!("unknown function `{}`", f.pred.name))
                    );
                };
                if arity != f.args.len() {
                    return Err(src.error(
                        f.span.start,
                        format!("`{}` takes {arity} arguments", f.pred.name),
                    ));
                }
                if self.fluent_functions.contains(&f.pred.name) {
                    return Err(src.error(f.span.start, format!("`{}` is a numeric fluent changed by actions: the translation supports static functions only here", f.pred.name)));
                }
                let mut args = Vec::new();
                for a in &f.args {
                    match arg(a) {
                        Some(o) => args.push(o),
                        None => return Err(src.error(f.span.start, format!("this value of `{}` depends on the action's parameters: the model's durations and levels are fixed per task, not tables over its parameters", f.pred.name))),
                    }
                }
                self.values
                    .get(&(f.pred.name.clone(), args))
                    .copied()
                    .ok_or_else(|| {
                        src.error(
                            f.span.start,
                            format!(
                                "`{}` has no value for these arguments in the problem",
                                f.pred.name
                            ),
                        )
                    })
            }
        }
    }

    /// The object named by a constant argument.
    pub fn constant(&self, n: &ast::Name, src: &Src) -> Result<ObjectId, PddlError> {
        self.objs
            .get(&n.name)
            .copied()
            .ok_or_else(|| src.error(n.span.start, format!("unknown object `{}`", n.name)))
    }

    /// The objects of a ground atom of the problem file.
    pub fn ground(&self, a: &Atom) -> Result<Vec<ObjectId>, PddlError> {
        a.args
            .iter()
            .map(|x| self.constant(x.name(), self.ps))
            .collect()
    }

    /// The representation and declared parameters of the predicate of `a`, arity checked.
    pub fn pred(&self, a: &Atom, src: &Src) -> Result<&(PredRep, Vec<ast::Typed>), PddlError> {
        let Some(p) = self.preds.get(&a.pred.name) else {
            return Err(src.error(a.span.start, format!("unknown predicate `{}`", a.pred.name)));
        };
        if p.1.len() != a.args.len() {
            return Err(src.error(
                a.span.start,
                format!(
                    "`{}` takes {} arguments, not {}",
                    a.pred.name,
                    p.1.len(),
                    a.args.len()
                ),
            ));
        }
        Ok(p)
    }
}

/// Translates a parsed domain and problem (`ds`, `ps`: their texts, for messages).
pub fn translate(
    ds: &Src,
    d: &ast::Domain,
    ps: &Src,
    p: &ast::Problem,
) -> Result<Translated, PddlError> {
    if p.domain.name != d.name.name {
        return Err(ps.error(
            p.domain.span.start,
            format!(
                "this problem is for domain `{}`, not `{}`",
                p.domain.name, d.name.name
            ),
        ));
    }
    let mut cx = Cx {
        ds,
        ps,
        objs: HashMap::new(),
        obj_type: BTreeMap::new(),
        parent: HashMap::new(),
        flat: false,
        type_ids: HashMap::new(),
        preds: HashMap::new(),
        init_true: HashMap::new(),
        values: HashMap::new(),
        fluent_functions: BTreeSet::new(),
        functions: HashMap::new(),
        needs_false: BTreeSet::new(),
        numeric: BTreeSet::new(),
        metric_only: BTreeSet::new(),
        instances: HashMap::new(),
        fluent_initial: HashMap::new(),
    };
    let mut model = Domain::new(d.name.name.clone());
    model.source = Some(ds.file.clone());
    types(&mut cx, &mut model, d, p)?;
    for c in &d.constants {
        add_object(&mut cx, &mut model.objects.len(), c, ds)?;
        let ty = cx.model_type(&c.types);
        model.add_object(Object {
            name: c.name.name.clone(),
            ty,
            position: None,
        });
    }
    // Problem objects are numbered after every domain object; their ids are fixed once the domain's
    // enumeration members are known (below).
    let fluent = fluent_predicates(d, p);
    let locks: BTreeSet<String> = d
        .predicates
        .iter()
        .filter(|(n, ps)| fluent.contains(&n.name) && is_lock(&cx, d, p, &n.name, ps))
        .map(|(n, _)| n.name.clone())
        .collect();
    let groupable: BTreeSet<String> = fluent.difference(&locks).cloned().collect();
    let groups = invariants::groups(d, p, &groupable);
    let mut multi_valued = Vec::new();
    let mut grouped: HashMap<String, (usize, Option<ObjectId>)> = HashMap::new();
    let mut group_attrs = Vec::new();
    for (gi, g) in groups.iter().enumerate() {
        let (attr, desc) = group_attr(&mut cx, &mut model, d, g, &mut grouped, gi)?;
        group_attrs.push(attr);
        multi_valued.push(desc);
    }
    let base = model.objects.len();
    let mut next = base;
    for o in &p.objects {
        if cx.objs.contains_key(&o.name.name) {
            return Err(ps.error(
                o.name.span.start,
                format!("`{}` is declared twice", o.name.name),
            ));
        }
        add_object(&mut cx, &mut next, o, ps)?;
    }
    predicates(
        &mut cx,
        &mut model,
        &locks,
        d,
        &fluent,
        &groups,
        &grouped,
        &group_attrs,
    )?;
    functions(&mut cx, d, p)?;
    let mut notes = fluents::analyse(&mut cx, d, p, &mut model)?;
    let mut numeric_tasks = Vec::new();
    let mut seen: BTreeSet<&str> = BTreeSet::new();
    for a in &d.actions {
        if !seen.insert(&a.name.name) {
            return Err(ds.error(
                a.name.span.start,
                format!("action `{}` is declared twice", a.name.name),
            ));
        }
        match task::tasks(&mut cx, a)? {
            Ok(ts) => {
                for (t, n) in ts {
                    model.add_task(t);
                    numeric_tasks.push(n);
                }
            }
            Err(why) => notes.push(format!("action `{}` dropped: {why}", a.name.name)),
        }
    }
    if let Some(m) = &p.metric {
        let is_time = matches!(&m.expr, NExpr::Fluent(f) if f.pred.name == "total-time");
        notes.push(if is_time && m.minimize {
            "metric minimize total-time: the plan is not optimised, its actions start at the earliest".into()
        } else {
            "metric ignored: the planner does not optimise it".into()
        });
    }
    let model = Arc::new(model);
    let problem = problem(&cx, &model, p, base)?;
    Ok(Translated {
        domain: model,
        problem: Arc::new(problem),
        multi_valued,
        notes,
        fluents: fluents::Fluents {
            initial: cx.fluent_initial.clone(),
            tasks: numeric_tasks,
        },
    })
}

fn types(
    cx: &mut Cx,
    model: &mut Domain,
    d: &ast::Domain,
    p: &ast::Problem,
) -> Result<(), PddlError> {
    for (child, parent) in &d.types {
        if child.name == "object" {
            continue;
        }
        cx.parent.insert(child.name.clone(), parent.name.clone());
    }
    // A supertype used without being declared (crew planning's `objects`) is a type of its own directly
    // below the implicit root `object`, as the other PDDL readers take it.
    for (_, parent) in &d.types {
        if parent.name != "object" && !cx.parent.contains_key(&parent.name) {
            cx.parent.insert(parent.name.clone(), "object".into());
        }
    }
    for (child, _) in &d.types {
        if cx.root(&child.name) != "object"
            && cx
                .parent
                .get(cx.root(&child.name))
                .is_some_and(|x| x != "object")
        {
            return Err(cx.derr(
                child.span,
                format!("type `{}` is its own ancestor", child.name),
            ));
        }
    }
    let known = |n: &ast::Name| n.name == "object" || cx.parent.contains_key(&n.name);
    let mut all_typed: Vec<(&ast::Typed, &Src)> = Vec::new();
    all_typed.extend(d.constants.iter().map(|t| (t, cx.ds)));
    all_typed.extend(p.objects.iter().map(|t| (t, cx.ps)));
    all_typed.extend(
        d.predicates
            .iter()
            .flat_map(|(_, ps)| ps.iter())
            .map(|t| (t, cx.ds)),
    );
    all_typed.extend(
        d.functions
            .iter()
            .flat_map(|(_, ps)| ps.iter())
            .map(|t| (t, cx.ds)),
    );
    all_typed.extend(
        d.actions
            .iter()
            .flat_map(|a| a.params.iter())
            .map(|t| (t, cx.ds)),
    );
    let mut flat = false;
    for (t, src) in &all_typed {
        for n in &t.types {
            if !known(n) {
                return Err(src.error(n.span.start, format!("unknown type `{}`", n.name)));
            }
        }
        flat |= t.types.len() > 1 || t.types.iter().any(|n| n.name == "object");
    }
    cx.flat = flat;
    let roots: BTreeSet<String> = if flat {
        std::iter::once("object".to_string()).collect()
    } else {
        cx.parent.keys().map(|t| cx.root(t).to_string()).collect()
    };
    for r in roots {
        let id = model.add_type(&r, TypeKind::Object);
        cx.type_ids.insert(r, id);
    }
    Ok(())
}

/// Records object `o` under id `*next` (then advanced).
fn add_object(cx: &mut Cx, next: &mut usize, o: &ast::Typed, src: &Src) -> Result<(), PddlError> {
    if o.types.len() != 1 {
        return Err(src.error(
            o.name.span.start,
            "an object has one type, not `(either ...)`",
        ));
    }
    if cx.objs.contains_key(&o.name.name) {
        return Err(src.error(
            o.name.span.start,
            format!("`{}` is declared twice", o.name.name),
        ));
    }
    let id = ObjectId::from_index(*next);
    *next += 1;
    cx.objs.insert(o.name.name.clone(), id);
    cx.obj_type.insert(id, o.types[0].name.clone());
    Ok(())
}

/// Predicates some action's effect or some timed initial literal changes.
fn fluent_predicates(d: &ast::Domain, p: &ast::Problem) -> BTreeSet<String> {
    let mut out: BTreeSet<String> = d
        .actions
        .iter()
        .flat_map(|a| a.effects.iter())
        .filter_map(|(_, e)| match e {
            Effect::Add(a) | Effect::Del(a) => Some(a.pred.name.clone()),
            Effect::Num(..) => None,
        })
        .collect();
    for i in &p.init {
        match i {
            Init::Atom(a, Some(_)) | Init::NotAtom(a, _) => {
                out.insert(a.pred.name.clone());
            }
            _ => {}
        }
    }
    out
}

/// The attribute of a mutex group, and its description.
fn group_attr(
    cx: &mut Cx,
    model: &mut Domain,
    d: &ast::Domain,
    g: &Group,
    grouped: &mut HashMap<String, (usize, Option<ObjectId>)>,
    gi: usize,
) -> Result<(AttrId, String), PddlError> {
    let decl = |name: &str| d.predicates.iter().find(|(n, _)| n.name == name);
    let Some((first, params)) = g.preds.first().and_then(|n| decl(n)) else {
        return Err(cx.derr(d.name.span, "internal: a mutex group without predicates"));
    };
    let key: Vec<(String, TypeId)> = params
        .iter()
        .enumerate()
        .filter(|(i, _)| Some(*i) != g.value_pos)
        .map(|(_, t)| {
            (
                t.name.name.trim_start_matches('?').to_string(),
                cx.model_type(&t.types),
            )
        })
        .collect();
    let (value_type, name, members) = match g.value_pos {
        Some(v) => {
            let ty = params
                .get(v)
                .map_or(Domain::BOOL, |t| cx.model_type(&t.types));
            (ty, first.name.clone(), vec![None])
        }
        None => {
            let tname = format!("{}-state", g.preds.join("-"));
            let ty = model.add_type(&tname, TypeKind::Enum);
            let mut members = Vec::new();
            for p in &g.preds {
                let mut m = p.clone();
                while cx.objs.contains_key(&m) || model.object_id(&m).is_some() {
                    m.push_str("-value");
                }
                let id = model.add_enum_member(ty, &m);
                members.push(Some(id));
            }
            (ty, g.preds.join("/"), members)
        }
    };
    let attr = model.add_attr(LogicalAttr {
        name: name.clone(),
        params: key.clone(),
        value_type,
        line: Some(srctext::locate(&cx.ds.file, &cx.ds.text, first.span.start, "").line),
    });
    for (p, m) in g.preds.iter().zip(members) {
        grouped.insert(p.clone(), (gi, m));
    }
    let keys: Vec<String> = key
        .iter()
        .map(|(n, t)| format!("?{n}: {}", model.ty(*t).name))
        .collect();
    Ok((
        attr,
        format!(
            "{name}({}) = {}",
            keys.join(", "),
            model.ty(value_type).name
        ),
    ))
}

#[allow(clippy::too_many_arguments)]
fn predicates(
    cx: &mut Cx,
    model: &mut Domain,
    locks: &BTreeSet<String>,
    d: &ast::Domain,
    fluent: &BTreeSet<String>,
    groups: &[Group],
    grouped: &HashMap<String, (usize, Option<ObjectId>)>,
    group_attrs: &[AttrId],
) -> Result<(), PddlError> {
    for (name, params) in &d.predicates {
        if cx.preds.contains_key(&name.name) {
            return Err(cx.derr(
                name.span,
                format!("predicate `{}` is declared twice", name.name),
            ));
        }
        let rep = match grouped.get(&name.name) {
            Some(&(gi, member)) => PredRep::Group(GroupMember {
                attr: group_attrs[gi],
                value_pos: groups[gi].value_pos,
                member,
            }),
            None if locks.contains(&name.name) => PredRep::Lock {
                resource: model.add_resource(ResourceAttr {
                    name: name.name.clone(),
                    kind: ResourceKind::Unary,
                    capacity: 1.0,
                    line: Some(srctext::locate(&cx.ds.file, &cx.ds.text, name.span.start, "").line),
                }),
            },
            None => {
                let attr = model.add_attr(LogicalAttr {
                    name: name.name.clone(),
                    params: params
                        .iter()
                        .map(|t| {
                            (
                                t.name.name.trim_start_matches('?').to_string(),
                                cx.model_type(&t.types),
                            )
                        })
                        .collect(),
                    value_type: Domain::BOOL,
                    line: Some(srctext::locate(&cx.ds.file, &cx.ds.text, name.span.start, "").line),
                });
                PredRep::Bool {
                    attr,
                    fluent: fluent.contains(&name.name),
                }
            }
        };
        cx.preds.insert(name.name.clone(), (rep, params.clone()));
    }
    Ok(())
}

fn functions(cx: &mut Cx, d: &ast::Domain, p: &ast::Problem) -> Result<(), PddlError> {
    for (n, ps) in &d.functions {
        cx.functions.insert(n.name.clone(), ps.len());
    }
    for a in &d.actions {
        for (_, e) in &a.effects {
            if let Effect::Num(_, f, _, _) = e {
                cx.fluent_functions.insert(f.pred.name.clone());
            }
        }
    }
    for i in &p.init {
        match i {
            Init::Value(f, v) => {
                let args = cx.ground(f)?;
                if !cx.functions.contains_key(&f.pred.name) {
                    return Err(cx.perr(f.span, format!("unknown function `{}`", f.pred.name)));
                }
                cx.values.insert((f.pred.name.clone(), args), *v);
            }
            Init::Atom(a, None) => {
                cx.pred(a, cx.ps)?;
                let args = cx.ground(a)?;
                cx.init_true
                    .entry(a.pred.name.clone())
                    .or_default()
                    .insert(args);
            }
            Init::Atom(a, Some(_)) | Init::NotAtom(a, _) => {
                cx.pred(a, cx.ps)?;
            }
        }
    }
    // Which boolean predicates need their false instances: negative conditions and goals.
    for a in &d.actions {
        for (_, l) in &a.conditions {
            if let Lit::Neg(x) = l {
                cx.needs_false.insert(x.pred.name.clone());
            }
        }
    }
    for l in &p.goal {
        if let Lit::Neg(x) = l {
            cx.needs_false.insert(x.pred.name.clone());
        }
    }
    Ok(())
}

/// Whether predicate `name` is a lock (see [`PredRep::Lock`]). Decided on names, before objects are
/// numbered (locks are kept out of the mutex groups).
fn is_lock(cx: &Cx, d: &ast::Domain, p: &ast::Problem, name: &str, params: &[ast::Typed]) -> bool {
    let mut ground: Vec<&str> = Vec::new();
    for t in params {
        let named: Vec<&str> = d
            .constants
            .iter()
            .chain(&p.objects)
            .filter(|o| {
                o.types
                    .iter()
                    .any(|ot| t.types.iter().any(|pt| cx.is_sub(&ot.name, &pt.name)))
            })
            .map(|o| o.name.name.as_str())
            .collect();
        match named.as_slice() {
            [o] => ground.push(o),
            _ => return false,
        }
    }
    let initially = p.init.iter().any(|i| match i {
        Init::Atom(a, None) if a.pred.name == name => {
            a.args.len() == ground.len()
                && a.args.iter().zip(&ground).all(|(x, o)| x.name().name == *o)
        }
        _ => false,
    });
    let timed = p
        .init
        .iter()
        .any(|i| matches!(i, Init::Atom(a, Some(_)) | Init::NotAtom(a, _) if a.pred.name == name));
    let in_goal = p
        .goal
        .iter()
        .any(|l| matches!(l, Lit::Pos(a) | Lit::Neg(a) if a.pred.name == name));
    if !initially || timed || in_goal {
        return false;
    }
    d.actions.iter().all(|a| {
        let conds: Vec<_> = a
            .conditions
            .iter()
            .filter(|(_, l)| matches!(l, Lit::Pos(x) | Lit::Neg(x) if x.pred.name == name))
            .collect();
        let effs: Vec<_> = a
            .effects
            .iter()
            .filter(|(_, e)| matches!(e, Effect::Add(x) | Effect::Del(x) if x.pred.name == name))
            .collect();
        if conds.is_empty() && effs.is_empty() {
            return true;
        }
        let cond_ok = matches!(conds.as_slice(), [(ast::When::Start, Lit::Pos(_))]);
        let mut kinds: Vec<(ast::When, bool)> = effs
            .iter()
            .map(|(w, e)| (*w, matches!(e, Effect::Add(_))))
            .collect();
        kinds.sort();
        cond_ok && kinds == [(ast::When::Start, false), (ast::When::End, true)]
    })
}

/// Every combination of `choices` (the ground instances of a predicate), or `None` beyond `limit`.
fn combinations(choices: &[Vec<ObjectId>], limit: usize) -> Option<Vec<Vec<ObjectId>>> {
    let n = choices
        .iter()
        .try_fold(1usize, |acc, c| acc.checked_mul(c.len()))?;
    if n > limit {
        return None;
    }
    Some(crate::model::combinations(choices))
}

fn value_of(b: bool) -> Value {
    Value::Obj(Domain::truth(b))
}

fn problem(cx: &Cx, model: &Domain, p: &ast::Problem, base: usize) -> Result<Problem, PddlError> {
    let mut pr = Problem::new(p.name.name.clone(), model, HORIZON_S * MS_PER_S);
    for o in &p.objects {
        let ty = cx.model_type(&o.types);
        let id = pr.add_object(Object {
            name: o.name.name.clone(),
            ty,
            position: None,
        });
        if cx.objs.get(&o.name.name) != Some(&id) || id.index() < base {
            return Err(cx.perr(
                o.name.span,
                "internal: object numbering differs between the domain and the problem",
            ));
        }
    }
    let mut facts: Vec<(Time, Fact)> = Vec::new();
    let mut pred_names: Vec<&String> = cx.preds.keys().collect();
    pred_names.sort();
    for name in pred_names {
        let Some((rep, params)) = cx.preds.get(name) else {
            continue;
        };
        let trues = cx.init_true.get(name);
        match rep {
            PredRep::Lock { .. } => {}
            PredRep::Bool { attr, fluent } => {
                if *fluent || cx.needs_false.contains(name) {
                    let choices: Vec<Vec<ObjectId>> =
                        params.iter().map(|t| cx.objects_of(&t.types)).collect();
                    let Some(all) = combinations(&choices, MAX_GROUND_ATOMS) else {
                        return Err(cx.derr(Span::default(), format!("predicate `{name}` has more than {MAX_GROUND_ATOMS} ground atoms: too many for the closed-world initial state")));
                    };
                    for args in all {
                        let v = trues.is_some_and(|t| t.contains(&args));
                        facts.push((
                            0,
                            Fact {
                                attr: *attr,
                                args,
                                value: value_of(v),
                            },
                        ));
                    }
                } else if let Some(t) = trues {
                    for args in t {
                        facts.push((
                            0,
                            Fact {
                                attr: *attr,
                                args: args.clone(),
                                value: value_of(true),
                            },
                        ));
                    }
                }
            }
            PredRep::Group(g) => {
                for args in trues.into_iter().flatten() {
                    let (key, value) = g.split_ground(args);
                    facts.push((
                        0,
                        Fact {
                            attr: g.attr,
                            args: key,
                            value,
                        },
                    ));
                }
            }
        }
    }
    for i in &p.init {
        let (a, at, add) = match i {
            Init::Atom(a, Some(t)) => (a, *t, true),
            Init::NotAtom(a, t) => (a, *t, false),
            _ => continue,
        };
        let (rep, _) = cx.pred(a, cx.ps)?;
        let args = cx.ground(a)?;
        let at_ms = (at * MS_PER_S as f64).round() as Time;
        if at_ms >= HORIZON_S * MS_PER_S {
            return Err(cx.perr(
                a.span,
                format!("timed initial literals are supported up to {HORIZON_S} s"),
            ));
        }
        let fact = match rep {
            PredRep::Bool { attr, .. } => Fact {
                attr: *attr,
                args,
                value: value_of(add),
            },
            PredRep::Lock { .. } | PredRep::Group(_) => {
                return Err(cx.perr(
                    a.span,
                    "internal: a timed literal on a multi-valued variable",
                ))
            }
        };
        facts.push((at_ms, fact));
    }
    pr.add_facts(facts);
    for (r, level) in &cx.fluent_initial {
        if let Some(setup) = pr.resources.get_mut(r.index()) {
            setup.level = *level;
        }
    }
    let horizon = pr.horizon;
    for (i, l) in p.goal.iter().enumerate() {
        let (a, positive) = match l {
            Lit::Pos(a) => (a, true),
            Lit::Neg(a) => (a, false),
            Lit::Equal(..) | Lit::Compare(..) => {
                return Err(cx.perr(
                    l.span(),
                    "goals are conjunctions of atoms and negated atoms",
                ))
            }
        };
        let (rep, _) = cx.pred(a, cx.ps)?;
        let args = cx.ground(a)?;
        let (attr, args, value) = match rep {
            PredRep::Bool { attr, fluent } => {
                if !fluent {
                    let holds = cx
                        .init_true
                        .get(&a.pred.name)
                        .is_some_and(|t| t.contains(&args));
                    if holds == positive {
                        continue;
                    }
                    return Err(cx.perr(a.span, "this goal is false initially and no action changes it: the problem has no plan"));
                }
                (*attr, args, value_of(positive))
            }
            PredRep::Group(g) => {
                let (key, value) = g.split_ground(&args);
                (g.attr, key, value)
            }
            PredRep::Lock { .. } => {
                return Err(cx.perr(a.span, "internal: a goal on a lock"));
            }
        };
        // PDDL goals hold at the end of the plan: at the horizon, after every action.
        pr.goals.push(Goal {
            name: format!("g{}", i + 1),
            kind: GoalOrigin::External,
            priority: 1,
            attr,
            args,
            value,
            start_window: TimeInterval::exactly(horizon),
            duration: TimeInterval::exactly(0),
            achieve: 0,
        });
    }
    Ok(pr)
}
