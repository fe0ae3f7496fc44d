//! The binding CSP (seed 1 §2.2: "the other CSP manages symbolic variables with constraints such as domain
//! restrictions, equalities or inequalities").
//!
//! Variables have finite domains of objects. Equalities merge variables into one class (union-find without
//! path compression, so that a trail can undo a union); inequalities are kept as pairs and propagated by
//! forward checking (a singleton class removes its value from the other side). Every change is trailed:
//! [`Bindings::save`] / [`Bindings::restore`].
//!
//! Each class also lists the other ends of the inequalities of its members, so "is there a `≠` between
//! these two classes" scans that class's own inequalities, not every one of the plan (each move of a tour
//! posts its `?from ≠ ?to`: a scan of them all made every binding test grow with the plan).
//!
//! This is the *minimal domain* view IxTeT keeps for least commitment: nothing is bound unless a resolver
//! requires it. Forward checking is not complete for ≠ (a pigeonhole of ≠ may pass); the checker instantiates
//! the final plan and would catch it.

use backtrack::{Level, Trail};
use serde::Serialize;

use crate::model::{ObjectId, Value};

/// A symbolic variable of the plan (one per variable of each inserted task).
#[derive(Copy, Clone, Eq, PartialEq, Ord, PartialOrd, Hash, Debug, Serialize)]
pub struct VarId(pub u32);

/// A symbolic term of the plan: a variable, an object, or IxTeT's `+oo` (unknown / in transit).
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug, Serialize)]
pub enum STerm {
    Var(VarId),
    Obj(ObjectId),
    Unknown,
}

impl From<Value> for STerm {
    fn from(v: Value) -> Self {
        match v {
            Value::Obj(o) => STerm::Obj(o),
            Value::Unknown => STerm::Unknown,
        }
    }
}

#[derive(Clone, Debug)]
enum Entry {
    NewVar,
    /// Old domain of a class root.
    Domain(u32, Vec<ObjectId>),
    /// `child` was attached under a root: undo by making it a root again, and by cutting the root's
    /// inequality list back to its length before the union.
    Union(u32, u32),
    /// An inequality between the classes of these two roots (each got the other end in its list).
    NewNe(u32, u32),
}

/// The binding constraint network.
#[derive(Clone, Debug, Default)]
pub struct Bindings {
    parent: Vec<u32>,
    /// Domain of each class root (sorted); stale for non-roots.
    domain: Vec<Vec<ObjectId>>,
    size: Vec<u32>,
    ne: Vec<(u32, u32)>,
    /// Per class root, the other end of every inequality of a member of the class (stale for non-roots,
    /// kept as they were for undoing a union).
    ne_of: Vec<Vec<u32>>,
    trail: Trail<Entry>,
    /// Variables whose class domain changed since the last [`Bindings::take_changed`] (for the numeric CSP).
    changed: Vec<u32>,
}

/// The constraints cannot all hold.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("inconsistent bindings")]
pub struct BindingConflict;

impl Bindings {
    /// A new variable ranging over `domain`.
    pub fn new_var(&mut self, mut domain: Vec<ObjectId>) -> VarId {
        domain.sort();
        domain.dedup();
        let v = self.parent.len() as u32;
        self.parent.push(v);
        self.domain.push(domain);
        self.size.push(1);
        self.ne_of.push(Vec::new());
        self.trail.push(Entry::NewVar);
        VarId(v)
    }

    pub fn num_vars(&self) -> usize {
        self.parent.len()
    }

    fn root(&self, mut v: u32) -> u32 {
        while self.parent[v as usize] != v {
            v = self.parent[v as usize];
        }
        v
    }

    /// The current domain of `v` (of its class).
    pub fn domain(&self, v: VarId) -> &[ObjectId] {
        &self.domain[self.root(v.0) as usize]
    }

    /// The value of `t` if it is bound (an object, `+oo`, or a variable with a singleton domain).
    pub fn value(&self, t: STerm) -> Option<Value> {
        match t {
            STerm::Obj(o) => Some(Value::Obj(o)),
            STerm::Unknown => Some(Value::Unknown),
            STerm::Var(v) => match self.domain(v) {
                [o] => Some(Value::Obj(*o)),
                _ => None,
            },
        }
    }

    fn has_ne(&self, a: u32, b: u32) -> bool {
        let (a, b) = (self.root(a), self.root(b));
        // The shorter of the two lists: each holds the pair.
        let (list, other) = if self.ne_of[a as usize].len() <= self.ne_of[b as usize].len() {
            (&self.ne_of[a as usize], b)
        } else {
            (&self.ne_of[b as usize], a)
        };
        list.iter().any(|&z| self.root(z) == other)
    }

