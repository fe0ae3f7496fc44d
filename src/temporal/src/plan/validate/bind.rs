//! Instantiation of the plan's symbolic variables: a small backtracking search for one object per
//! variable, within its reported domain and its type, respecting the plan's ≠ and every binding
//! constraint of the tasks (re-derived from the templates). Any constraint the chosen (or, when none
//! exists, a fallback) instantiation breaks is reported.

use crate::model::{Binding, Domain, NumConstraint, ObjectId, Problem, Term};
use crate::plan::solution::{PlanTerm, Solution};

use super::Violation;

/// Bound on search nodes: the plans checked are small; beyond this we report no instantiation.
const MAX_NODES: usize = 200_000;

/// Relative tolerance of distance comparisons (the planner computes them in floating point too).
pub(super) fn close_enough(x: f64, lo: f64, hi: f64) -> bool {
    let eps = 1e-6 * x.abs().max(1.0);
    x >= lo - eps && x <= hi + eps
}

/// A constraint over plan terms, labelled with the action it comes from.
enum Con {
    Eq(PlanTerm, PlanTerm),
    Ne(PlanTerm, PlanTerm),
    In(PlanTerm, Vec<ObjectId>),
    /// `distance(a, b) ∈ [lo, hi]` (the reported bounds of a `?dist = distance(a, b)` variable); only
    /// guides the search, the numeric check reports it.
    Dist(PlanTerm, PlanTerm, f64, f64),
}

struct Labelled {
    who: String,
    con: Con,
}

pub(super) fn instantiate(
    d: &Domain,
    p: &Problem,
    s: &Solution,
    out: &mut Vec<Violation>,
) -> Vec<ObjectId> {
    let mut domains: Vec<Vec<ObjectId>> = s.variables.iter().map(|v| v.domain.clone()).collect();
    let mut cons: Vec<Labelled> = s
        .different
        .iter()
        .map(|&(a, b)| Labelled {
            who: "plan".into(),
            con: Con::Ne(PlanTerm::Var(a), PlanTerm::Var(b)),
        })
        .collect();
    for a in &s.actions {
        let task = d.task(a.task);
        let who = format!("{} ({})", a.name, task.name);
        let term = |t: &Term| match *t {
            Term::Obj(o) => PlanTerm::Obj(o),
            Term::Unknown => PlanTerm::Unknown,
            Term::Var(v) => a.arg(v).unwrap_or(PlanTerm::Unknown),
        };
        // Types: a variable only takes objects of the type of every task variable mapped onto it.
        for (i, (sv, arg)) in task.sym_vars.iter().zip(&a.args).enumerate() {
            match *arg {
                PlanTerm::Obj(o) if p.object(o).is_some_and(|ob| ob.ty != sv.ty) => {
                    out.push(Violation::Binding {
                        action: who.clone(),
                        reason: format!(
                            "?{} = {} is not a {}",
                            sv.name,
                            p.object_name(o),
                            d.ty(sv.ty).name
                        ),
                    })
                }
                PlanTerm::Var(v) => {
                    if let Some(dom) = domains.get_mut(v.index()) {
                        dom.retain(|&o| p.object(o).is_some_and(|ob| ob.ty == sv.ty));
                    }
                }
                PlanTerm::Unknown => out.push(Violation::Binding {
                    action: who.clone(),
                    reason: format!("variable #{i} ?{} is bound to +oo", sv.name),
                }),
                PlanTerm::Obj(_) => {}
            }
        }
        for b in &task.bindings {
            let con = match b {
                Binding::Eq(x, y) => Con::Eq(term(x), term(y)),
                Binding::Ne(x, y) => Con::Ne(term(x), term(y)),
                Binding::In(v, set) => Con::In(term(&Term::Var(*v)), set.clone()),
            };
            cons.push(Labelled {
                who: who.clone(),
                con,
            });
        }
        for n in &task.numeric {
            if let NumConstraint::Distance { var, a: x, b: y } = n {
                let nb = a.num(*var);
                let lo = nb.and_then(|b| b.lo).unwrap_or(f64::NEG_INFINITY);
                let hi = nb.and_then(|b| b.hi).unwrap_or(f64::INFINITY);
                cons.push(Labelled {
                    who: who.clone(),
                    con: Con::Dist(term(x), term(y), lo, hi),
                });
            }
        }
    }
    for (v, dom) in s.variables.iter().zip(&domains) {
        if dom.is_empty() {
            out.push(Violation::Binding {
                action: "plan".into(),
                reason: format!(
                    "variable {} has no value of its type left in its domain",
                    v.name
                ),
            });
        }
    }
    let mut search = Search {
        p,
        domains: &domains,
        cons: &cons,
        vals: vec![None; domains.len()],
        nodes: 0,
    };
    let found = search.run(0);
    let vals: Vec<ObjectId> = if found {
        search
            .vals
            .iter()
            .map(|v| v.unwrap_or(ObjectId(0)))
            .collect()
    } else {
        // No instantiation: take each variable's first value and report what that breaks.
        domains
            .iter()
            .zip(&s.variables)
            .map(|(d, v)| {
                d.first()
                    .or(v.domain.first())
                    .copied()
                    .unwrap_or(ObjectId(0))
            })
            .collect()
    };
    let full: Vec<Option<ObjectId>> = vals.iter().copied().map(Some).collect();
    for c in &cons {
        if matches!(c.con, Con::Dist(..)) {
            continue;
        }
        if holds(p, &c.con, &full) == Some(false) {
            out.push(Violation::Binding {
                action: c.who.clone(),
                reason: describe(p, s, &c.con, &vals),
            });
        }
    }
    if !found && out.iter().all(|v| !matches!(v, Violation::Binding { .. })) {
        out.push(Violation::Binding {
            action: "plan".into(),
            reason: "no instantiation of the plan's variables satisfies its binding and distance constraints"
                .into(),
        });
    }
    vals
}

