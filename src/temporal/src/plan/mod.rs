//! The plan: the planner's partial plan P = (A, C, L, F), its output ([`solution`]) and the independent
//! checker ([`validate`], which shares no code with the search).
//!
//! The partial plan P = (A, C, L, F) of seed 1 §2.2, with the extra state the executive needs (§3.1).
//!
//! - **A**: [`Action`]s, task instances with their timepoints in the STN, their symbolic variables in the
//!   binding CSP, their numeric variables, and the [`EventRec`]s, [`Condition`]s and [`Usage`]s they bring.
//!   The initial state and the predicted timed facts are events of the pseudo-owners [`Owner::Initial`] and
//!   [`Owner::Exogenous`] (at / after the origin); goals are conditions (holds) of [`Owner::Goal`].
//! - **C**: the [`Stn`], the [`Bindings`] CSP and the [`Numeric`] CSP.
//! - **L**: [`CausalLink`]s from an establishing event to a condition on the same attribute instance,
//!   protected over an interval (see [`Condition`] for the exact semantics).
//! - **F**: [`Flaw`]s, detected incrementally (see [`flaws`]).
//!
//! Everything is trailed: [`PartialPlan::save`] / [`PartialPlan::restore`] undo any number of changes in
//! time proportional to the changes, so the search never clones a plan. Structural changes are appended to a
//! change log ([`PlanChange`]) that also records their undoing on backtrack (for the dispatcher's incremental
//! marking, seed 2 Algorithms 3–8).
//!
//! Semantics shared with the checker: an event at `t` takes effect at `t` (the value is `to` from `t` on,
//! `from` just before `t`); an action's hold over `(st, et)` asserts the value on `[st, et[` (so the action's
//! own event at `et` may change it), an instantaneous hold or a goal's hold asserts it on `[st, et]`.

mod bindings;
mod build;
mod candidates;
mod changes;
mod envelope;
mod exec_edits;
mod export;
pub mod flaws;
mod numeric;
mod order;
pub mod solution;
mod stnu;
pub mod validate;
mod withdraw;

use std::sync::Arc;

use backtrack::{Level, Trail};
use serde::Serialize;

pub use bindings::{BindingConflict, Bindings, STerm, VarId};
pub use changes::{ChangeCursor, LinkEnds, PlanChange};
pub use envelope::{reservoir_conflict, ReservoirConflict};
pub use flaws::{Flaw, ThreatCheck};
pub use numeric::{NTerm, NVar, NumConflict, NumCons, Numeric};
pub use stnu::{DcPlan, NotControllable, PlanLink, PlanStnu};

use crate::model::{AttrId, Domain, GoalId, Problem, ResourceId, TaskId, Time};
use crate::stn::{ConstraintId, Inconsistent, Stn, Timepoint};

macro_rules! plan_id {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Copy, Clone, Eq, PartialEq, Ord, PartialOrd, Hash, Debug, Serialize)]
        pub struct $name(pub u32);
        impl $name {
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }
    };
}

plan_id!(
    /// An action (task instance) of the plan.
    ActionId
);
plan_id!(
    /// An event (instantaneous change of a logical attribute instance).
    EventId
);
plan_id!(
    /// A condition: a hold, the `from` value of an event, or a goal.
    CondId
);
plan_id!(
    /// A causal link.
    LinkId
);
plan_id!(
    /// A resource usage (use / consume / produce).
    UsageId
);

/// Who brings an event or a condition.
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug, Serialize)]
pub enum Owner {
    /// The initial state (events at the origin).
    Initial,
    /// A predicted timed fact of the problem (index in [`Problem::exogenous`]).
    Exogenous(usize),
    Action(ActionId),
    Goal(GoalId),
}

impl Owner {
    pub fn action(self) -> Option<ActionId> {
        match self {
            Owner::Action(a) => Some(a),
            _ => None,
        }
    }
}

