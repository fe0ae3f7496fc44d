//! Grounding a PDDL problem for the forward search ([`crate::planner::forward`]): every action instance
//! whose conditions can hold, found by relaxed reachability (Hoffmann & Nebel's, as FF grounds): starting
//! from the initial atoms, the instances whose static conditions hold in the initial state and whose
//! positive conditions are reachable are generated, their additions become reachable, until nothing new
//! appears. Static atoms (no action changes them) are decided at grounding and left out of the ground
//! conditions. Numeric fluents that actions change are numeric state variables (one per ground instance);
//! comparisons on them are left to the search (relaxed reachability takes them as satisfiable), and a
//! function changed by actions but read by nothing (a cost such as `total-fuel-used`, read by the metric
//! alone) is left out, as the translation does. What the forward search does not model is refused with
//! the reason — timed initial literals, goals beyond literals, `?duration` in an effect of an action
//! without `(= ?duration e)` — and the POCL planner alone plans those problems.

use std::collections::{BTreeSet, HashMap, HashSet};

use super::ast::{self, Arg, Atom, Cmp, Effect, Init, Lit, NExpr, When};
use crate::planner::forward::{
    AtomId, Cond, GroundAction, GroundTask, Happening, NumCond, NumEffect, NumExpr,
};

/// Ground actions beyond which grounding gives up (the forward search would not get far either).
const MAX_GROUND_ACTIONS: usize = 200_000;

/// Why a problem is not grounded for the forward search.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GroundError {
    #[error("{0} are not handled by the forward search")]
    Unsupported(&'static str),
    #[error("more than {MAX_GROUND_ACTIONS} ground actions")]
    TooLarge,
    #[error("`{0}` is not a parameter, a constant or an object")]
    UnknownName(String),
}

#[derive(Clone, Copy, Debug)]
enum A {
    Param(usize),
    Obj(u32),
}

#[derive(Clone, Debug)]
struct Lifted {
    pred: u32,
    args: Vec<A>,
}

/// What is checked once the first `depth` parameters are assigned.
#[derive(Clone, Debug)]
enum Check {
    /// A static atom must be (`true`) or not be initially true.
    Static(Lifted, bool),
    /// A fluent atom must be reachable.
    Reachable(Lifted),
    Equal(A, A, bool),
    Compare(Cmp, NExpr, NExpr),
}

struct Names {
    preds: HashMap<String, u32>,
    objects: HashMap<String, u32>,
    object_names: Vec<String>,
}

impl Names {
    fn pred(&mut self, p: &str) -> u32 {
        let n = self.preds.len() as u32;
        *self.preds.entry(p.to_string()).or_insert(n)
    }
}

type Key = (u32, Vec<u32>);

