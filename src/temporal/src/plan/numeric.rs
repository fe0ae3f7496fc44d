//! Numeric variables over real intervals (seed 1 §2.2, Trinquart & Ghallab 2001): `?dist = distance(..)`,
//! `?dist = ?speed * ?duration`, `?duration = et − st`. Each variable keeps bounds `[lo, hi]`, narrowed by
//! interval propagation (bounds consistency) to a fixed point; the mixed constraint `?d = et − st` is the
//! supervisor's bridge: it reads the STN constraint's interval and tightens it back. Trailed like the rest.

use backtrack::{Level, Trail};
use serde::Serialize;

use super::bindings::{Bindings, STerm};
use crate::model::{Problem, MS_PER_S};
use crate::stn::{ConstraintId, Stn, INF};

/// A numeric variable of the plan.
#[derive(Copy, Clone, Eq, PartialEq, Ord, PartialOrd, Hash, Debug, Serialize)]
pub struct NVar(pub u32);

/// A numeric term: a variable or a constant.
#[derive(Copy, Clone, PartialEq, Debug, Serialize)]
pub enum NTerm {
    Var(NVar),
    Const(f64),
}

/// A numeric constraint of an inserted task (see [`crate::model::NumConstraint`]).
#[derive(Clone, Debug, PartialEq)]
pub enum NumCons {
    Distance {
        var: NVar,
        a: STerm,
        b: STerm,
    },
    /// `var · 1000 = to − from` in the STN constraint `c` (seconds vs milliseconds).
    Duration {
        var: NVar,
        c: ConstraintId,
    },
    Product {
        var: NVar,
        a: NTerm,
        b: NTerm,
    },
    Sum {
        var: NVar,
        a: NTerm,
        b: NTerm,
    },
    Le(NTerm, NTerm),
    Equal(NTerm, NTerm),
}

/// The bounds became empty.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("inconsistent numeric constraints")]
pub struct NumConflict;

#[derive(Clone, Debug)]
enum Entry {
    NewVar,
    Bounds(u32, f64, f64),
}

/// Interval bounds of every numeric variable.
#[derive(Clone, Debug, Default)]
pub struct Numeric {
    lo: Vec<f64>,
    hi: Vec<f64>,
    trail: Trail<Entry>,
}

/// Relative tolerance under which a narrowing is not a change (avoids endless tiny steps).
const EPS: f64 = 1e-9;

impl Numeric {
    pub fn new_var(&mut self, lo: f64, hi: f64) -> NVar {
        self.lo.push(lo);
        self.hi.push(hi);
        self.trail.push(Entry::NewVar);
        NVar(self.lo.len() as u32 - 1)
    }

    /// `[lo, hi]` of `v`.
    pub fn bounds(&self, v: NVar) -> (f64, f64) {
        (self.lo[v.0 as usize], self.hi[v.0 as usize])
    }

    /// `[lo, hi]` of a term.
    pub fn term(&self, t: NTerm) -> (f64, f64) {
        match t {
            NTerm::Var(v) => self.bounds(v),
            NTerm::Const(c) => (c, c),
        }
    }

    /// Intersects `v` with `[lo, hi]`; `Ok(true)` if it narrowed.
    pub fn narrow(&mut self, v: NVar, lo: f64, hi: f64) -> Result<bool, NumConflict> {
        let i = v.0 as usize;
        let (olo, ohi) = (self.lo[i], self.hi[i]);
        let tol = EPS * (1.0 + olo.abs().max(ohi.abs()).min(1e12));
        let nlo = if lo > olo + tol { lo } else { olo };
        let nhi = if hi < ohi - tol { hi } else { ohi };
        if nlo > nhi + tol {
            return Err(NumConflict);
        }
        if nlo == olo && nhi == ohi {
            return Ok(false);
        }
        self.trail.push(Entry::Bounds(v.0, olo, ohi));
        self.lo[i] = nlo;
        self.hi[i] = nhi.max(nlo);
        Ok(true)
    }

