//! Reservoir conflicts (seed 1 §2.2 "resource conflicts"; Laborie & Ghallab 1995) detected by a **sound
//! level envelope over the partial order**, not on one schedule.
//!
//! Each usage is a change of the level at a timepoint: a consumption `−q` at `at`, a production `+q`, a
//! borrowing (`use`) `−q` at its start and `+q` at its end. At each decrease `i`, the lowest level any
//! schedule can reach just after `i` is at least
//!
//! `L0 + Σ_{increases j necessarily < i} q_min(j) − Σ_{decreases j possibly ≤ i (i included)} q_max(j)`,
//!
//! and at each increase `i`, the highest level is at most
//!
//! `L0 + Σ_{increases j possibly ≤ i (i included)} q_max(j) − Σ_{decreases j necessarily < i} q_min(j)`.
//!
//! (Changes at the same instant are taken in their worst order, as the checker does.) A saturating
//! production (`saturating produce`) is clipped at the capacity: it never overflows, and its quantity
//! interval is first narrowed to what it can add whatever the order ([`clip_saturating`]).
//!
//! Levels only change at these instants, so if every bound is within `[0, capacity]` every schedule of the
//! partial plan (every instantiation of the quantities) keeps the level inside: no conflict is missed.
//! A violation names the checkpoint and the usages whose ordering is still open — the resolvers.

use super::order::{necessarily_after, possibly_after};
use super::{NTerm, PartialPlan, UsageId, UsageKind};
use crate::model::ResourceId;
use crate::stn::Timepoint;

/// A reservoir whose level may leave `[0, capacity]`.
#[derive(Clone, Debug, PartialEq)]
pub struct ReservoirConflict {
    pub resource: ResourceId,
    /// The usage at whose instant the level may leave its bounds.
    pub at: UsageId,
    pub point: Timepoint,
    /// `true`: the level may exceed the capacity (over-production); `false`: it may drop below 0.
    pub overflow: bool,
    /// The pessimistic level bound at `point`.
    pub level: f64,
    pub capacity: f64,
    /// Decreases (usages, timepoints) possibly but not necessarily (strictly) before `point`.
    pub open_decreases: Vec<(UsageId, Timepoint)>,
    /// Increases possibly but not necessarily before `point`.
    pub open_increases: Vec<(UsageId, Timepoint)>,
    /// Increases necessarily before `point` (or at it) whose quantity is not fixed: counted at their
    /// minimum in a shortage, they can be made to produce more.
    pub short_producers: Vec<UsageId>,
    /// In a shortage, for each saturating production necessarily before `point`, the decreases that may
    /// still come between it and `point` (pairs: decrease, production): each, ordered before the
    /// production, may be absorbed by the refill (a download after three pictures frees their room
    /// whatever their sizes).
    pub refill: Option<Vec<(Timepoint, Timepoint)>>,
    /// In a shortage, the saturating production that gives the best bound when it refills the whole
    /// capacity whatever it finds (a download that sends every stored image): a producer inserted before it
    /// cannot help, so one is inserted after it.
    pub reset: Option<Timepoint>,
}

/// Numeric tolerance on levels: the checker's.
const EPS: f64 = crate::model::LEVEL_TOLERANCE;

struct Change {
    usage: UsageId,
    at: Timepoint,
    up: bool,
    lo: f64,
    hi: f64,
    /// A saturating production: clipped at the capacity, never an overflow.
    saturating: bool,
    /// The quantity's lower bound before [`clip_saturating`].
    raw_lo: f64,
}