/// A task instance.
#[derive(Clone, Debug)]
pub struct Action {
    pub task: TaskId,
    /// One plan variable per task symbolic variable (parameters first).
    pub vars: Vec<VarId>,
    /// One numeric variable per task numeric variable.
    pub nums: Vec<NVar>,
    /// One STN timepoint per task timepoint.
    pub tps: Vec<Timepoint>,
    pub start: Timepoint,
    pub end: Timepoint,
    pub events: Vec<EventId>,
    pub conds: Vec<CondId>,
    pub usages: Vec<UsageId>,
    pub num_cons: Vec<NumCons>,
    /// Removed from the plan by the executive (past action) — its effects stay as events.
    pub removed: bool,
    /// How many insertions of the same task, each made for the `from` condition of the previous one, lead
    /// to this action (0 when it was inserted for anything else): the planner bounds such regressions.
    pub regress: u32,
}

/// An event `attr(args): (from, to)` at `at`.
#[derive(Clone, Debug)]
pub struct EventRec {
    pub owner: Owner,
    pub attr: AttrId,
    pub args: Vec<STerm>,
    /// The condition on the value just before `at` (`None` for initial and exogenous events).
    pub cond: Option<CondId>,
    pub to: STerm,
    pub at: Timepoint,
    /// Primary effect (may justify inserting its task).
    pub primary: bool,
}

/// What a condition asks for.
#[derive(Copy, Clone, Eq, PartialEq, Debug)]
pub enum CondKind {
    /// `hold(attr(args): value, (from, to))`; `closed` when the value must still hold at `to` (goals,
    /// instantaneous holds), else it holds on `[from, to[`.
    Hold { closed: bool },
    /// The value just before the event `EventId` (its `from`), at `from == to == event time`.
    Before(EventId),
}

/// A condition (an open condition while `link` is `None`).
#[derive(Clone, Debug)]
pub struct Condition {
    pub owner: Owner,
    pub attr: AttrId,
    pub args: Vec<STerm>,
    pub value: STerm,
    pub from: Timepoint,
    pub to: Timepoint,
    pub kind: CondKind,
    pub link: Option<LinkId>,
}

impl Condition {
    /// The minimal delay `from − establisher` (0 for a hold, 1 for an event's `from`: strictly before).
    pub fn support_delay(&self) -> Time {
        match self.kind {
            CondKind::Hold { .. } => 0,
            CondKind::Before(_) => 1,
        }
    }

    /// The minimal delay `threat − to` for an event after the protected interval (1 when `to` is included).
    pub fn end_delay(&self) -> Time {
        match self.kind {
            CondKind::Hold { closed: false } if self.from != self.to => 0,
            _ => 1,
        }
    }
}

/// A causal link `event → cond`: the value of `cond` is established by `event` and protected from
/// `event.at` to `cond.to`.
#[derive(Clone, Debug)]
pub struct CausalLink {
    pub event: EventId,
    pub cond: CondId,
    /// The precedence `event.at → cond.from` (None when both are the same timepoint).
    pub precedence: Option<ConstraintId>,
    pub active: bool,
}

/// What a usage does, on plan timepoints.
#[derive(Copy, Clone, Eq, PartialEq, Debug)]
pub enum UsageKind {
    Use { from: Timepoint, to: Timepoint },
    Consume { at: Timepoint },
    Produce { at: Timepoint },
}

/// A resource usage of an action.
#[derive(Clone, Debug)]
pub struct Usage {
    pub action: ActionId,
    pub resource: ResourceId,
    pub kind: UsageKind,
    pub quantity: NTerm,
    /// A saturating production (see [`crate::model::ResourceUsage::saturating`]).
    pub saturating: bool,
}

/// A goal in the plan: its timepoints and its condition.
#[derive(Clone, Debug)]
pub struct PlanGoal {
    pub goal: GoalId,
    pub st: Timepoint,
    pub et: Timepoint,
    pub cond: CondId,
    pub active: bool,
}

/// Where new timepoints go (seed 1 §3.4: after the end of the current cycle; §3.6: after T_end).
#[derive(Copy, Clone, Eq, PartialEq, Debug, Default)]
pub enum TimeFloor {
    #[default]
    None,
    /// `t − origin ≥ time`.
    At(Time),
    /// `t` after this timepoint (strictly).
    After(Timepoint),
}