    fn narrow_term(&mut self, t: NTerm, lo: f64, hi: f64) -> Result<bool, NumConflict> {
        match t {
            NTerm::Var(v) => self.narrow(v, lo, hi),
            NTerm::Const(c) => {
                let tol = EPS * (1.0 + c.abs());
                if c < lo - tol || c > hi + tol {
                    Err(NumConflict)
                } else {
                    Ok(false)
                }
            }
        }
    }

    /// The current trail level.
    pub fn save(&self) -> Level {
        self.trail.level()
    }

    /// Undoes every narrowing and new variable after `level`.
    pub fn restore(&mut self, level: Level) {
        let (lo, hi) = (&mut self.lo, &mut self.hi);
        self.trail.restore(level, |entry| match entry {
            Entry::NewVar => {
                lo.pop();
                hi.pop();
            }
            Entry::Bounds(v, old_lo, old_hi) => {
                lo[v as usize] = old_lo;
                hi[v as usize] = old_hi;
            }
        });
    }

    /// Propagates `cons` to a fixed point (bounded number of rounds), reading distances from `problem`
    /// through `bindings` and exchanging durations with `stn`.
    pub fn propagate(
        &mut self,
        cons: &[NumCons],
        bindings: &Bindings,
        problem: &Problem,
        stn: &mut Stn,
    ) -> Result<(), NumConflict> {
        for _round in 0..20 {
            let mut changed = false;
            for c in cons {
                changed |= self.revise(c, bindings, problem, stn)?;
            }
            if !changed {
                return Ok(());
            }
        }
        Ok(())
    }

    fn revise(
        &mut self,
        c: &NumCons,
        bindings: &Bindings,
        problem: &Problem,
        stn: &mut Stn,
    ) -> Result<bool, NumConflict> {
        match *c {
            NumCons::Distance { var, a, b } => match distance_range(a, b, bindings, problem) {
                Some(Some((lo, hi))) => self.narrow(var, lo, hi),
                // Every leg the domains allow leaves the vehicle's limits (Problem::legs).
                Some(None) => Err(NumConflict),
                None => Ok(false),
            },
            NumCons::Duration { var, c } => {
                let k = stn.constraint(c);
                let s = MS_PER_S as f64;
                let lo = if k.lb <= -INF {
                    f64::NEG_INFINITY
                } else {
                    k.lb as f64 / s
                };
                let hi = if k.ub >= INF {
                    f64::INFINITY
                } else {
                    k.ub as f64 / s
                };
                let changed = self.narrow(var, lo, hi)?;
                let (vlo, vhi) = self.bounds(var);
                let tlo = if vlo.is_finite() {
                    (vlo * s - 1e-6).ceil() as i64
                } else {
                    -INF
                };
                let thi = if vhi.is_finite() {
                    (vhi * s + 1e-6).floor() as i64
                } else {
                    INF
                };
                if tlo > k.lb || thi < k.ub {
                    stn.tighten(c, tlo, thi).map_err(|_| NumConflict)?;
                }
                Ok(changed)
            }
            NumCons::Product { var, a, b } => {
                let (alo, ahi) = self.term(a);
                let (blo, bhi) = self.term(b);
                let (plo, phi) = mul((alo, ahi), (blo, bhi));
                let mut ch = self.narrow(var, plo, phi)?;
                let v = self.bounds(var);
                if let Some((lo, hi)) = div(v, (blo, bhi)) {
                    ch |= self.narrow_term(a, lo, hi)?;
                }
                let v = self.bounds(var);
                if let Some((lo, hi)) = div(v, self.term(a)) {
                    ch |= self.narrow_term(b, lo, hi)?;
                }
                Ok(ch)
            }
            NumCons::Sum { var, a, b } => {
                let (alo, ahi) = self.term(a);
                let (blo, bhi) = self.term(b);
                let mut ch = self.narrow(var, alo + blo, ahi + bhi)?;
                let (vlo, vhi) = self.bounds(var);
                ch |= self.narrow_term(a, vlo - bhi, vhi - blo)?;
                let (alo, ahi) = self.term(a);
                ch |= self.narrow_term(b, vlo - ahi, vhi - alo)?;
                Ok(ch)
            }
            NumCons::Le(a, b) => {
                let (alo, _) = self.term(a);
                let (_, bhi) = self.term(b);
                let ch = self.narrow_term(a, f64::NEG_INFINITY, bhi)?;
                Ok(ch | self.narrow_term(b, alo, f64::INFINITY)?)
            }
            NumCons::Equal(a, b) => {
                let (alo, ahi) = self.term(a);
                let ch = self.narrow_term(b, alo, ahi)?;
                let (blo, bhi) = self.term(b);
                Ok(ch | self.narrow_term(a, blo, bhi)?)
            }
        }
    }
}