/// The first checkpoint (earliest lower bound) where reservoir `r`'s envelope leaves `[0, capacity]`.
pub fn reservoir_conflict(plan: &PartialPlan, r: ResourceId) -> Option<ReservoirConflict> {
    let setup = plan.problem.resource(r)?;
    let l0 = setup.level;
    // The lowest capacity of the availability profile: sound whatever the checkpoint's time.
    let capacity = if setup.profile.is_empty() {
        plan.domain.resource(r).capacity
    } else {
        setup
            .profile
            .iter()
            .map(|&(_, c)| c)
            .fold(f64::INFINITY, f64::min)
    };
    let mut changes: Vec<Change> = Vec::new();
    for &u in plan.usages_of(r) {
        let us = plan.usage(u);
        if plan.action(us.action).removed {
            continue;
        }
        let (lo, hi) = match us.quantity {
            NTerm::Var(v) => plan.numeric.bounds(v),
            NTerm::Const(c) => (c, c),
        };
        let saturating = us.saturating;
        let mut push = |at, up| {
            changes.push(Change {
                usage: u,
                at,
                up,
                lo,
                hi,
                saturating,
                raw_lo: lo,
            })
        };
        match us.kind {
            UsageKind::Consume { at } => push(at, false),
            UsageKind::Produce { at } => push(at, true),
            UsageKind::Use { from, to } => {
                push(from, false);
                push(to, true);
            }
        }
    }
    let stn = &plan.stn;
    let mut rel = Relations::new(stn, &changes);
    clip_saturating(&mut rel, l0, capacity, &mut changes);
    let mut order: Vec<usize> = (0..changes.len()).collect();
    order.sort_by_key(|&i| (stn.lb(changes[i].at), i));
    for &i in &order {
        let ci = &changes[i];
        let mut level = l0;
        let mut open_dec = Vec::new();
        let mut open_inc = Vec::new();
        let mut short_producers = Vec::new();
        for (j, cj) in changes.iter().enumerate() {
            let nec = j == i || rel.before(j, i);
            let poss = nec || rel.possibly_before(j, i);
            if ci.up {
                if cj.up && poss {
                    level += cj.hi;
                } else if !cj.up && nec {
                    level -= cj.lo;
                }
            } else if cj.up && nec {
                level += cj.lo;
                if cj.lo < cj.hi {
                    short_producers.push(cj.usage);
                }
            } else if !cj.up && poss {
                level -= cj.hi;
            }
            if poss && !nec {
                if cj.up {
                    open_inc.push((cj.usage, cj.at));
                } else {
                    open_dec.push((cj.usage, cj.at));
                }
            }
        }
        let mut refill = None;
        let mut reset = None;
        if !ci.up && level < -EPS {
            if let Some(r) = best_refill(&mut rel, l0, capacity, &changes, i) {
                if r.bound > level {
                    level = r.bound;
                    reset = r.reset;
                }
                refill = Some(r.pairs);
            }
        }
        let violated = if ci.up {
            !ci.saturating && level > capacity + EPS
        } else {
            level < -EPS
        };
        if violated {
            return Some(ReservoirConflict {
                resource: r,
                at: ci.usage,
                point: ci.at,
                overflow: ci.up,
                level,
                capacity,
                open_decreases: open_dec,
                open_increases: open_inc,
                short_producers,
                refill,
                reset,
            });
        }
    }
    None
}

/// A saturating production adds `min(q, capacity − L)` to the level L it finds. Its quantity interval is
/// narrowed, soundly, to what it can add whatever the order the plan still allows: at least
/// `min(q_lo, capacity − UB)` and at most `min(q_hi, capacity − LB)`, with `[LB, UB]` the pessimistic level
/// bounds just before it (other saturating productions count at most their `q_hi` above and nothing below).
fn clip_saturating(rel: &mut Relations, l0: f64, capacity: f64, changes: &mut [Change]) {
    let clipped: Vec<(usize, f64, f64)> = changes
        .iter()
        .enumerate()
        .filter(|(_, c)| c.up && c.saturating)
        .map(|(i, ci)| {
            if ci.lo >= capacity - EPS {
                // A refill of the whole capacity: it adds between nothing and everything, and
                // [`best_refill`] knows the level after it exactly; no need for the quadratic bounds.
                return (i, 0.0, capacity);
            }
            let (mut lb, mut ub) = (l0, l0);
            for (j, cj) in changes.iter().enumerate() {
                if j == i {
                    continue;
                }
                let nec = rel.before(j, i);
                let poss = nec || rel.possibly_before(j, i);
                if cj.up {
                    if poss {
                        ub += cj.hi;
                    }
                    if nec && !cj.saturating {
                        lb += cj.lo;
                    }
                } else {
                    if nec {
                        ub -= cj.lo;
                    }
                    if poss {
                        lb -= cj.hi;
                    }
                }
            }
            let lo = ci.lo.min(capacity - ub.min(capacity)).max(0.0);
            let hi = ci.hi.min(capacity - lb.clamp(0.0, capacity)).max(lo);
            (i, lo, hi)
        })
        .collect();
    for (i, lo, hi) in clipped {
        changes[i].lo = lo;
        changes[i].hi = hi;
    }
}