    /// Whether `a = b` is consistent with the current constraints (forward-checking view).
    pub fn possibly_equal(&self, a: STerm, b: STerm) -> bool {
        match (a, b) {
            (STerm::Unknown, STerm::Unknown) => true,
            (STerm::Unknown, _) | (_, STerm::Unknown) => false,
            (STerm::Obj(x), STerm::Obj(y)) => x == y,
            (STerm::Var(v), STerm::Obj(o)) | (STerm::Obj(o), STerm::Var(v)) => {
                self.domain(v).binary_search(&o).is_ok()
            }
            (STerm::Var(x), STerm::Var(y)) => {
                let (rx, ry) = (self.root(x.0), self.root(y.0));
                if rx == ry {
                    return true;
                }
                let (dx, dy) = (&self.domain[rx as usize], &self.domain[ry as usize]);
                intersects(dx, dy) && !self.has_ne(rx, ry)
            }
        }
    }

    /// Whether `a = b` in every instantiation.
    pub fn necessarily_equal(&self, a: STerm, b: STerm) -> bool {
        if let (STerm::Var(x), STerm::Var(y)) = (a, b) {
            if self.root(x.0) == self.root(y.0) {
                return true;
            }
        }
        matches!((self.value(a), self.value(b)), (Some(x), Some(y)) if x == y)
    }

    /// Whether `a ≠ b` in every instantiation.
    pub fn necessarily_different(&self, a: STerm, b: STerm) -> bool {
        !self.possibly_equal(a, b)
    }

    /// Posts `a = b`.
    pub fn unify(&mut self, a: STerm, b: STerm) -> Result<(), BindingConflict> {
        match (a, b) {
            (STerm::Unknown, STerm::Unknown) => Ok(()),
            (STerm::Unknown, _) | (_, STerm::Unknown) => Err(BindingConflict),
            (STerm::Obj(x), STerm::Obj(y)) => {
                if x == y {
                    Ok(())
                } else {
                    Err(BindingConflict)
                }
            }
            (STerm::Var(v), STerm::Obj(o)) | (STerm::Obj(o), STerm::Var(v)) => {
                let r = self.root(v.0);
                self.restrict(r, &[o])?;
                self.propagate()
            }
            (STerm::Var(x), STerm::Var(y)) => {
                let (rx, ry) = (self.root(x.0), self.root(y.0));
                if rx == ry {
                    return Ok(());
                }
                if self.has_ne(rx, ry) {
                    return Err(BindingConflict);
                }
                let (big, small) = if self.size[rx as usize] >= self.size[ry as usize] {
                    (rx, ry)
                } else {
                    (ry, rx)
                };
                let other = self.domain[small as usize].clone();
                self.restrict(big, &other)?;
                self.parent[small as usize] = big;
                self.size[big as usize] += self.size[small as usize];
                let before = self.ne_of[big as usize].len() as u32;
                let moved = self.ne_of[small as usize].clone();
                self.ne_of[big as usize].extend(moved);
                self.trail.push(Entry::Union(small, before));
                self.changed.push(small);
                self.propagate()
            }
        }
    }

    /// Posts `a ≠ b`.
    pub fn separate(&mut self, a: STerm, b: STerm) -> Result<(), BindingConflict> {
        match (a, b) {
            (STerm::Var(x), STerm::Var(y)) => {
                if self.root(x.0) == self.root(y.0) {
                    return Err(BindingConflict);
                }
                let (rx, ry) = (self.root(x.0), self.root(y.0));
                self.ne.push((x.0, y.0));
                self.ne_of[rx as usize].push(y.0);
                self.ne_of[ry as usize].push(x.0);
                self.trail.push(Entry::NewNe(rx, ry));
                self.propagate()
            }
            (STerm::Var(v), STerm::Obj(o)) | (STerm::Obj(o), STerm::Var(v)) => {
                let r = self.root(v.0);
                self.exclude(r, o)?;
                self.propagate()
            }
            _ => {
                if self.possibly_equal(a, b) {
                    Err(BindingConflict)
                } else {
                    Ok(())
                }
            }
        }
    }

    /// Restricts `v`'s domain to `allowed`.
    pub fn restrict_var(&mut self, v: VarId, allowed: &[ObjectId]) -> Result<(), BindingConflict> {
        let mut allowed = allowed.to_vec();
        allowed.sort();
        let r = self.root(v.0);
        self.restrict(r, &allowed)?;
        self.propagate()
    }

    /// Intersects the domain of root `r` with the sorted `allowed`.
    fn restrict(&mut self, r: u32, allowed: &[ObjectId]) -> Result<(), BindingConflict> {
        let cur = &self.domain[r as usize];
        let new: Vec<ObjectId> = cur
            .iter()
            .copied()
            .filter(|o| allowed.binary_search(o).is_ok())
            .collect();
        if new.is_empty() {
            return Err(BindingConflict);
        }
        if new.len() != cur.len() {
            let old = std::mem::replace(&mut self.domain[r as usize], new);
            self.trail.push(Entry::Domain(r, old));
            self.changed.push(r);
        }
        Ok(())
    }

