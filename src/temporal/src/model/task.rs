//! Tasks: IxTeT's lifted action templates (seed 1 Fig. 3).
//!
//! A task has typed parameters, named timepoints (`st`, `et` and possibly more), `event`s and `hold`s on
//! logical attributes, resource usages, temporal constraints between its timepoints, binding constraints on
//! its symbolic variables, numeric variables with interval domains and numeric constraints among them and
//! its durations, and a preemption class.

use serde::Serialize;

use super::{
    AttrId, NumInterval, NumVarId, ObjectId, ResourceId, SymVarId, TimeInterval, TpId, TypeId,
};

/// A symbolic term in a task: a variable (parameter or local), a constant, or `+oo` (values only).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Term {
    Var(SymVarId),
    Obj(ObjectId),
    /// IxTeT's `+oo`: "unknown / in transit". Never an attribute argument.
    Unknown,
}

/// A numeric term: a numeric variable of the task or a constant.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum NumTerm {
    Var(NumVarId),
    Const(f64),
}

/// A typed symbolic variable (parameters are the first [`Task::n_params`] ones).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SymVar {
    /// Without the `?`.
    pub name: String,
    pub ty: TypeId,
}

/// A numeric variable (`variable ?dist;`) with its declared domain (`?speed in [0.3, 0.6];`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NumVar {
    /// Without the `?`.
    pub name: String,
    pub domain: NumInterval,
}

/// `event(attr(args): (from, to), at)`: the value changes from `from` to `to` at timepoint `at`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Event {
    pub attr: AttrId,
    pub args: Vec<Term>,
    pub from: Term,
    pub to: Term,
    pub at: TpId,
    /// Primary effects justify inserting the task to support an open condition and define the task's
    /// *main attributes* (seed 1 §3.3, abstraction hierarchy). Events are primary unless marked `secondary`.
    pub primary: bool,
}

/// `hold(attr(args): value, (from, to))`: the value persists over `[from, to]`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Hold {
    pub attr: AttrId,
    pub args: Vec<Term>,
    pub value: Term,
    pub from: TpId,
    pub to: TpId,
}

/// What a resource usage does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum UsageKind {
    /// `use(r: q, (from, to))`: borrows `q` over `[from, to]` (unary or reservoir).
    Use { from: TpId, to: TpId },
    /// `consume(r: q, at)`: the level drops by `q` at `at` (reservoir).
    Consume { at: TpId },
    /// `produce(r: q, at)`: the level rises by `q` at `at` (reservoir).
    Produce { at: TpId },
}

/// A resource usage of a task.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResourceUsage {
    pub resource: ResourceId,
    pub kind: UsageKind,
    /// A number or a numeric variable whose domain is the quantity interval `[q_min, q_max]`.
    pub quantity: NumTerm,
    /// Productions are primary effects (they justify inserting e.g. download_images) unless marked
    /// `secondary`; uses and consumptions are never effects.
    pub primary: bool,
    /// `saturating produce`: the level rises by the quantity but not above the capacity (a recharge up to
    /// full, a download that frees what is stored). Such a production never overflows.
    #[serde(default)]
    pub saturating: bool,
}

/// `(to - from) in interval` between two timepoints of the task.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TemporalConstraint {
    pub from: TpId,
    pub to: TpId,
    pub interval: TimeInterval,
}

/// A binding (atemporal symbolic) constraint.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Binding {
    Eq(Term, Term),
    Ne(Term, Term),
    /// `?v in {a, b, c}`.
    In(SymVarId, Vec<ObjectId>),
}

/// A numeric constraint, in one of the forms the planner's numeric CSP propagates.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum NumConstraint {
    /// `?var = distance(a, b)`: straight-line metres between two location-valued terms
    /// (see [`crate::model::Position::distance`]).
    Distance { var: NumVarId, a: Term, b: Term },
    /// `?var = to - from` in **seconds** (the numeric side of the mixed temporal/atemporal constraint).
    Duration { var: NumVarId, from: TpId, to: TpId },
    /// `?var = a * b`.
    Product {
        var: NumVarId,
        a: NumTerm,
        b: NumTerm,
    },
    /// `?var = a + b`.
    Sum {
        var: NumVarId,
        a: NumTerm,
        b: NumTerm,
    },
    /// `a <= b`.
    Le(NumTerm, NumTerm),
    /// `a = b` (also written `?x = 3`).
    Equal(NumTerm, NumTerm),
}

/// When the executive may stop an action (seed 1 §2.1, §3.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Preemption {
    /// `et` is not controllable: the executive waits for the report (t_exec = et_ub).
    NonPreemptive,
    /// Stopped as soon as possible (t_exec = et_lb).
    EarlyPreemptive,
    /// Stopped as late as possible (t_exec = et_ub − ts), e.g. `move`.
    LatePreemptive,
}

