//! The flaw set F (seed 1 §2.2): open conditions, threats, resource conflicts.
//!
//! Detection is incremental: a threat candidate (event, link) or a unary-resource candidate (use, use) is
//! recorded when the later of the two enters the plan, and a reservoir is marked for re-checking when a usage
//! of it is added. Adding constraints can only resolve a candidate, never revive it, so a candidate found
//! resolved is marked done (on the trail) and never examined again on this branch. After the executive
//! *relaxes* constraints, [`PartialPlan::recompute_candidates`] starts over.

use super::envelope::{reservoir_conflict, ReservoirConflict};
use std::collections::BTreeMap;

use super::order::{necessarily_after, necessarily_after_by_bounds};
use super::{
    ActionId, Candidate, CondId, EventId, LinkId, Owner, PartialPlan, STerm, UsageId, UsageKind,
};
use crate::model::{ResourceId, ResourceKind, Value};
use crate::stn::{Time, Timepoint};

/// A flaw of the partial plan.
#[derive(Clone, Debug, PartialEq)]
pub enum Flaw {
    /// A condition (hold, event `from`, goal) without a causal link.
    OpenCondition(CondId),
    /// `event` may change the value protected by `link` inside its interval.
    Threat { event: EventId, link: LinkId },
    /// Two borrowings of a unary resource may overlap.
    UnaryConflict { a: UsageId, b: UsageId },
    /// A reservoir's level may leave `[0, capacity]`.
    Reservoir(ReservoirConflict),
}

/// A threat candidate's event (or link) with at least this many candidates undecided by the bounds has them
/// decided by one pair of shortest-path trees rather than one search each — unless the network keeps its
/// matrix of paths: a query is then a look-up, and a tree a whole row or column of it.
const BATCH: usize = 16;

/// The timepoints whose order decides a threat candidate: the threatening event's, the link's
/// establisher's, and the end of the protected condition (with its delay).
#[derive(Copy, Clone, Debug)]
struct ThreatWindow {
    event: Timepoint,
    establisher: Timepoint,
    cond_end: Timepoint,
    end_delay: Time,
}

fn threat_verdict(resolved: bool) -> ThreatCheck {
    if resolved {
        ThreatCheck::Resolved
    } else {
        ThreatCheck::Threat
    }
}

/// Whether a threat candidate is (still) a threat.
#[derive(Copy, Clone, Eq, PartialEq, Debug)]
pub enum ThreatCheck {
    Threat,
    /// Resolved for good on this branch (separated in time or in value / attribute instance).
    Resolved,
    /// Not applicable now (owner removed, link inactive); may be re-examined after a recompute.
    Inactive,
}

impl PartialPlan {
    /// Whether `e` threatens `l`: same attribute instance possibly, a value possibly different from the
    /// protected one, and possibly inside `[establisher, end of the condition]`.
    pub fn check_threat(&self, e: EventId, l: LinkId) -> ThreatCheck {
        match self.threat_window(e, l) {
            Err(check) => check,
            Ok(w) => self.window_verdict(&w),
        }
    }

    /// Whether the order of a threat candidate's timepoints resolves it.
    fn window_verdict(&self, w: &ThreatWindow) -> ThreatCheck {
        threat_verdict(
            necessarily_after(&self.stn, w.event, w.establisher, 1)
                || necessarily_after(&self.stn, w.cond_end, w.event, w.end_delay),
        )
    }

    /// Whether `e` can never threaten `l`, whatever happens to the plan: `e` establishes `l`, or `l` supports
    /// `e`'s own prior value. Such candidates are marked done (a flaw pass would otherwise re-examine one per
    /// link at every step).
    fn never_threatens(&self, e: EventId, l: LinkId) -> bool {
        let link = self.link(l);
        e == link.event || self.cond(link.cond).kind == super::CondKind::Before(e)
    }

    /// The non-temporal part of [`Self::check_threat`]: `Err` with the answer when it decides, otherwise the
    /// timepoints whose order decides.
    fn threat_window(&self, e: EventId, l: LinkId) -> Result<ThreatWindow, ThreatCheck> {
        let link = self.link(l);
        if !link.active || !self.cond_live(link.cond) || e == link.event || !self.event_in_effect(e)
        {
            return Err(ThreatCheck::Inactive);
        }
        let cond = self.cond(link.cond);
        if cond.kind == super::CondKind::Before(e) {
            return Err(ThreatCheck::Inactive);
        }
        let ev = self.event(e);
        let b = &self.bindings;
        if ev
            .args
            .iter()
            .zip(&cond.args)
            .any(|(&x, &y)| !b.possibly_equal(x, y))
            || b.necessarily_equal(ev.to, cond.value)
        {
            return Err(ThreatCheck::Resolved);
        }
        Ok(ThreatWindow {
            event: ev.at,
            establisher: self.event(link.event).at,
            cond_end: cond.to,
            end_delay: cond.end_delay(),
        })
    }