    /// Removes `o` from the domain of root `r`.
    fn exclude(&mut self, r: u32, o: ObjectId) -> Result<(), BindingConflict> {
        let keep: Vec<ObjectId> = self.domain[r as usize]
            .iter()
            .copied()
            .filter(|&x| x != o)
            .collect();
        self.restrict(r, &keep)
    }

    /// Forward checking of the inequalities to a fixed point.
    fn propagate(&mut self) -> Result<(), BindingConflict> {
        loop {
            let mut progress = false;
            for i in 0..self.ne.len() {
                let (a, b) = self.ne[i];
                let (ra, rb) = (self.root(a), self.root(b));
                if ra == rb {
                    return Err(BindingConflict);
                }
                for (x, y) in [(ra, rb), (rb, ra)] {
                    if let [o] = self.domain[x as usize][..] {
                        if self.domain[y as usize].binary_search(&o).is_ok() {
                            self.exclude(y, o)?;
                            progress = true;
                        }
                    }
                }
            }
            if !progress {
                return Ok(());
            }
        }
    }

    /// Whether `v` was (possibly) affected by a domain change since the last call, then forgets the changes.
    /// Returns the roots whose domain changed.
    pub fn take_changed(&mut self) -> Vec<u32> {
        std::mem::take(&mut self.changed)
    }

    /// The class representative of `v` (changes reported by [`Bindings::take_changed`] are representatives
    /// or merged-away roots).
    pub fn class_of(&self, v: VarId) -> u32 {
        self.root(v.0)
    }

    /// The posted inequalities between variables.
    pub fn ne_pairs(&self) -> impl Iterator<Item = (VarId, VarId)> + '_ {
        self.ne.iter().map(|&(a, b)| (VarId(a), VarId(b)))
    }

    /// The current trail level.
    pub fn save(&self) -> Level {
        self.trail.level()
    }

    /// Undoes every change made after `level`, and forgets the changed domains not yet taken.
    pub fn restore(&mut self, level: Level) {
        let (parent, domain, size, ne, ne_of) = (
            &mut self.parent,
            &mut self.domain,
            &mut self.size,
            &mut self.ne,
            &mut self.ne_of,
        );
        self.trail.restore(level, |entry| match entry {
            Entry::NewVar => {
                parent.pop();
                domain.pop();
                size.pop();
                ne_of.pop();
            }
            Entry::Domain(r, old) => domain[r as usize] = old,
            Entry::Union(child, before) => {
                let root = parent[child as usize];
                size[root as usize] -= size[child as usize];
                ne_of[root as usize].truncate(before as usize);
                parent[child as usize] = child;
            }
            Entry::NewNe(ra, rb) => {
                ne.pop();
                ne_of[ra as usize].pop();
                ne_of[rb as usize].pop();
            }
        });
        self.changed.clear();
    }
}

backtrack::impl_backtrack!(Bindings, Level);

fn intersects(a: &[ObjectId], b: &[ObjectId]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Equal => return true,
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;

    fn o(i: u32) -> ObjectId {
        ObjectId(i)
    }

    #[test]
    fn unify_intersects_and_restore_undoes() {
        let mut b = Bindings::default();
        let x = b.new_var(vec![o(1), o(2), o(3)]);
        let y = b.new_var(vec![o(2), o(3), o(4)]);
        let l = b.save();
        b.unify(STerm::Var(x), STerm::Var(y)).unwrap();
        assert_eq!(b.domain(x), &[o(2), o(3)]);
        assert!(b.necessarily_equal(STerm::Var(x), STerm::Var(y)));
        b.restore(l);
        assert_eq!(b.domain(x), &[o(1), o(2), o(3)]);
        assert!(!b.necessarily_equal(STerm::Var(x), STerm::Var(y)));
    }

    #[test]
    fn inequality_forward_checks_and_conflicts() {
        let mut b = Bindings::default();
        let x = b.new_var(vec![o(1), o(2)]);
        let y = b.new_var(vec![o(1), o(2)]);
        b.separate(STerm::Var(x), STerm::Var(y)).unwrap();
        assert!(b.possibly_equal(STerm::Var(x), STerm::Obj(o(1))));
        assert!(!b.possibly_equal(STerm::Var(x), STerm::Var(y)));
        b.unify(STerm::Var(x), STerm::Obj(o(1))).unwrap();
        assert_eq!(b.domain(y), &[o(2)]);
        assert!(b.unify(STerm::Var(x), STerm::Var(y)).is_err());
        assert!(b.unify(STerm::Var(y), STerm::Obj(o(1))).is_err());
    }
}

#[cfg(test)]
#[path = "bindings_tests.rs"]
mod ne_index_tests;