/// Why a change to the plan was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PlanError {
    #[error(transparent)]
    Temporal(#[from] Inconsistent),
    #[error(transparent)]
    Binding(#[from] BindingConflict),
    #[error(transparent)]
    Numeric(#[from] NumConflict),
    #[error("{0}")]
    Invalid(String),
    /// A flaw left without any resolver (found while propagating forced resolvers).
    #[error("dead end: no resolver left for {0}")]
    DeadEnd(String),
}

#[derive(Clone, Debug)]
enum Entry {
    CondLink(CondId, Option<LinkId>),
    LinkActive(LinkId, bool),
    ActionRemoved(ActionId, bool),
    GoalActive(usize, bool),
    ThreatDone(usize),
    UnaryDone(usize),
    ReservoirDirty(usize, bool),
    Floor(TimeFloor),
}

/// A trail level of the whole plan: the levels of its networks and of its own trail, and the lengths of
/// the arrays it only appends to (truncated on restore).
#[derive(Copy, Clone, Eq, PartialEq, Debug)]
pub struct PlanLevel {
    stn: Level,
    bindings: Level,
    numeric: Level,
    trail: Level,
    actions: usize,
    events: usize,
    conds: usize,
    links: usize,
    usages: usize,
    goals: usize,
    threats: usize,
    unary: usize,
}

/// A pair (event, link) that may be a threat, found when either was added (flaws are detected
/// incrementally: once resolved, a candidate stays resolved as constraints are only added).
#[derive(Copy, Clone, Debug)]
pub(crate) struct Candidate<A, B> {
    pub a: A,
    pub b: B,
    pub done: bool,
}

/// The partial plan. Its networks and tables are read from outside this crate through accessors and
/// changed only through its methods (the planner's resolvers, [`exec_edits`]), which keep the flaw caches,
/// the indexes and the trail right: a caller cannot forget them.
#[derive(Clone, Debug)]
pub struct PartialPlan {
    pub(crate) domain: Arc<Domain>,
    pub(crate) problem: Arc<Problem>,
    pub(crate) stn: Stn,
    pub(crate) bindings: Bindings,
    pub(crate) numeric: Numeric,
    pub(crate) actions: Vec<Action>,
    pub(crate) events: Vec<EventRec>,
    pub(crate) conds: Vec<Condition>,
    pub(crate) links: Vec<CausalLink>,
    pub(crate) usages: Vec<Usage>,
    pub(crate) goals: Vec<PlanGoal>,
    /// The horizon timepoint's bound: every timepoint is before `problem.horizon`.
    pub(crate) horizon: Time,
    floor: TimeFloor,
    /// Events per attribute (index = AttrId).
    events_by_attr: Vec<Vec<EventId>>,
    /// Links per attribute.
    links_by_attr: Vec<Vec<LinkId>>,
    /// Usages per resource.
    usages_by_res: Vec<Vec<UsageId>>,
    pub(crate) threats: candidates::CandidateSet<EventId, LinkId>,
    pub(crate) unary: candidates::CandidateSet<UsageId, UsageId>,
    /// Reservoirs to re-check (a usage was added since their envelope was last found clean).
    pub(crate) reservoir_dirty: Vec<bool>,
    trail: Trail<Entry>,
    changes: changes::ChangeLog,
    /// The planner's bound on same-task regressions (see [`RegressBound`]); not on the trail.
    pub(crate) regress: RegressBound,
}

/// How deep a chain of same-task insertions made for `from` conditions (move ← move ← move ...) may
/// grow before the resolvers leave the next one out, and whether they left one out since the search last
/// looked. A search that exhausts its tree with such a cut has proved nothing: it starts again with a
/// deeper bound (iterative deepening), so a bound never turns into a false "no plan".
#[derive(Clone, Debug)]
pub(crate) struct RegressBound {
    pub limit: u32,
    pub cut: std::cell::Cell<bool>,
}

impl Default for RegressBound {
    /// Three hops cover the detours of the shipped domains (the AUV's surface → vent1 → vent2).
    fn default() -> Self {
        RegressBound {
            limit: 3,
            cut: std::cell::Cell::new(false),
        }
    }
}

impl PartialPlan {
    /// The current level of the whole plan: of its networks, of its own trail and of its arrays.
    pub fn save(&mut self) -> PlanLevel {
        PlanLevel {
            stn: self.stn.save(),
            bindings: self.bindings.save(),
            numeric: self.numeric.save(),
            trail: self.trail.level(),
            actions: self.actions.len(),
            events: self.events.len(),
            conds: self.conds.len(),
            links: self.links.len(),
            usages: self.usages.len(),
            goals: self.goals.len(),
            threats: self.threats.len(),
            unary: self.unary.len(),
        }
    }

    /// Undoes everything done after `level`; the change log records the undone structure.
    pub fn restore(&mut self, level: PlanLevel) {
        while let Some(entry) = self.trail.pop_after(level.trail) {
            self.undo(entry, &level);
        }
        for l in (level.links..self.links.len()).rev() {
            if self.links[l].active {
                let ends = self.link_ends(LinkId(l as u32));
                self.changes.push(PlanChange::LinkRemoved(ends));
            }
            let attr = self.conds[self.links[l].cond.index()].attr;
            self.links_by_attr[attr.index()].pop();
        }
        self.links.truncate(level.links);
        for g in (level.goals..self.goals.len()).rev() {
            if self.goals[g].active {
                self.changes
                    .push(PlanChange::GoalRemoved(self.goals[g].goal));
            }
        }
        self.goals.truncate(level.goals);
        for a in (level.actions..self.actions.len()).rev() {
            if !self.actions[a].removed {
                self.changes
                    .push(PlanChange::ActionRemoved(ActionId(a as u32)));
            }
        }
        self.actions.truncate(level.actions);
        for e in (level.events..self.events.len()).rev() {
            let attr = self.events[e].attr;
            self.events_by_attr[attr.index()].pop();
        }
        self.events.truncate(level.events);
        self.conds.truncate(level.conds);
        for u in (level.usages..self.usages.len()).rev() {
            let r = self.usages[u].resource;
            self.usages_by_res[r.index()].pop();
        }
        self.usages.truncate(level.usages);
        self.threats.truncate(level.threats);
        self.unary.truncate(level.unary);
        self.numeric.restore(level.numeric);
        self.bindings.restore(level.bindings);
        self.stn.restore(level.stn);
    }

    /// Undoes one trailed change; announces it in the change log when the item outlives `level`.
    fn undo(&mut self, entry: Entry, level: &PlanLevel) {
        match entry {
            Entry::CondLink(c, old) => self.conds[c.index()].link = old,
            Entry::LinkActive(l, old) => {
                self.links[l.index()].active = old;
                if l.index() < level.links {
                    let ends = self.link_ends(l);
                    self.changes.push(if old {
                        PlanChange::LinkAdded(ends)
                    } else {
                        PlanChange::LinkRemoved(ends)
                    });
                }
            }
            Entry::ActionRemoved(a, old) => {
                self.actions[a.index()].removed = old;
                if a.index() < level.actions {
                    self.changes.push(if old {
                        PlanChange::ActionRemoved(a)
                    } else {
                        PlanChange::ActionAdded(a)
                    });
                }
            }
            Entry::GoalActive(g, old) => {
                self.goals[g].active = old;
                if g < level.goals {
                    let id = self.goals[g].goal;
                    self.changes.push(if old {
                        PlanChange::GoalAdded(id)
                    } else {
                        PlanChange::GoalRemoved(id)
                    });
                }
            }
            Entry::ThreatDone(i) => self.threats.reopen(i),
            Entry::UnaryDone(i) => self.unary.reopen(i),
            Entry::ReservoirDirty(r, old) => self.reservoir_dirty[r] = old,
            Entry::Floor(old) => self.floor = old,
        }
    }

    /// The change log (plan-change notifications for the dispatcher), from `cursor` on.
    pub fn changes_since(&self, cursor: ChangeCursor) -> &[PlanChange] {
        self.changes.since(cursor)
    }

    /// The identity of this plan's change log (a clone of the plan gets a new one).
    pub fn change_log_id(&self) -> u64 {
        self.changes.id()
    }

    /// The changes after `cursor` of change log `log`: `None` unless `log` is this plan's log or that of a
    /// plan this one was cloned from after `cursor` (then both logs agree up to `cursor`).
    pub fn changes_continuing(&self, log: u64, cursor: ChangeCursor) -> Option<&[PlanChange]> {
        self.changes.continuing(log, cursor)
    }

    /// The position after the last change (pass it to [`PartialPlan::changes_since`] later).
    pub fn change_cursor(&self) -> ChangeCursor {
        self.changes.cursor()
    }

    /// Where new timepoints are placed from now on.
    pub fn set_time_floor(&mut self, floor: TimeFloor) {
        self.trail.push(Entry::Floor(self.floor));
        self.floor = floor;
    }

    pub fn time_floor(&self) -> TimeFloor {
        self.floor
    }

    /// Events on `attr`.
    pub fn events_on(&self, attr: AttrId) -> &[EventId] {
        &self.events_by_attr[attr.index()]
    }

    /// Causal links protecting a condition on `attr`.
    pub fn links_on(&self, attr: AttrId) -> &[LinkId] {
        &self.links_by_attr[attr.index()]
    }

    /// Usages of `r`.
    pub fn usages_of(&self, r: ResourceId) -> &[UsageId] {
        &self.usages_by_res[r.index()]
    }

    pub fn domain(&self) -> &Arc<Domain> {
        &self.domain
    }

    pub fn problem(&self) -> &Arc<Problem> {
        &self.problem
    }

    /// The binding CSP of its symbolic variables.
    pub fn bindings(&self) -> &Bindings {
        &self.bindings
    }

    /// The CSP of its numeric variables.
    pub fn numeric(&self) -> &Numeric {
        &self.numeric
    }

    /// Every action ever inserted, removed ones included, indexed by [`ActionId`].
    pub fn actions(&self) -> &[Action] {
        &self.actions
    }

    /// Every event, indexed by [`EventId`].
    pub fn events(&self) -> &[EventRec] {
        &self.events
    }

    /// Every condition, indexed by [`CondId`].
    pub fn conds(&self) -> &[Condition] {
        &self.conds
    }

    /// Every causal link, removed ones included, indexed by [`LinkId`].
    pub fn links(&self) -> &[CausalLink] {
        &self.links
    }

    /// Every resource usage, indexed by [`UsageId`].
    pub fn usages(&self) -> &[Usage] {
        &self.usages
    }

    /// The problem's goals as the plan holds them (active or rejected).
    pub fn goals(&self) -> &[PlanGoal] {
        &self.goals
    }

    /// The horizon: every timepoint is before it.
    pub fn horizon(&self) -> Time {
        self.horizon
    }

    pub fn event(&self, e: EventId) -> &EventRec {
        &self.events[e.index()]
    }

    pub fn cond(&self, c: CondId) -> &Condition {
        &self.conds[c.index()]
    }

    /// Whether `c` is the `from` condition of an action's event that takes whatever value precedes it
    /// ([`crate::model::Task::free_from`]): any establisher before it will do.
    pub fn cond_takes_any(&self, c: CondId) -> bool {
        let cond = &self.conds[c.index()];
        let (CondKind::Before(e), Owner::Action(a)) = (cond.kind, cond.owner) else {
            return false;
        };
        let act = &self.actions[a.index()];
        act.events.iter().position(|&x| x == e).is_some_and(|k| {
            self.domain
                .task(act.task)
                .free_from(k, self.domain.attrs[cond.attr.index()].value_type)
        })
    }

    pub fn link(&self, l: LinkId) -> &CausalLink {
        &self.links[l.index()]
    }

    pub fn usage(&self, u: UsageId) -> &Usage {
        &self.usages[u.index()]
    }

    pub fn action(&self, a: ActionId) -> &Action {
        &self.actions[a.index()]
    }

    /// Actions in the plan (not removed).
    pub fn live_actions(&self) -> impl Iterator<Item = ActionId> + '_ {
        (0..self.actions.len())
            .filter(|&a| !self.actions[a].removed)
            .map(|a| ActionId(a as u32))
    }

    /// Whether the condition's owner is still in the plan.
    pub fn cond_live(&self, c: CondId) -> bool {
        match self.conds[c.index()].owner {
            Owner::Action(a) => !self.actions[a.index()].removed,
            Owner::Goal(g) => self
                .goals
                .iter()
                .any(|pg| pg.goal == g && pg.active && pg.cond == c),
            _ => true,
        }
    }

    /// Open conditions: live conditions without a causal link.
    pub fn open_conditions(&self) -> impl Iterator<Item = CondId> + '_ {
        (0..self.conds.len())
            .map(|c| CondId(c as u32))
            .filter(|&c| self.conds[c.index()].link.is_none() && self.cond_live(c))
    }

    pub(crate) fn mark_threat_done(&mut self, i: usize) {
        self.threats.set_done(i);
        self.trail.push(Entry::ThreatDone(i));
    }

    pub(crate) fn mark_unary_done(&mut self, i: usize) {
        self.unary.set_done(i);
        self.trail.push(Entry::UnaryDone(i));
    }

    pub(crate) fn set_reservoir_dirty(&mut self, r: usize, dirty: bool) {
        if self.reservoir_dirty[r] != dirty {
            self.trail
                .push(Entry::ReservoirDirty(r, self.reservoir_dirty[r]));
            self.reservoir_dirty[r] = dirty;
        }
    }

    /// Removes a causal link (the executive breaks contradicted links, §3.3): its condition becomes open.
    pub fn remove_link(&mut self, l: LinkId) {
        let link = &self.links[l.index()];
        if !link.active {
            return;
        }
        let (cond, prec) = (link.cond, link.precedence);
        self.trail.push(Entry::LinkActive(l, true));
        self.links[l.index()].active = false;
        if self.conds[cond.index()].link == Some(l) {
            self.trail.push(Entry::CondLink(cond, Some(l)));
            self.conds[cond.index()].link = None;
        }
        if let Some(c) = prec {
            self.stn.remove_constraint(c);
        }
        let ends = self.link_ends(l);
        self.changes.push(PlanChange::LinkRemoved(ends));
    }

    /// Removes a (past) action from the plan: its conditions are no longer open conditions and its links
    /// are dropped; its events stay (their effects are in the state), as in seed 1 Definition 1.
    pub fn remove_action(&mut self, a: ActionId) {
        if self.actions[a.index()].removed {
            return;
        }
        self.trail.push(Entry::ActionRemoved(a, false));
        self.actions[a.index()].removed = true;
        self.changes.push(PlanChange::ActionRemoved(a));
    }

    /// Withdraws a goal (complete replanning rejects goals, §3.6).
    pub fn remove_goal(&mut self, g: GoalId) {
        if let Some(i) = self.goals.iter().position(|pg| pg.goal == g && pg.active) {
            self.trail.push(Entry::GoalActive(i, true));
            self.goals[i].active = false;
            self.changes.push(PlanChange::GoalRemoved(g));
        }
    }

    /// Number of actions in the plan (not removed).
    pub fn num_actions(&self) -> usize {
        self.live_actions().count()
    }

    /// Replaces the problem (e.g. a new location object discovered at run time; ids must be preserved).
    /// Initial facts the new problem appends (a new object's wildcard defaults, e.g. `PICTURE(new) =
    /// false`) become initial events at the origin, so that the new object can be planned for.
    pub fn set_problem(&mut self, problem: Arc<Problem>) {
        let known = self.problem.initial.len();
        for f in problem.initial.iter().skip(known) {
            self.push_initial(f);
        }
        self.problem = problem;
    }
}

backtrack::impl_backtrack!(PartialPlan, PlanLevel);