    /// Whether two borrowings of a unary resource may overlap (`Some(true)`), are ordered for good
    /// (`Some(false)`), or are not comparable now (`None`).
    pub fn check_unary(&self, a: UsageId, b: UsageId) -> Option<bool> {
        let (ua, ub) = (self.usage(a), self.usage(b));
        if self.action(ua.action).removed || self.action(ub.action).removed {
            return None;
        }
        let (UsageKind::Use { from: fa, to: ta }, UsageKind::Use { from: fb, to: tb }) =
            (ua.kind, ub.kind)
        else {
            return Some(false);
        };
        Some(!(necessarily_after(&self.stn, ta, fb, 0) || necessarily_after(&self.stn, tb, fa, 0)))
    }

    /// The live threats (marks resolved candidates done).
    ///
    /// Candidates the bounds cannot decide are answered by shortest paths; when one event has many of them
    /// (a new action's events, a plan just built, or candidates recomputed by the executive: ~n per event),
    /// two searches from that event answer them all instead of one search per candidate; likewise two
    /// searches from a link's ends for a new link's candidates. The answers are the same. With the matrix of
    /// paths kept, each is answered by its look-ups at once.
    pub fn live_threats(&mut self) -> Vec<(EventId, LinkId)> {
        let pending = self.threats.pending();
        let mut verdicts: Vec<(usize, ThreatCheck)> = Vec::with_capacity(pending.len());
        let mut open: Vec<(usize, ThreatWindow)> = Vec::new();
        let paths = self.stn.has_paths();
        for i in pending {
            let c = self.threats.get(i);
            if self.never_threatens(c.a, c.b) {
                verdicts.push((i, ThreatCheck::Resolved));
                continue;
            }
            let w = match self.threat_window(c.a, c.b) {
                Err(check) => {
                    verdicts.push((i, check));
                    continue;
                }
                Ok(w) => w,
            };
            let stn = &self.stn;
            let first = necessarily_after_by_bounds(stn, w.event, w.establisher, 1);
            let second = necessarily_after_by_bounds(stn, w.cond_end, w.event, w.end_delay);
            match (first, second) {
                (Some(true), _) | (_, Some(true)) => verdicts.push((i, ThreatCheck::Resolved)),
                (Some(false), Some(false)) => verdicts.push((i, ThreatCheck::Threat)),
                _ if paths => verdicts.push((i, self.window_verdict(&w))),
                _ => open.push((i, w)),
            }
        }
        // The candidates the bounds leave open, answered in batches: those sharing an event (a new action's
        // events against the links already there), then those sharing a link (a new link against the
        // events already there), then one by one.
        let mut by_event: BTreeMap<EventId, Vec<(usize, ThreatWindow)>> = BTreeMap::new();
        for (i, w) in open {
            by_event
                .entry(self.threats.get(i).a)
                .or_default()
                .push((i, w));
        }
        let mut by_link: BTreeMap<LinkId, Vec<(usize, ThreatWindow)>> = BTreeMap::new();
        for group in by_event.into_values() {
            if group.len() < BATCH {
                for (i, w) in group {
                    by_link
                        .entry(self.threats.get(i).b)
                        .or_default()
                        .push((i, w));
                }
                continue;
            }
            // d(x, event) and d(event, x) for every x: the event is necessarily before the establisher iff
            // d(establisher, event) < 0, and after the condition's end (by end_delay) iff
            // d(event, cond_end) < 1 − end_delay (see `necessarily_after`).
            let at = group[0].1.event;
            let (to, from) = (self.stn.distances_to(at), self.stn.distances_from(at));
            for (i, w) in group {
                let resolved =
                    to[w.establisher.index()] < 0 || from[w.cond_end.index()] < 1 - w.end_delay;
                verdicts.push((i, threat_verdict(resolved)));
            }
        }
        for group in by_link.into_values() {
            if group.len() < BATCH {
                for (i, _) in group {
                    let c = self.threats.get(i);
                    verdicts.push((i, self.check_threat(c.a, c.b)));
                }
                continue;
            }
            // The same two distances, from the link's establisher and to its condition's end.
            let (est, end) = (group[0].1.establisher, group[0].1.cond_end);
            let (from_est, to_end) = (self.stn.distances_from(est), self.stn.distances_to(end));
            for (i, w) in group {
                let resolved =
                    from_est[w.event.index()] < 0 || to_end[w.event.index()] < 1 - w.end_delay;
                verdicts.push((i, threat_verdict(resolved)));
            }
        }
        verdicts.sort_unstable_by_key(|&(i, _)| i);
        let mut out = Vec::new();
        for (i, check) in verdicts {
            let c = self.threats.get(i);
            match check {
                ThreatCheck::Threat => out.push((c.a, c.b)),
                ThreatCheck::Resolved => self.mark_threat_done(i),
                ThreatCheck::Inactive => {}
            }
        }
        out
    }

