//! Numeric constraints (`?dist = distance(?from, ?to)`, `?duration = et − st`, `?dist = ?speed *
//! ?duration` ...): at the schedule and instantiation, the distance and duration variables are fixed;
//! the remaining constraints must keep every variable's domain (declared ∩ reported bounds) non-empty
//! under interval propagation to a fixed point (bounds consistency — for the tree-shaped constraint sets
//! of the tasks, this decides satisfiability).

use crate::model::{NumConstraint, NumTerm, NumVarId, Task, MS_PER_S};
use crate::plan::solution::PlanAction;

use super::bind::close_enough;
use super::{Ctx, NumericFault, Violation};

/// A closed real interval `[lo, hi]` (infinite ends allowed).
pub(super) type Iv = (f64, f64);

/// Propagation rounds per action (the tasks' constraint sets are small and settle in a few).
const ROUNDS: usize = 32;

/// Checks every action; returns the propagated domain of each action's numeric variables (in
/// `s.actions` order), used for the resource quantities.
pub(super) fn check(cx: &Ctx, out: &mut Vec<Violation>) -> Vec<Vec<Iv>> {
    cx.s.actions
        .iter()
        .map(|a| {
            let task = cx.d.task(a.task);
            match action(cx, task, a) {
                Ok(doms) => doms,
                Err(reason) => {
                    out.push(Violation::Numeric {
                        action: cx.label(a),
                        reason,
                    });
                    reported(task, a)
                }
            }
        })
        .collect()
}

/// Declared domains intersected with the reported bounds (no emptiness check).
fn reported(task: &Task, a: &PlanAction) -> Vec<Iv> {
    task.num_vars
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let b = a.num(NumVarId::from_index(i));
            let lo = b.and_then(|b| b.lo).unwrap_or(f64::NEG_INFINITY);
            let hi = b.and_then(|b| b.hi).unwrap_or(f64::INFINITY);
            (v.domain.lo().max(lo), v.domain.hi().min(hi))
        })
        .collect()
}

fn action(cx: &Ctx, task: &Task, a: &PlanAction) -> Result<Vec<Iv>, NumericFault> {
    let mut dom = reported(task, a);
    let name = |v: NumVarId| {
        task.num_vars
            .get(v.index())
            .map_or("?".to_string(), |x| format!("?{}", x.name))
    };
    for (i, (lo, hi)) in dom.iter().enumerate() {
        if *lo > *hi {
            return Err(NumericFault::EmptyDomain {
                var: name(NumVarId::from_index(i)),
                lo: *lo,
                hi: *hi,
            });
        }
    }
    // The values the schedule and the instantiation fix.
    for c in &task.numeric {
        let (var, x, what) = match c {
            NumConstraint::Duration { var, from, to } => {
                let ms = cx.at(a, *to) - cx.at(a, *from);
                (*var, ms as f64 / MS_PER_S as f64, "the scheduled duration")
            }
            NumConstraint::Distance { var, a: p, b: q } => {
                let (pv, qv) = (cx.term(a, *p), cx.term(a, *q));
                let d = match (pv, qv) {
                    (crate::model::Value::Obj(x), crate::model::Value::Obj(y)) => {
                        cx.p.distance(x, y)
                    }
                    _ => None,
                };
                let Some(d) = d else {
                    return Err(NumericFault::NoCoordinates {
                        var: name(*var),
                        from: cx.value_name(pv),
                        to: cx.value_name(qv),
                    });
                };
                (*var, d, "the distance")
            }
            _ => continue,
        };
        let Some(slot) = dom.get_mut(var.index()) else {
            return Err(NumericFault::UnknownVariable(var.0));
        };
        if !close_enough(x, slot.0, slot.1) {
            return Err(NumericFault::OutOfBounds {
                var: name(var),
                value: x,
                what,
                lo: slot.0,
                hi: slot.1,
            });
        }
        *slot = (x, x);
    }
    for _ in 0..ROUNDS {
        let before = dom.clone();
        for c in &task.numeric {
            narrow(c, &mut dom).map_err(|()| NumericFault::NoSolution {
                constraint: show(c, &name),
                domains: show_doms(&dom, &name),
            })?;
        }
        if dom == before {
            break;
        }
    }
    Ok(dom)
}