/// The ground task of a PDDL domain and problem.
pub fn ground(d: &ast::Domain, p: &ast::Problem) -> Result<GroundTask, GroundError> {
    for i in &p.init {
        if matches!(i, Init::Atom(_, Some(_)) | Init::NotAtom(..)) {
            return Err(GroundError::Unsupported("timed initial literals"));
        }
    }
    let mut names = Names {
        preds: HashMap::new(),
        objects: HashMap::new(),
        object_names: Vec::new(),
    };
    let mut object_types: Vec<Vec<String>> = Vec::new();
    for o in d.constants.iter().chain(&p.objects) {
        if names.objects.contains_key(&o.name.name) {
            continue;
        }
        names
            .objects
            .insert(o.name.name.clone(), names.object_names.len() as u32);
        names.object_names.push(o.name.name.clone());
        object_types.push(o.types.iter().map(|t| t.name.clone()).collect());
    }
    let is_sub = super::simulate::subtype_test(d);
    let mut changed: HashSet<&str> = HashSet::new();
    for a in &d.actions {
        for (_, e) in &a.effects {
            if let Effect::Add(x) | Effect::Del(x) = e {
                changed.insert(&x.pred.name);
            }
        }
    }
    let numeric = Numeric::of(d, p);
    let mut values: HashMap<(String, Vec<u32>), f64> = HashMap::new();
    let mut init: HashSet<Key> = HashSet::new();
    for i in &p.init {
        match i {
            Init::Atom(x, _) => {
                let k = ground_const(&mut names, x)?;
                init.insert(k);
            }
            Init::Value(f, v) => {
                let k = ground_const(&mut names, f)?;
                values.insert((f.pred.name.clone(), k.1), *v);
            }
            Init::NotAtom(..) => {}
        }
    }
    // Each action's checks by the number of parameters they need assigned.
    let mut plans: Vec<Vec<Vec<Check>>> = Vec::new();
    for a in &d.actions {
        let start_adds: HashSet<&str> = a
            .effects
            .iter()
            .filter_map(|(w, e)| match (w, e) {
                (When::Start, Effect::Add(x)) => Some(x.pred.name.as_str()),
                _ => None,
            })
            .collect();
        let mut checks: Vec<Vec<Check>> = vec![Vec::new(); a.params.len() + 1];
        for (w, l) in &a.conditions {
            let (check, depth) = match l {
                Lit::Pos(x) | Lit::Neg(x) => {
                    let lifted = lift(&mut names, a, x)?;
                    let depth = depth_of(&lifted.args);
                    let positive = matches!(l, Lit::Pos(_));
                    if !changed.contains(x.pred.name.as_str()) {
                        (Check::Static(lifted, positive), depth)
                    } else if positive
                        && (*w == When::Start || !start_adds.contains(x.pred.name.as_str()))
                    {
                        (Check::Reachable(lifted), depth)
                    } else {
                        continue;
                    }
                }
                Lit::Equal(x, y, eq, _) => {
                    let (x, y) = (arg(&names, a, x)?, arg(&names, a, y)?);
                    (Check::Equal(x, y, *eq), depth_of(&[x, y]))
                }
                Lit::Compare(_, x, y, _) if numeric.reads_state(x) || numeric.reads_state(y) => {
                    // A condition on numeric state: decided by the search.
                    for e in [x, y] {
                        expr_depth(&names, a, e)?;
                    }
                    continue;
                }
                Lit::Compare(c, x, y, _) => {
                    let mut depth = 0;
                    for e in [x, y] {
                        depth = depth.max(expr_depth(&names, a, e)?);
                    }
                    (Check::Compare(*c, x.clone(), y.clone()), depth)
                }
            };
            checks[depth.min(a.params.len())].push(check);
        }
        plans.push(checks);
    }
    let domains: Vec<Vec<Vec<u32>>> = d
        .actions
        .iter()
        .map(|a| {
            a.params
                .iter()
                .map(|q| {
                    (0..names.object_names.len() as u32)
                        .filter(|&o| {
                            object_types[o as usize]
                                .iter()
                                .any(|t| q.types.iter().any(|x| is_sub(t, &x.name)))
                        })
                        .collect()
                })
                .collect()
        })
        .collect();
    // Relaxed reachability to a fixpoint.
    let mut reachable: HashSet<Key> = init.clone();
    let mut instances: Vec<(usize, Vec<u32>)>;
    loop {
        instances = Vec::new();
        for (ai, a) in d.actions.iter().enumerate() {
            let mut binding = Vec::with_capacity(a.params.len());
            let cx = Cx {
                checks: &plans[ai],
                domains: &domains[ai],
                init: &init,
                reachable: &reachable,
                values: &values,
                names: &names,
                action: a,
                numeric: &numeric,
            };
            cx.enumerate(&mut binding, &mut |b| instances.push((ai, b.to_vec())))?;
            if instances.len() > MAX_GROUND_ACTIONS {
                return Err(GroundError::TooLarge);
            }
        }
        let before = reachable.len();
        for (ai, b) in &instances {
            for (_, e) in &d.actions[*ai].effects {
                if let Effect::Add(x) = e {
                    reachable.insert(ground_atom(&mut names, d, *ai, x, b)?);
                }
            }
        }
        if reachable.len() == before {
            break;
        }
    }
    // The ground task: atoms numbered as met, static ones left out of conditions.
    let mut atoms: HashMap<Key, AtomId> = HashMap::new();
    let mut atom_names: Vec<String> = Vec::new();
    let mut id = |k: Key, names: &Names| -> AtomId {
        let n = atoms.len() as AtomId;
        *atoms.entry(k.clone()).or_insert_with(|| {
            let pred = names
                .preds
                .iter()
                .find(|(_, &v)| v == k.0)
                .map_or("?", |(s, _)| s.as_str());
            let args: Vec<&str> =
                k.1.iter()
                    .map(|&o| names.object_names[o as usize].as_str())
                    .collect();
            atom_names.push(format!("({pred} {})", args.join(" ")));
            n
        })
    };
    let mut task_init: Vec<AtomId> = Vec::new();
    // In a fixed order: atom numbers break the heuristic's ties, and a hash set's order changes per run.
    let mut init_sorted: Vec<&Key> = init.iter().collect();
    init_sorted.sort();
    for k in init_sorted {
        let pred_name = names
            .preds
            .iter()
            .find(|(_, &v)| v == k.0)
            .map(|(s, _)| s.clone());
        if pred_name.is_some_and(|s| changed.contains(s.as_str())) {
            task_init.push(id(k.clone(), &names));
        }
    }
    let mut goal = Cond::default();
    for l in &p.goal {
        let (x, positive) = match l {
            Lit::Pos(x) => (x, true),
            Lit::Neg(x) => (x, false),
            _ => return Err(GroundError::Unsupported("goals other than literals")),
        };
        let k = ground_const(&mut names, x)?;
        if !changed.contains(x.pred.name.as_str()) {
            if init.contains(&k) != positive {
                // A static goal that is false: no plan; the forward search finds the goal unreachable.
                goal.pos.push(id((u32::MAX, Vec::new()), &names));
            }
            continue;
        }
        let a = id(k, &names);
        if positive {
            goal.pos.push(a);
        } else {
            goal.neg.push(a);
        }
    }
    let mut vars = Vars::default();
    let mut actions = Vec::with_capacity(instances.len());
    for (ai, b) in instances {
        let a = &d.actions[ai];
        let mut start = Happening::default();
        let mut over_all = Cond::default();
        let mut end = Happening::default();
        let mut gx = Grounder {
            action: a,
            binding: &b,
            values: &values,
            numeric: &numeric,
            vars: &mut vars,
        };
        for (w, l) in &a.conditions {
            let (x, positive) = match l {
                Lit::Pos(x) => (x, true),
                Lit::Neg(x) => (x, false),
                Lit::Compare(cmp, x, y, _) if numeric.reads_state(x) || numeric.reads_state(y) => {
                    let c = NumCond {
                        cmp: *cmp,
                        lhs: gx.expr(&names, x)?,
                        rhs: gx.expr(&names, y)?,
                    };
                    match w {
                        When::Start => start.pre.num.push(c),
                        When::OverAll => over_all.num.push(c),
                        When::End => end.pre.num.push(c),
                    }
                    continue;
                }
                _ => continue,
            };
            if !changed.contains(x.pred.name.as_str()) {
                continue;
            }
            let k = ground_atom(&mut names, d, ai, x, &b)?;
            let c = match w {
                When::Start => &mut start.pre,
                When::OverAll => &mut over_all,
                When::End => &mut end.pre,
            };
            let atom = id(k, &names);
            if positive {
                c.pos.push(atom);
            } else {
                c.neg.push(atom);
            }
        }
        for (w, e) in &a.effects {
            let h = if *w == When::End {
                &mut end
            } else {
                &mut start
            };
            match e {
                Effect::Add(x) => h
                    .add
                    .push(id(ground_atom(&mut names, d, ai, x, &b)?, &names)),
                Effect::Del(x) => h
                    .del
                    .push(id(ground_atom(&mut names, d, ai, x, &b)?, &names)),
                Effect::Num(_, f, _, _) if !numeric.read.contains(&f.pred.name) => {}
                Effect::Num(op, f, e, _) => {
                    let var = gx.var(&names, f)?;
                    let expr = gx.expr(&names, e)?;
                    h.num.push(NumEffect { op: *op, var, expr });
                }
            }
        }
        let mut duration = None;
        if a.effects.iter().any(|(_, e)| match e {
            Effect::Num(_, f, e, _) => numeric.read.contains(&f.pred.name) && e.uses_duration(),
            _ => false,
        }) {
            let Some((_, e, _)) = a.duration.iter().find(|(c, _, _)| *c == Cmp::Eq) else {
                return Err(GroundError::Unsupported(
                    "`?duration` in effects of actions without `(= ?duration e)`",
                ));
            };
            duration = Some(gx.expr(&names, e)?);
        }
        actions.push(GroundAction {
            name: a.name.name.clone(),
            args: b
                .iter()
                .map(|&o| names.object_names[o as usize].clone())
                .collect(),
            start,
            over_all,
            end,
            duration,
        });
    }
    Ok(GroundTask {
        atoms: atom_names,
        init: task_init,
        nums: vars.names,
        init_nums: vars.init,
        goal,
        actions,
    })
}