/// The best lower bound of the level just after decrease `i` that a saturating production P necessarily
/// before it gives. Whatever the order of the decreases D not yet ordered before P, the level just after `i`
/// is at least `min(LB_P + q_lo(P), capacity) − Σ q_max(D)` (a D before P can only lower the refill's
/// starting point by what it would have cost after P), with `LB_P` the bound from the changes necessarily
/// before P. Returns the best bound over the productions P, and for every P the pairs (D, P) of the D other
/// than `i`: each one ordered before P may be absorbed by the refill.
fn best_refill(
    rel: &mut Relations,
    l0: f64,
    capacity: f64,
    changes: &[Change],
    i: usize,
) -> Option<Refill> {
    let mut best: Option<(f64, Option<Timepoint>)> = None;
    let mut pairs = Vec::new();
    let anchors: Vec<usize> = changes
        .iter()
        .enumerate()
        .filter(|&(p, cp)| p != i && cp.up && cp.saturating)
        .map(|(p, _)| p)
        .filter(|&p| rel.before(p, i))
        .collect();
    let is_reset = |c: &Change| c.raw_lo >= capacity - EPS;
    for &p in &anchors {
        let cp = &changes[p];
        // A production followed, before `i`, by a refill of the whole capacity gives a weaker bound
        // than that refill (its base is lower and more decreases may follow it): skip it. This keeps
        // the anchors to the last refills before `i`, one or two, instead of every earlier one.
        if anchors
            .iter()
            .any(|&q| q != p && is_reset(&changes[q]) && rel.before(p, q))
        {
            continue;
        }
        let mut before = l0;
        let mut after = 0.0;
        for (j, cj) in changes.iter().enumerate() {
            if j == p {
                continue;
            }
            let nec_before_p = rel.before(j, p);
            if cj.up {
                if nec_before_p {
                    before += cj.lo;
                } else if rel.before(p, j) && rel.before(j, i) {
                    after += cj.lo;
                }
            } else if nec_before_p {
                before -= cj.hi;
            } else if j == i || rel.possibly_before(j, i) {
                after -= cj.hi;
                if j != i {
                    pairs.push((cj.at, cp.at));
                }
            }
        }
        // The level before P is taken as at least 0: a schedule where it is lower runs out at an earlier
        // decrease, whose own checkpoint reports it (the first violation of any schedule is caught there).
        let bound = (before.max(0.0) + cp.raw_lo).min(capacity) + after;
        if best.is_none_or(|(b, _)| bound > b) {
            let reset = (cp.raw_lo >= capacity - EPS).then_some(cp.at);
            best = Some((bound, reset));
        }
    }
    best.map(|(bound, reset)| Refill {
        bound,
        pairs,
        reset,
    })
}

/// What the saturating productions before a decrease guarantee ([`best_refill`]).
struct Refill {
    bound: f64,
    pairs: Vec<(Timepoint, Timepoint)>,
    /// The best one's instant when it refills the whole capacity.
    reset: Option<Timepoint>,
}

/// The ordering questions of one envelope pass between its changes, each asked of the network once: the
/// pass and its refill bounds ask the same pairs over and over.
struct Relations<'a> {
    stn: &'a crate::stn::Stn,
    at: Vec<Timepoint>,
    /// `n × n`, row `j`, column `i`: 0 unknown, 1 no, 2 yes.
    before: Vec<u8>,
    possibly: Vec<u8>,
}

impl<'a> Relations<'a> {
    fn new(stn: &'a crate::stn::Stn, changes: &[Change]) -> Self {
        let n = changes.len();
        Relations {
            stn,
            at: changes.iter().map(|c| c.at).collect(),
            before: vec![0; n * n],
            possibly: vec![0; n * n],
        }
    }

    fn cached(slot: &mut u8, ask: impl FnOnce() -> bool) -> bool {
        if *slot == 0 {
            *slot = if ask() { 2 } else { 1 };
        }
        *slot == 2
    }

    /// Change `j` necessarily strictly before change `i`.
    fn before(&mut self, j: usize, i: usize) -> bool {
        let (stn, a, b) = (self.stn, self.at[j], self.at[i]);
        let k = j * self.at.len() + i;
        Self::cached(&mut self.before[k], || necessarily_after(stn, a, b, 1))
    }

    /// Change `j` possibly at or before change `i`.
    fn possibly_before(&mut self, j: usize, i: usize) -> bool {
        let (stn, a, b) = (self.stn, self.at[j], self.at[i]);
        let k = j * self.at.len() + i;
        Self::cached(&mut self.possibly[k], || possibly_after(stn, a, b, 0))
    }
}