fn get(t: NumTerm, dom: &[Iv]) -> Iv {
    match t {
        NumTerm::Const(c) => (c, c),
        NumTerm::Var(v) => dom
            .get(v.index())
            .copied()
            .unwrap_or((f64::NEG_INFINITY, f64::INFINITY)),
    }
}

/// Intersects term `t` with `iv`; `Err` when nothing is left.
fn set(t: NumTerm, iv: Iv, dom: &mut [Iv]) -> Result<(), ()> {
    let cur = get(t, dom);
    let (mut lo, mut hi) = (cur.0.max(iv.0), cur.1.min(iv.1));
    if lo > hi {
        let eps = 1e-6 * lo.abs().max(hi.abs()).max(1.0);
        if lo - hi > eps || lo.is_nan() || hi.is_nan() {
            return Err(());
        }
        let mid = (lo + hi) / 2.0;
        (lo, hi) = (mid, mid);
    }
    if let NumTerm::Var(v) = t {
        if let Some(slot) = dom.get_mut(v.index()) {
            *slot = (lo, hi);
        }
    }
    Ok(())
}

/// `0 × ∞ = 0`: the product of interval ends.
fn m(x: f64, y: f64) -> f64 {
    if x == 0.0 || y == 0.0 {
        0.0
    } else {
        x * y
    }
}

fn mul(a: Iv, b: Iv) -> Iv {
    let p = [m(a.0, b.0), m(a.0, b.1), m(a.1, b.0), m(a.1, b.1)];
    (
        p.iter().copied().fold(f64::INFINITY, f64::min),
        p.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    )
}

/// `a / b`, or everything when `b` contains 0.
fn div(a: Iv, b: Iv) -> Iv {
    if b.0 <= 0.0 && b.1 >= 0.0 {
        return (f64::NEG_INFINITY, f64::INFINITY);
    }
    mul(a, (1.0 / b.1, 1.0 / b.0))
}

fn narrow(c: &NumConstraint, dom: &mut [Iv]) -> Result<(), ()> {
    match *c {
        NumConstraint::Product { var, a, b } => {
            let v = NumTerm::Var(var);
            set(v, mul(get(a, dom), get(b, dom)), dom)?;
            set(a, div(get(v, dom), get(b, dom)), dom)?;
            set(b, div(get(v, dom), get(a, dom)), dom)
        }
        NumConstraint::Sum { var, a, b } => {
            let v = NumTerm::Var(var);
            let (x, y) = (get(a, dom), get(b, dom));
            set(v, (x.0 + y.0, x.1 + y.1), dom)?;
            let z = get(v, dom);
            let y = get(b, dom);
            set(a, (z.0 - y.1, z.1 - y.0), dom)?;
            let x = get(a, dom);
            set(b, (z.0 - x.1, z.1 - x.0), dom)
        }
        NumConstraint::Le(a, b) => {
            let (x, y) = (get(a, dom), get(b, dom));
            set(a, (f64::NEG_INFINITY, y.1), dom)?;
            set(b, (x.0, f64::INFINITY), dom)
        }
        NumConstraint::Equal(a, b) => {
            set(a, get(b, dom), dom)?;
            set(b, get(a, dom), dom)
        }
        // Fixed beforehand.
        NumConstraint::Distance { .. } | NumConstraint::Duration { .. } => Ok(()),
    }
}

fn show(c: &NumConstraint, name: &dyn Fn(NumVarId) -> String) -> String {
    let t = |t: NumTerm| match t {
        NumTerm::Const(c) => c.to_string(),
        NumTerm::Var(v) => name(v),
    };
    match *c {
        NumConstraint::Product { var, a, b } => format!("{} = {} * {}", name(var), t(a), t(b)),
        NumConstraint::Sum { var, a, b } => format!("{} = {} + {}", name(var), t(a), t(b)),
        NumConstraint::Le(a, b) => format!("{} <= {}", t(a), t(b)),
        NumConstraint::Equal(a, b) => format!("{} = {}", t(a), t(b)),
        NumConstraint::Distance { var, .. } => format!("{} = distance(..)", name(var)),
        NumConstraint::Duration { var, .. } => format!("{} = et - st", name(var)),
    }
}

fn show_doms(dom: &[Iv], name: &dyn Fn(NumVarId) -> String) -> String {
    let v: Vec<String> = dom
        .iter()
        .enumerate()
        .map(|(i, (lo, hi))| format!("{} in [{lo}, {hi}]", name(NumVarId::from_index(i))))
        .collect();
    v.join(", ")
}