    /// The threat candidates not resolved yet (indices, in the order they were recorded).
    pub(crate) fn threat_candidates(&mut self) -> Vec<usize> {
        self.threats.pending()
    }

    /// The event and the link of threat candidate `i`.
    pub(crate) fn threat_pair(&self, i: usize) -> (EventId, LinkId) {
        let Candidate { a, b, .. } = self.threats.get(i);
        (a, b)
    }

    /// [`Self::check_threat`] of candidate `i`, marked done when resolved for good.
    pub(crate) fn threat_live(&mut self, i: usize) -> ThreatCheck {
        let (e, l) = self.threat_pair(i);
        let check = if self.never_threatens(e, l) {
            ThreatCheck::Resolved
        } else {
            self.check_threat(e, l)
        };
        if check == ThreatCheck::Resolved {
            self.mark_threat_done(i);
        }
        check
    }

    /// The live unary-resource conflicts (marks resolved candidates done).
    pub fn live_unary_conflicts(&mut self) -> Vec<(UsageId, UsageId)> {
        let mut out = Vec::new();
        for i in self.unary_candidates() {
            if self.unary_live(i) == Some(true) {
                out.push(self.unary_pair(i));
            }
        }
        out
    }

    /// The unary-resource candidates not resolved yet (indices, in the order they were recorded).
    pub(crate) fn unary_candidates(&mut self) -> Vec<usize> {
        self.unary.pending()
    }

    /// The two borrowings of unary candidate `i`.
    pub(crate) fn unary_pair(&self, i: usize) -> (UsageId, UsageId) {
        let Candidate { a, b, .. } = self.unary.get(i);
        (a, b)
    }

    /// [`Self::check_unary`] of candidate `i`, marked done when ordered for good.
    pub(crate) fn unary_live(&mut self, i: usize) -> Option<bool> {
        let (a, b) = self.unary_pair(i);
        let live = self.check_unary(a, b);
        if live == Some(false) {
            self.mark_unary_done(i);
        }
        live
    }

    /// The reservoir conflicts (re-checks the reservoirs marked dirty, marks clean ones).
    pub fn reservoir_conflicts(&mut self) -> Vec<ReservoirConflict> {
        self.reservoir_conflicts_of(|_| true)
    }

    /// The reservoir conflicts of the dirty reservoirs `wanted` selects (the planner skips those it would
    /// not resolve now: the envelope costs a quadratic number of ordering queries).
    pub fn reservoir_conflicts_of(
        &mut self,
        wanted: impl Fn(ResourceId) -> bool,
    ) -> Vec<ReservoirConflict> {
        let mut out = Vec::new();
        for r in 0..self.reservoir_dirty.len() {
            let id = ResourceId::from_index(r);
            if !self.reservoir_dirty[r] || !wanted(id) {
                continue;
            }
            // Unary resources have their own pairwise conflicts.
            if self.domain.resources[r].kind == ResourceKind::Unary {
                self.set_reservoir_dirty(r, false);
                continue;
            }
            match reservoir_conflict(self, id) {
                Some(c) => out.push(c),
                None => self.set_reservoir_dirty(r, false),
            }
        }
        out
    }

    /// The whole flaw set F.
    pub fn flaws(&mut self) -> Vec<Flaw> {
        let mut out: Vec<Flaw> = self
            .live_threats()
            .into_iter()
            .map(|(event, link)| Flaw::Threat { event, link })
            .collect();
        out.extend(
            self.live_unary_conflicts()
                .into_iter()
                .map(|(a, b)| Flaw::UnaryConflict { a, b }),
        );
        out.extend(self.reservoir_conflicts().into_iter().map(Flaw::Reservoir));
        out.extend(self.open_conditions().map(Flaw::OpenCondition));
        out
    }

