//! The network: timepoints, constraints, bounds, and the public operations.

use backtrack::Trail;

use super::error::Inconsistent;
use super::trail::Entry;
use super::{norm_lb, norm_ub, Constraint, ConstraintId, Time, Timepoint, INF};

/// One direction of a constraint: `Forward` is `to − from ≤ ub` (edge from→to, weight ub), `Backward` is
/// `from − to ≤ −lb` (edge to→from, weight −lb).
#[derive(Copy, Clone, Eq, PartialEq, Debug)]
pub(crate) struct Half {
    pub c: u32,
    pub forward: bool,
}

#[derive(Clone, Debug)]
pub(crate) struct CData {
    pub from: u32,
    pub to: u32,
    pub lb: Time,
    pub ub: Time,
    pub active: bool,
    /// Index of the forward half in `out[from]` and of the backward half in `out[to]` (and in `wout`).
    pub at_from: u32,
    pub at_to: u32,
}

impl CData {
    /// (tail, head, weight) of one direction; weight `INF` means no edge.
    pub fn edge(&self, forward: bool) -> (u32, u32, Time) {
        if forward {
            (self.from, self.to, self.ub)
        } else {
            (
                self.to,
                self.from,
                if self.lb <= -INF { INF } else { -self.lb },
            )
        }
    }
}

/// A Simple Temporal Network with incrementally maintained bounds and a trail. See the module docs.
#[derive(Clone, Debug)]
pub struct Stn {
    pub(crate) lb: Vec<Time>,
    pub(crate) ub: Vec<Time>,
    pub(crate) cons: Vec<CData>,
    /// Halves leaving each timepoint (all halves, finite or not: a tightening can make one finite).
    pub(crate) out: Vec<Vec<Half>>,
    /// Halves entering each timepoint.
    pub(crate) inc: Vec<Vec<Half>>,
    /// `out` as (head, weight), `INF` where there is no edge (removed constraint, infinite bound), kept in
    /// step by [`Stn::sync_edges`]: what the distance queries scan, without a look-up per half.
    pub(crate) wout: Vec<Vec<(u32, Time)>>,
    pub(crate) executed: Vec<Option<ConstraintId>>,
    pub(crate) trail: Trail<Entry>,
    pub(crate) scratch: super::propagate::Scratch,
    /// Edges added or lowered, for [`super::memo`] (undone edges are dropped by restores).
    pub(crate) log: Vec<super::memo::LoggedEdge>,
    /// Stamp of the last logged edge (never decreases).
    pub(crate) log_stamp: u64,
    pub(crate) memo: super::memo::Memo,
    /// The all-pairs matrix of paths avoiding the origin, when kept ([`super::paths`]).
    pub(crate) paths: super::paths::PathsCache,
}

impl Default for Stn {
    fn default() -> Self {
        Self::new()
    }
}

impl Stn {
    /// A network holding only the origin (fixed at 0).
    pub fn new() -> Self {
        Stn {
            lb: vec![0],
            ub: vec![0],
            cons: Vec::new(),
            out: vec![Vec::new()],
            inc: vec![Vec::new()],
            wout: vec![Vec::new()],
            executed: vec![None],
            trail: Trail::new(),
            scratch: Default::default(),
            log: Vec::new(),
            log_stamp: 0,
            memo: Default::default(),
            paths: Default::default(),
        }
    }

    pub fn origin(&self) -> Timepoint {
        Timepoint(0)
    }

    /// A new timepoint, bounds `[0, +INF]` relative to the origin.
    pub fn add_timepoint(&mut self) -> Timepoint {
        let t = self.lb.len() as u32;
        self.lb.push(0);
        self.ub.push(INF);
        self.out.push(Vec::new());
        self.inc.push(Vec::new());
        self.wout.push(Vec::new());
        self.executed.push(None);
        self.trail.push(Entry::AddTimepoint);
        self.paths_push_timepoint();
        Timepoint(t)
    }