/// Which functions are numeric state: changed by some action (`changed`) and read by a condition, a
/// duration or an effect (`read`, a subset of `changed`; the others are costs, left out).
struct Numeric {
    changed: BTreeSet<String>,
    read: BTreeSet<String>,
}

impl Numeric {
    fn of(d: &ast::Domain, p: &ast::Problem) -> Self {
        let mut changed = BTreeSet::new();
        for a in &d.actions {
            for (_, e) in &a.effects {
                if let Effect::Num(_, f, _, _) = e {
                    changed.insert(f.pred.name.clone());
                }
            }
        }
        let read = changed
            .intersection(&super::fluents::read_functions(d, p))
            .cloned()
            .collect();
        Numeric { changed, read }
    }

    /// Whether `e` reads a function that actions change.
    fn reads_state(&self, e: &NExpr) -> bool {
        super::fluents::mentions(e, &self.changed)
    }
}

/// The numeric state variables met so far: one per ground instance of a function that is state.
#[derive(Default)]
struct Vars {
    ids: HashMap<(String, Vec<u32>), u32>,
    names: Vec<String>,
    init: Vec<f64>,
}

/// Grounds the numeric expressions of one action instance.
struct Grounder<'a> {
    action: &'a ast::Action,
    binding: &'a [u32],
    values: &'a HashMap<(String, Vec<u32>), f64>,
    numeric: &'a Numeric,
    vars: &'a mut Vars,
}