backtrack::impl_backtrack!(Numeric, Level);

/// Range of `distance(a, b)` over the current domains and the legs the vehicle may drive (`None` if
/// unknowable or too many pairs to scan; `Some(None)` when no pair is a leg it may drive).
fn distance_range(
    a: STerm,
    b: STerm,
    bindings: &Bindings,
    problem: &Problem,
) -> Option<Option<(f64, f64)>> {
    let dom = |t: STerm| -> Option<Vec<crate::model::ObjectId>> {
        match t {
            STerm::Obj(o) => Some(vec![o]),
            STerm::Var(v) => Some(bindings.domain(v).to_vec()),
            STerm::Unknown => None,
        }
    };
    let (da, db) = (dom(a)?, dom(b)?);
    if da.is_empty() || db.is_empty() || da.len() * db.len() > 4096 {
        return None;
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &x in &da {
        for &y in &db {
            if x != y && !problem.leg_allowed(x, y) {
                continue;
            }
            let d = if x == y { 0.0 } else { problem.distance(x, y)? };
            lo = lo.min(d);
            hi = hi.max(d);
        }
    }
    Some((lo <= hi).then_some((lo, hi)))
}

fn mul(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    let ps = [a.0 * b.0, a.0 * b.1, a.1 * b.0, a.1 * b.1];
    let ps = ps.map(|p| if p.is_nan() { 0.0 } else { p });
    let lo = ps.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ps.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (lo, hi)
}

/// `v / d` when `d` excludes 0 (otherwise no information).
fn div(v: (f64, f64), d: (f64, f64)) -> Option<(f64, f64)> {
    if d.0 <= 0.0 && d.1 >= 0.0 {
        return None;
    }
    Some(mul(v, (1.0 / d.1, 1.0 / d.0)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn product_narrows_each_side() {
        let mut n = Numeric::default();
        let dist = n.new_var(10.0, 10.0);
        let speed = n.new_var(0.5, 1.0);
        let dur = n.new_var(0.0, f64::INFINITY);
        let cons = [NumCons::Product {
            var: dist,
            a: NTerm::Var(speed),
            b: NTerm::Var(dur),
        }];
        let b = Bindings::default();
        let p = Problem::new("p", &crate::model::Domain::new("d"), 1000);
        let mut stn = Stn::new();
        n.propagate(&cons, &b, &p, &mut stn).unwrap();
        let (lo, hi) = n.bounds(dur);
        assert!(
            (lo - 10.0).abs() < 1e-9 && (hi - 20.0).abs() < 1e-9,
            "{lo} {hi}"
        );
        assert!(n.narrow(dur, 25.0, 30.0).is_err());
        // A higher minimal speed shortens the longest duration; undone by restore.
        let l = n.save();
        assert_eq!(n.narrow(speed, 0.8, 1.0), Ok(true));
        n.propagate(&cons, &b, &p, &mut stn).unwrap();
        assert!((n.bounds(dur).1 - 12.5).abs() < 1e-9);
        n.restore(l);
        assert_eq!(n.bounds(dur), (lo, hi));
        assert_eq!(n.bounds(speed), (0.5, 1.0));
    }
}