struct Search<'a> {
    p: &'a Problem,
    domains: &'a [Vec<ObjectId>],
    cons: &'a [Labelled],
    vals: Vec<Option<ObjectId>>,
    nodes: usize,
}

impl Search<'_> {
    fn run(&mut self, i: usize) -> bool {
        if i == self.domains.len() {
            return true;
        }
        for &o in &self.domains[i] {
            self.nodes += 1;
            if self.nodes > MAX_NODES {
                return false;
            }
            self.vals[i] = Some(o);
            let ok = self
                .cons
                .iter()
                .all(|c| holds(self.p, &c.con, &self.vals) != Some(false));
            if ok && self.run(i + 1) {
                return true;
            }
        }
        self.vals[i] = None;
        false
    }
}

/// The object a term denotes under a partial instantiation (`None`: unassigned or `+oo`).
fn obj(t: PlanTerm, vals: &[Option<ObjectId>]) -> Option<ObjectId> {
    match t {
        PlanTerm::Obj(o) => Some(o),
        PlanTerm::Var(v) => vals.get(v.index()).copied().flatten(),
        PlanTerm::Unknown => None,
    }
}

/// `Some(truth)` once every term is assigned, `None` before.
fn holds(p: &Problem, c: &Con, vals: &[Option<ObjectId>]) -> Option<bool> {
    match c {
        Con::Eq(a, b) => Some(obj(*a, vals)? == obj(*b, vals)?),
        Con::Ne(a, b) => Some(obj(*a, vals)? != obj(*b, vals)?),
        Con::In(a, set) => Some(set.contains(&obj(*a, vals)?)),
        Con::Dist(a, b, lo, hi) => {
            let d = p.distance(obj(*a, vals)?, obj(*b, vals)?)?;
            Some(close_enough(d, *lo, *hi))
        }
    }
}

fn describe(p: &Problem, s: &Solution, c: &Con, vals: &[ObjectId]) -> String {
    let show = |t: &PlanTerm| match *t {
        PlanTerm::Obj(o) => p.object_name(o).to_string(),
        PlanTerm::Unknown => "+oo".to_string(),
        PlanTerm::Var(v) => {
            let name = s.variables.get(v.index()).map_or("?", |x| x.name.as_str());
            let val = vals.get(v.index()).map_or("?", |&o| p.object_name(o));
            format!("{name} (= {val})")
        }
    };
    match c {
        Con::Eq(a, b) => format!("{} = {}", show(a), show(b)),
        Con::Ne(a, b) => format!("{} ≠ {}", show(a), show(b)),
        Con::In(a, set) => {
            let names: Vec<&str> = set.iter().map(|&o| p.object_name(o)).collect();
            format!("{} in {{{}}}", show(a), names.join(", "))
        }
        Con::Dist(a, b, lo, hi) => format!("distance({}, {}) in [{lo}, {hi}]", show(a), show(b)),
    }
}