    pub fn num_timepoints(&self) -> usize {
        self.lb.len()
    }

    /// All timepoints, the origin first.
    pub fn timepoints(&self) -> impl Iterator<Item = Timepoint> + '_ {
        (0..self.lb.len() as u32).map(Timepoint)
    }

    /// Adds `to − from ∈ [lb, ub]` (`lb` may be `-INF`, `ub` may be `INF`; finite bounds are clamped to
    /// ±[`MAX_FINITE`](super::MAX_FINITE)) and propagates the bounds.
    /// On `Err` the network is left exactly as before.
    pub fn add_constraint(
        &mut self,
        from: Timepoint,
        to: Timepoint,
        lb: Time,
        ub: Time,
    ) -> Result<ConstraintId, Inconsistent> {
        // Not `save`: a rollback point that the matrix of paths need not honour (it is updated on success).
        let level = self.trail.level();
        let c = self.cons.len() as u32;
        let at_from = self.out[from.0 as usize].len() as u32;
        self.out[from.0 as usize].push(Half { c, forward: true });
        self.inc[to.0 as usize].push(Half { c, forward: true });
        let at_to = self.out[to.0 as usize].len() as u32;
        self.out[to.0 as usize].push(Half { c, forward: false });
        self.inc[from.0 as usize].push(Half { c, forward: false });
        self.wout[from.0 as usize].push((to.0, INF));
        self.wout[to.0 as usize].push((from.0, INF));
        self.cons.push(CData {
            from: from.0,
            to: to.0,
            lb: -INF,
            ub: INF,
            active: true,
            at_from,
            at_to,
        });
        self.trail.push(Entry::AddConstraint);
        match self.impose(c, norm_lb(lb), norm_ub(ub)) {
            Ok(()) => Ok(ConstraintId(c)),
            Err(e) => {
                self.restore(level);
                Err(e)
            }
        }
    }

    /// `a` strictly before `b`: `b − a ∈ ]0, +INF[`, i.e. `[1, INF]`.
    pub fn add_precedence(
        &mut self,
        a: Timepoint,
        b: Timepoint,
    ) -> Result<ConstraintId, Inconsistent> {
        self.add_constraint(a, b, 1, INF)
    }

    /// Intersects constraint `c`'s interval with `[lb, ub]` and propagates. On `Err` nothing changes.
    pub fn tighten(&mut self, c: ConstraintId, lb: Time, ub: Time) -> Result<(), Inconsistent> {
        // Not `save`: a rollback point that the matrix of paths need not honour (it is updated on success).
        let level = self.trail.level();
        let d = &self.cons[c.index()];
        let (old_lb, old_ub) = (d.lb, d.ub);
        let (new_lb, new_ub) = (old_lb.max(norm_lb(lb)), old_ub.min(norm_ub(ub)));
        if (new_lb, new_ub) == (old_lb, old_ub) {
            return Ok(());
        }
        self.trail.push(Entry::Weights(c.0, old_lb, old_ub));
        let result = if self.cons[c.index()].active {
            self.impose(c.0, new_lb, new_ub)
        } else {
            let d = &mut self.cons[c.index()];
            d.lb = new_lb;
            d.ub = new_ub;
            // Inactive: its edges stay INF in `wout` until a restore makes it active again.
            Ok(())
        };
        if result.is_err() {
            self.restore(level);
        }
        result
    }

    /// Copies constraint `c`'s current edges into `wout` (after any change of its bounds or activity).
    pub(crate) fn sync_edges(&mut self, c: u32) {
        let d = &self.cons[c as usize];
        let (fw, bw) = if d.active {
            (d.edge(true).2, d.edge(false).2)
        } else {
            (INF, INF)
        };
        let (from, to) = (d.from as usize, d.to as usize);
        let (at_from, at_to) = (d.at_from as usize, d.at_to as usize);
        self.wout[from][at_from].1 = fw;
        self.wout[to][at_to].1 = bw;
    }

    /// The constraint as currently stored (also for removed ones).
    pub fn constraint(&self, c: ConstraintId) -> Constraint {
        let d = &self.cons[c.index()];
        Constraint {
            from: Timepoint(d.from),
            to: Timepoint(d.to),
            lb: d.lb,
            ub: d.ub,
        }
    }

    /// Whether `c` is in the network (not removed).
    pub fn is_active(&self, c: ConstraintId) -> bool {
        self.cons[c.index()].active
    }

    /// The constraints in the network (removed ones excluded).
    pub fn constraints(&self) -> impl Iterator<Item = (ConstraintId, Constraint)> + '_ {
        (0..self.cons.len() as u32)
            .map(ConstraintId)
            .filter(|c| self.is_active(*c))
            .map(|c| (c, self.constraint(c)))
    }

    /// The constraints in the network that involve `t`.
    pub fn constraints_of(
        &self,
        t: Timepoint,
    ) -> impl Iterator<Item = (ConstraintId, Constraint)> + '_ {
        self.out[t.index()]
            .iter()
            .filter(|h| h.forward)
            .chain(self.inc[t.index()].iter().filter(|h| h.forward))
            .map(|h| ConstraintId(h.c))
            .filter(|c| self.is_active(*c))
            .map(|c| (c, self.constraint(c)))
    }

    /// Timepoints that must strictly precede `t` by a constraint between them (`t − p ≥ 1` stated directly,
    /// not implied through other timepoints). May repeat a timepoint constrained twice.
    pub fn predecessors(&self, t: Timepoint) -> impl Iterator<Item = Timepoint> + '_ {
        self.strict_neighbours(t, false)
    }

    /// Timepoints that must strictly follow `t` by a constraint between them (`s − t ≥ 1` stated directly).
    pub fn successors(&self, t: Timepoint) -> impl Iterator<Item = Timepoint> + '_ {
        self.strict_neighbours(t, true)
    }

    /// The other ends of the constraints of `t` that put them strictly after `t` (`after`) or strictly
    /// before it.
    fn strict_neighbours(&self, t: Timepoint, after: bool) -> impl Iterator<Item = Timepoint> + '_ {
        self.constraints_of(t).filter_map(move |(_, k)| {
            // The constraint read from t: `other − t ∈ [lo, hi]`.
            let (other, lo, hi) = if k.from == t {
                (k.to, k.lb, k.ub)
            } else {
                (k.from, -k.ub, -k.lb)
            };
            let strict = if after { lo > 0 } else { hi < 0 };
            (other != t && strict).then_some(other)
        })
    }

    /// Earliest time of `t` (relative to the origin).
    pub fn lb(&self, t: Timepoint) -> Time {
        self.lb[t.index()]
    }

    /// Latest time of `t` (relative to the origin); `INF` if unbounded.
    pub fn ub(&self, t: Timepoint) -> Time {
        self.ub[t.index()]
    }

    /// Removes constraint `c` (relaxation) and recomputes the bounds that depended on it. Removing a removed
    /// constraint does nothing. Removing an execution constraint un-executes its timepoint.
    pub fn remove_constraint(&mut self, c: ConstraintId) {
        if !self.cons[c.index()].active {
            return;
        }
        self.cons[c.index()].active = false;
        self.sync_edges(c.0);
        self.trail.push(Entry::Remove(c.0));
        self.paths_drop();
        let d = &self.cons[c.index()];
        let t = d.to as usize;
        if d.from == 0 && self.executed[t] == Some(c) {
            self.trail.push(Entry::Executed(t as u32, Some(c)));
            self.executed[t] = None;
        }
        self.relax_removed(&[c.0]);
    }

    /// Removes every constraint on `t` (the relaxation of a failed end timepoint); returns them.
    pub fn relax_timepoint(&mut self, t: Timepoint) -> Vec<ConstraintId> {
        let mut removed: Vec<ConstraintId> = self.constraints_of(t).map(|(c, _)| c).collect();
        removed.sort();
        removed.dedup();
        self.paths_drop();
        for c in &removed {
            self.cons[c.index()].active = false;
            self.sync_edges(c.0);
            self.trail.push(Entry::Remove(c.0));
        }
        if let Some(c) = self.executed[t.index()] {
            self.trail.push(Entry::Executed(t.0, Some(c)));
            self.executed[t.index()] = None;
        }
        for c in &removed {
            let d = &self.cons[c.index()];
            if d.from == 0 && d.to != t.0 && self.executed[d.to as usize] == Some(*c) {
                let other = d.to;
                self.trail.push(Entry::Executed(other, Some(*c)));
                self.executed[other as usize] = None;
            }
        }
        let ids: Vec<u32> = removed.iter().map(|c| c.0).collect();
        self.relax_removed(&ids);
        removed
    }

    /// Executes `t` at time `at` (relative to the origin): adds `t − origin ∈ [at, at]`. The returned
    /// constraint can be removed to un-execute. Executing the origin only checks `at == 0`.
    pub fn execute(&mut self, t: Timepoint, at: Time) -> Result<ConstraintId, Inconsistent> {
        let c = self.add_constraint(self.origin(), t, at, at)?;
        if t.0 != 0 && self.executed[t.index()].is_none() {
            self.trail.push(Entry::Executed(t.0, None));
            self.executed[t.index()] = Some(c);
        }
        Ok(c)
    }

    /// Whether `t` has been executed (the origin always is).
    pub fn is_executed(&self, t: Timepoint) -> bool {
        t.0 == 0 || self.executed[t.index()].is_some()
    }

    /// The time `t` was executed at, if it was.
    pub fn executed_at(&self, t: Timepoint) -> Option<Time> {
        if t.0 == 0 {
            return Some(0);
        }
        self.executed[t.index()].map(|c| self.cons[c.index()].ub)
    }

    /// Timepoints not executed whose earliest time is `<= now`.
    pub fn due(&self, now: Time) -> impl Iterator<Item = Timepoint> + '_ {
        self.timepoints()
            .filter(move |t| !self.is_executed(*t) && self.lb(*t) <= now)
    }

    /// Maximum possible `b − a` (the shortest path a→b); `INF` if unbounded. Computed on demand.
    pub fn distance(&self, a: Timepoint, b: Timepoint) -> Time {
        super::distance::distance(self, a.0, b.0)
    }

    /// Whether `distance(a, b) < limit`, answered without computing the distance when it is not
    /// (the form ordering tests need: much cheaper than [`Stn::distance`]).
    pub fn distance_below(&self, a: Timepoint, b: Timepoint, limit: Time) -> bool {
        super::distance::distance_below(self, a.0, b.0, limit)
    }

    /// `distance(a, x)` for every timepoint x (index = timepoint), in one search.
    pub fn distances_from(&self, a: Timepoint) -> Vec<Time> {
        super::distance::all_distances(self, a.0, true)
    }

    /// `distance(x, a)` for every timepoint x (index = timepoint), in one search.
    pub fn distances_to(&self, a: Timepoint) -> Vec<Time> {
        super::distance::all_distances(self, a.0, false)
    }

    /// Possible range of `b − a`: `[-distance(b, a), distance(a, b)]`.
    pub fn delay_bounds(&self, a: Timepoint, b: Timepoint) -> (Time, Time) {
        let back = self.distance(b, a);
        let lo = if back >= INF { -INF } else { -back };
        (lo, self.distance(a, b))
    }

    /// Whether `a` strictly before `b` (`b − a ≥ 1`) is consistent with the network.
    pub fn possibly_before(&self, a: Timepoint, b: Timepoint) -> bool {
        self.distance(a, b) >= 1
    }

    /// Whether every solution has `a` strictly before `b` (`b − a ≥ 1`).
    pub fn necessarily_before(&self, a: Timepoint, b: Timepoint) -> bool {
        self.distance(b, a) <= -1
    }
}