impl Grounder<'_> {
    fn key(&self, names: &Names, f: &Atom) -> Result<(String, Vec<u32>), GroundError> {
        let mut args = Vec::with_capacity(f.args.len());
        for x in &f.args {
            args.push(value(arg(names, self.action, x)?, self.binding));
        }
        Ok((f.pred.name.clone(), args))
    }

    /// The state variable of a ground instance of a numeric-state function.
    fn var(&mut self, names: &Names, f: &Atom) -> Result<u32, GroundError> {
        let k = self.key(names, f)?;
        if let Some(&i) = self.vars.ids.get(&k) {
            return Ok(i);
        }
        let i = self.vars.names.len() as u32;
        let text: Vec<&str> =
            k.1.iter()
                .map(|&o| names.object_names[o as usize].as_str())
                .collect();
        self.vars
            .names
            .push(format!("({} {})", k.0, text.join(" ")));
        self.vars
            .init
            .push(self.values.get(&k).copied().unwrap_or(f64::NAN));
        self.vars.ids.insert(k, i);
        Ok(i)
    }

    fn expr(&mut self, names: &Names, e: &NExpr) -> Result<NumExpr, GroundError> {
        Ok(match e {
            NExpr::Num(v, _) => NumExpr::Const(*v),
            NExpr::Duration(_) => NumExpr::Duration,
            NExpr::Neg(x, _) => NumExpr::Neg(Box::new(self.expr(names, x)?)),
            NExpr::Bin(op, x, y, _) => NumExpr::Bin(
                *op,
                Box::new(self.expr(names, x)?),
                Box::new(self.expr(names, y)?),
            ),
            NExpr::Fluent(f) if f.pred.name == "total-time" => {
                return Err(GroundError::Unsupported("`total-time` outside the metric"))
            }
            NExpr::Fluent(f) if self.numeric.changed.contains(&f.pred.name) => {
                NumExpr::Var(self.var(names, f)?)
            }
            NExpr::Fluent(f) => {
                let k = self.key(names, f)?;
                NumExpr::Const(self.values.get(&k).copied().unwrap_or(f64::NAN))
            }
        })
    }
}

struct Cx<'a> {
    checks: &'a [Vec<Check>],
    domains: &'a [Vec<u32>],
    init: &'a HashSet<Key>,
    reachable: &'a HashSet<Key>,
    values: &'a HashMap<(String, Vec<u32>), f64>,
    names: &'a Names,
    action: &'a ast::Action,
    numeric: &'a Numeric,
}