/// A task (action template).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Task {
    pub name: String,
    /// All symbolic variables; the first `n_params` are the parameters, in order.
    pub sym_vars: Vec<SymVar>,
    pub n_params: usize,
    pub num_vars: Vec<NumVar>,
    /// Timepoint names in declaration order (`(st, et)` or `(st, t1, et)`).
    pub timepoints: Vec<String>,
    /// The start timepoint (the first declared).
    pub start: TpId,
    /// The end timepoint (the last declared).
    pub end: TpId,
    pub events: Vec<Event>,
    pub holds: Vec<Hold>,
    pub usages: Vec<ResourceUsage>,
    /// Written constraints plus the implicit `start <= t <= end` for every timepoint `t`.
    pub temporal: Vec<TemporalConstraint>,
    pub bindings: Vec<Binding>,
    pub numeric: Vec<NumConstraint>,
    pub preemption: Preemption,
    /// Its duration (`end − start`) is decided by the world, not by the executive (`contingent (et - st)
    /// in [a, b];` or `contingent ?d = et - st;`): the plan keeps it as a contingent link of an STNU.
    pub contingent: bool,
    /// Where it is declared in its domain file (1-based), for messages about it; `None` when built in code.
    pub line: Option<usize>,
}

impl Task {
    /// A task with its name, parameter count, timepoints (`start` and `end` among them) and source line,
    /// and nothing else yet: the readers (the native language, PDDL) fill in its variables, events, holds,
    /// usages and constraints.
    pub fn new(
        name: String,
        n_params: usize,
        timepoints: Vec<String>,
        (start, end): (TpId, TpId),
        line: Option<usize>,
    ) -> Self {
        Task {
            name,
            sym_vars: Vec::new(),
            n_params,
            num_vars: Vec::new(),
            timepoints,
            start,
            end,
            events: Vec::new(),
            holds: Vec::new(),
            usages: Vec::new(),
            temporal: Vec::new(),
            bindings: Vec::new(),
            numeric: Vec::new(),
            preemption: Preemption::NonPreemptive,
            contingent: false,
            line,
        }
    }

    /// The parameters (the first `n_params` symbolic variables).
    pub fn params(&self) -> &[SymVar] {
        &self.sym_vars[..self.n_params.min(self.sym_vars.len())]
    }

    /// The symbolic variable named `name` (without `?`).
    pub fn sym_var(&self, name: &str) -> Option<SymVarId> {
        self.sym_vars
            .iter()
            .position(|v| v.name == name)
            .map(SymVarId::from_index)
    }

    /// The numeric variable named `name` (without `?`).
    pub fn num_var(&self, name: &str) -> Option<NumVarId> {
        self.num_vars
            .iter()
            .position(|v| v.name == name)
            .map(NumVarId::from_index)
    }

    /// The timepoint named `name`.
    pub fn timepoint(&self, name: &str) -> Option<TpId> {
        self.timepoints
            .iter()
            .position(|t| t == name)
            .map(TpId::from_index)
    }

    /// Whether event `k`'s `from` is a variable of the attribute's value type that occurs nowhere else
    /// in the task: the event takes whatever value precedes it (a PDDL add or deletion whose prior value
    /// the action does not require). Its condition never needs an action inserted for it (the planner
    /// links it to an event already in the plan, see `planner::resolvers`).
    pub fn free_from(&self, k: usize, value_type: TypeId) -> bool {
        let Some(Term::Var(v)) = self.events.get(k).map(|e| e.from) else {
            return false;
        };
        if self.sym_vars.get(v.index()).map(|s| s.ty) != Some(value_type) {
            return false;
        }
        let is_v = |t: &Term| *t == Term::Var(v);
        let in_events = self
            .events
            .iter()
            .flat_map(|e| e.args.iter().chain([&e.from, &e.to]))
            .filter(|t| is_v(t))
            .count();
        in_events == 1
            && !self
                .holds
                .iter()
                .any(|h| h.args.iter().chain([&h.value]).any(is_v))
            && !self.bindings.iter().any(|b| match b {
                Binding::Eq(x, y) | Binding::Ne(x, y) => is_v(x) || is_v(y),
                Binding::In(x, _) => *x == v,
            })
            && !self.numeric.iter().any(|n| match n {
                NumConstraint::Distance { a, b, .. } => is_v(a) || is_v(b),
                _ => false,
            })
    }

    /// The *main attributes* of the task: attributes of its primary events, deduplicated, in order
    /// (seed 1 §3.3; the executive builds the abstraction hierarchy from them).
    pub fn main_attributes(&self) -> Vec<AttrId> {
        let mut out: Vec<AttrId> = Vec::new();
        for e in self.events.iter().filter(|e| e.primary) {
            if !out.contains(&e.attr) {
                out.push(e.attr);
            }
        }
        out
    }

    /// Resources the task produces as a primary effect (it can resolve a reservoir conflict).
    pub fn produced_resources(&self) -> Vec<ResourceId> {
        let mut out: Vec<ResourceId> = Vec::new();
        for u in &self.usages {
            if matches!(u.kind, UsageKind::Produce { .. })
                && u.primary
                && !out.contains(&u.resource)
            {
                out.push(u.resource);
            }
        }
        out
    }

    /// Every attribute the task mentions (events and holds), deduplicated, in order.
    pub fn attributes(&self) -> Vec<AttrId> {
        let mut out: Vec<AttrId> = Vec::new();
        let all = self.events.iter().map(|e| e.attr);
        for a in all.chain(self.holds.iter().map(|h| h.attr)) {
            if !out.contains(&a) {
                out.push(a);
            }
        }
        out
    }
}