    /// A_t^f for one flaw (seed 1 footnote 6): the action of an open condition; for a threat, the
    /// threatening action and the action whose condition is threatened; the actions of a resource conflict.
    pub fn involved_actions(&self, flaw: &Flaw) -> Vec<ActionId> {
        let mut out = Vec::new();
        match flaw {
            Flaw::OpenCondition(c) => out.extend(self.cond(*c).owner.action()),
            Flaw::Threat { event, link } => {
                out.extend(self.event(*event).owner.action());
                out.extend(self.cond(self.link(*link).cond).owner.action());
            }
            Flaw::UnaryConflict { a, b } => {
                out.push(self.usage(*a).action);
                out.push(self.usage(*b).action);
            }
            Flaw::Reservoir(c) => {
                out.push(self.usage(c.at).action);
                for (u, _) in c.open_decreases.iter().chain(&c.open_increases) {
                    out.push(self.usage(*u).action);
                }
            }
        }
        out.sort();
        out.dedup();
        out
    }

    /// Definition 5 (executable plan): the constraint networks are consistent (the plan never holds an
    /// inconsistent network: inconsistent changes are refused) and no running action is involved in a flaw.
    pub fn executable(&mut self, running: &[ActionId]) -> bool {
        if running.is_empty() {
            return true;
        }
        self.flaws().iter().all(|f| {
            self.involved_actions(f)
                .iter()
                .all(|a| !running.contains(a))
        })
    }

    /// Forgets the incremental detection state and rebuilds every candidate (after relaxations by the
    /// executive). Trail levels saved before this call must not be restored afterwards.
    pub(crate) fn recompute_candidates(&mut self) {
        self.threats.clear();
        self.unary.clear();
        for attr in 0..self.events_by_attr.len() {
            for &e in &self.events_by_attr[attr] {
                for &l in &self.links_by_attr[attr] {
                    self.threats.push(e, l);
                }
            }
        }
        for r in 0..self.usages_by_res.len() {
            let unary = self.domain.resources[r].kind == ResourceKind::Unary;
            if unary {
                let us = &self.usages_by_res[r];
                for i in 0..us.len() {
                    for j in i + 1..us.len() {
                        self.unary.push(us[i], us[j]);
                    }
                }
            }
            self.reservoir_dirty[r] = true;
        }
    }

    /// A readable description of a term.
    pub fn term_name(&self, t: STerm) -> String {
        match self.bindings.value(t) {
            Some(Value::Obj(o)) => self.problem.object_name(o).to_string(),
            Some(Value::Unknown) => "+oo".into(),
            None => match t {
                STerm::Var(v) => {
                    let names: Vec<&str> = self
                        .bindings
                        .domain(v)
                        .iter()
                        .map(|&o| self.problem.object_name(o))
                        .collect();
                    format!("?v{}{{{}}}", v.0, names.join(","))
                }
                _ => "?".into(),
            },
        }
    }

    /// `ATTR(args) = value` of a condition.
    pub fn cond_text(&self, c: CondId) -> String {
        let cond = self.cond(c);
        let args: Vec<String> = cond.args.iter().map(|&a| self.term_name(a)).collect();
        format!(
            "{}({}) = {}",
            self.domain.attr(cond.attr).name,
            args.join(", "),
            self.term_name(cond.value)
        )
    }

    /// Who owns a condition or event, for messages.
    pub fn owner_text(&self, o: Owner) -> String {
        match o {
            Owner::Initial => "the initial state".into(),
            Owner::Exogenous(i) => format!("timed fact #{i}"),
            Owner::Goal(g) => format!(
                "goal {}",
                self.problem
                    .goals
                    .get(g.index())
                    .map_or("?", |g| g.name.as_str())
            ),
            Owner::Action(a) => format!("{}#{}", self.domain.task(self.action(a).task).name, a.0),
        }
    }

    /// A one-line description of a flaw (for failure reasons and traces).
    pub fn flaw_text(&self, f: &Flaw) -> String {
        match f {
            Flaw::OpenCondition(c) => format!(
                "open condition {} of {}",
                self.cond_text(*c),
                self.owner_text(self.cond(*c).owner)
            ),
            Flaw::Threat { event, link } => format!(
                "threat: event of {} on {}",
                self.owner_text(self.event(*event).owner),
                self.cond_text(self.link(*link).cond)
            ),
            Flaw::UnaryConflict { a, b } => format!(
                "unary resource {} used by {} and {} at once",
                self.domain.resource(self.usage(*a).resource).name,
                self.owner_text(Owner::Action(self.usage(*a).action)),
                self.owner_text(Owner::Action(self.usage(*b).action))
            ),
            Flaw::Reservoir(c) => format!(
                "reservoir {} may {} (level bound {:.2}, capacity {:.2}) at {}",
                self.domain.resource(c.resource).name,
                if c.overflow { "overflow" } else { "run out" },
                c.level,
                c.capacity,
                self.owner_text(Owner::Action(self.usage(c.at).action))
            ),
        }
    }
}