impl Cx<'_> {
    /// Every assignment of the remaining parameters that passes the checks, given to `out`.
    fn enumerate(
        &self,
        binding: &mut Vec<u32>,
        out: &mut dyn FnMut(&[u32]),
    ) -> Result<(), GroundError> {
        let depth = binding.len();
        for c in &self.checks[depth] {
            if !self.check(c, binding)? {
                return Ok(());
            }
        }
        if depth == self.domains.len() {
            if self.duration_defined(binding) {
                out(binding);
            }
            return Ok(());
        }
        for &o in &self.domains[depth] {
            binding.push(o);
            self.enumerate(binding, out)?;
            binding.pop();
        }
        Ok(())
    }

    fn check(&self, c: &Check, b: &[u32]) -> Result<bool, GroundError> {
        let key = |l: &Lifted| -> Key { (l.pred, l.args.iter().map(|a| value(*a, b)).collect()) };
        Ok(match c {
            Check::Static(l, positive) => self.init.contains(&key(l)) == *positive,
            Check::Reachable(l) => self.reachable.contains(&key(l)),
            Check::Equal(x, y, eq) => (value(*x, b) == value(*y, b)) == *eq,
            Check::Compare(op, x, y) => match (self.eval(x, b), self.eval(y, b)) {
                (Some(x), Some(y)) => op.holds(x, y),
                _ => false,
            },
        })
    }

    /// Whether every duration bound on static functions has a value for these arguments (a static
    /// function may have none: the action does not apply there, as the translation decides too); a bound
    /// on numeric state is the search's to evaluate.
    fn duration_defined(&self, b: &[u32]) -> bool {
        self.action
            .duration
            .iter()
            .filter(|(_, e, _)| !self.numeric.reads_state(e))
            .all(|(_, e, _)| self.eval(e, b).is_some_and(|v| v >= 0.0))
    }

    fn eval(&self, e: &NExpr, b: &[u32]) -> Option<f64> {
        Some(match e {
            NExpr::Num(v, _) => *v,
            NExpr::Duration(_) => return None,
            NExpr::Neg(x, _) => -self.eval(x, b)?,
            NExpr::Bin(op, x, y, _) => ast::arithmetic(*op, self.eval(x, b)?, self.eval(y, b)?),
            NExpr::Fluent(f) => {
                let mut args = Vec::with_capacity(f.args.len());
                for x in &f.args {
                    args.push(value(arg(self.names, self.action, x).ok()?, b));
                }
                *self.values.get(&(f.pred.name.clone(), args))?
            }
        })
    }
}

fn value(a: A, b: &[u32]) -> u32 {
    match a {
        A::Param(i) => b.get(i).copied().unwrap_or(u32::MAX),
        A::Obj(o) => o,
    }
}

fn depth_of(args: &[A]) -> usize {
    args.iter()
        .map(|a| match a {
            A::Param(i) => i + 1,
            A::Obj(_) => 0,
        })
        .max()
        .unwrap_or(0)
}

/// The parameters a numeric expression needs assigned; a fluent that actions change is refused.
fn expr_depth(names: &Names, a: &ast::Action, e: &NExpr) -> Result<usize, GroundError> {
    Ok(match e {
        NExpr::Num(..) => 0,
        NExpr::Duration(_) => return Err(GroundError::Unsupported("conditions on ?duration")),
        NExpr::Neg(x, _) => expr_depth(names, a, x)?,
        NExpr::Bin(_, x, y, _) => expr_depth(names, a, x)?.max(expr_depth(names, a, y)?),
        NExpr::Fluent(f) => {
            if f.pred.name == "total-time" {
                return Err(GroundError::Unsupported("conditions on total-time"));
            }
            let mut args = Vec::new();
            for x in &f.args {
                args.push(arg(names, a, x)?);
            }
            depth_of(&args)
        }
    })
}

fn arg(names: &Names, a: &ast::Action, x: &Arg) -> Result<A, GroundError> {
    match x {
        Arg::Var(n) => a
            .params
            .iter()
            .position(|q| q.name.name == n.name)
            .map(A::Param)
            .ok_or_else(|| GroundError::UnknownName(n.name.clone())),
        Arg::Const(n) => names
            .objects
            .get(&n.name)
            .map(|&o| A::Obj(o))
            .ok_or_else(|| GroundError::UnknownName(n.name.clone())),
    }
}

fn lift(names: &mut Names, a: &ast::Action, x: &Atom) -> Result<Lifted, GroundError> {
    let mut args = Vec::with_capacity(x.args.len());
    for y in &x.args {
        args.push(arg(names, a, y)?);
    }
    Ok(Lifted {
        pred: names.pred(&x.pred.name),
        args,
    })
}

fn ground_atom(
    names: &mut Names,
    d: &ast::Domain,
    ai: usize,
    x: &Atom,
    b: &[u32],
) -> Result<Key, GroundError> {
    let l = lift(names, &d.actions[ai], x)?;
    Ok((l.pred, l.args.iter().map(|a| value(*a, b)).collect()))
}

fn ground_const(names: &mut Names, x: &Atom) -> Result<Key, GroundError> {
    let mut args = Vec::with_capacity(x.args.len());
    for y in &x.args {
        match names.objects.get(&y.name().name) {
            Some(&o) => args.push(o),
            None => return Err(GroundError::UnknownName(y.name().name.clone())),
        }
    }
    Ok((names.pred(&x.pred.name), args))
}
