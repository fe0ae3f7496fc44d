//! The planner's output: a **flexible plan** (seed 1 §2.2) as plain data — partially ordered (timepoints with
//! [lb, ub] windows and the temporal network that bounds them), partially instantiated (variables with
//! their remaining domains and ≠ constraints), with its causal links and the goals it achieves or not.
//!
//! The planner produces a [`Solution`]; the independent checker ([`crate::plan::validate`]) consumes it,
//! re-solves the network itself and re-derives everything else from the domain's task templates. It is
//! also what `mavtempo plan --json` prints (serde, both ways).
//!
//! Conventions: times are integer milliseconds relative to the origin (timepoint 0); `None` bounds are
//! infinite (−∞ for a lower bound, +∞ for an upper bound), so the JSON never carries sentinel numbers.

use serde::{Deserialize, Serialize};

use crate::model::{AttrId, GoalId, NumVarId, ObjectId, SymVarId, TaskId, Time, TpId};

/// A timepoint of the plan: index into [`Solution::timepoints`] (0 is the origin).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct PlanTp(pub u32);

impl PlanTp {
    /// The origin of time (fixed at 0).
    pub const ORIGIN: PlanTp = PlanTp(0);

    /// Position in [`Solution::timepoints`].
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// An action of the plan: [`PlanAction::id`] (stable across repairs, not necessarily an index).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct PlanActionId(pub u32);

/// A symbolic variable of the plan: index into [`Solution::variables`]. Variables unified by the
/// planner (e.g. `a1.?to` and `a2.?from` after a causal link) are one plan variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct PlanVarId(pub u32);

impl PlanVarId {
    /// Position in [`Solution::variables`].
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A flexible plan: everything the executive needs, and everything the checker verifies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct Solution {
    /// The domain's name (`domain rover;`).
    pub domain: String,
    /// The problem's name.
    pub problem: String,
    /// All timepoints of the plan's temporal network, `timepoints[i].id == PlanTp(i)`; `timepoints[0]` is
    /// the origin.
    pub timepoints: Vec<Timepoint>,
    /// **All** constraints of the plan's temporal network (task-internal durations, precedences from
    /// causal links / threats / resource conflicts, goal windows, horizon ...), so that a reader can
    /// re-solve it. The windows in [`Solution::timepoints`] are what the planner computed from these.
    pub constraints: Vec<PlanConstraint>,
    /// Symbolic variables of the plan (not yet bound to one object), with their remaining domains.
    pub variables: Vec<PlanVar>,
    /// Binding constraints `a ≠ b` between plan variables (domain restrictions against constants are
    /// already applied to [`PlanVar::domain`]).
    pub different: Vec<(PlanVarId, PlanVarId)>,
    /// The actions (task instances) of the plan.
    pub actions: Vec<PlanAction>,
    /// The causal links L: each protects a value between its establisher and its consumer.
    pub causal_links: Vec<CausalLink>,
    /// One entry per goal of the problem the planner was given (achieved or not).
    pub goals: Vec<PlanGoal>,
}

/// A timepoint and its current window relative to the origin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Timepoint {
    /// Its own index (`PlanTp(i)` for `timepoints[i]`).
    pub id: PlanTp,
    /// For printing: `origin`, `a3.st` (action `a3`, task timepoint `st`), `g2.st` / `g2.et` (goal `g2`).
    pub name: String,
    /// Earliest time, ms after the origin (`None`: −∞, which a consistent plan never has).
    pub lb: Option<Time>,
    /// Latest time, ms after the origin (`None`: +∞).
    pub ub: Option<Time>,
}

/// A binary constraint of the temporal network: `to − from ∈ [lb, ub]` (ms).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PlanConstraint {
    pub from: PlanTp,
    pub to: PlanTp,
    /// `None`: −∞.
    pub lb: Option<Time>,
    /// `None`: +∞.
    pub ub: Option<Time>,
}

/// A symbolic variable of the plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanVar {
    /// Its own index (`PlanVarId(i)` for `variables[i]`).
    pub id: PlanVarId,
    /// For printing, e.g. `a2.?to`.
    pub name: String,
    /// The objects it may still take (non-empty in a consistent plan).
    pub domain: Vec<ObjectId>,
}

/// A symbolic term of the plan: an object, a plan variable, or IxTeT's `+oo` (values only).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum PlanTerm {
    Obj(ObjectId),
    Var(PlanVarId),
    /// `+oo`: unknown / in transit.
    Unknown,
}

/// Final bounds of a numeric variable (`None`: infinite on that side).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NumBounds {
    pub lo: Option<f64>,
    pub hi: Option<f64>,
}

/// An action: an instance of a task of the domain.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanAction {
    pub id: PlanActionId,
    /// For printing: `a3`.
    pub name: String,
    /// The task's name (redundant with `task`, checked by readers).
    pub task_name: String,
    pub task: TaskId,
    /// One term per symbolic variable of the task, indexed by [`SymVarId`] (the parameters first, then
    /// local variables).
    pub args: Vec<PlanTerm>,
    /// One plan timepoint per task timepoint, indexed by [`TpId`].
    pub timepoints: Vec<PlanTp>,
    /// Final bounds of the task's numeric variables, indexed by [`NumVarId`].
    pub num_vars: Vec<NumBounds>,
}

impl PlanAction {
    /// The plan timepoint of task timepoint `tp`.
    pub fn tp(&self, tp: TpId) -> Option<PlanTp> {
        self.timepoints.get(tp.index()).copied()
    }

    /// The term bound to task variable `v`.
    pub fn arg(&self, v: SymVarId) -> Option<PlanTerm> {
        self.args.get(v.index()).copied()
    }

    /// The bounds of numeric variable `v`.
    pub fn num(&self, v: NumVarId) -> Option<NumBounds> {
        self.num_vars.get(v.index()).copied()
    }
}

/// What establishes the value of a causal link.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Establisher {
    /// The initial value at the origin ([`crate::model::Problem::initial`]).
    Initial,
    /// A predicted exogenous change: index into [`crate::model::Problem::exogenous`].
    Timed { index: usize },
    /// Event number `event` (index into the task's `events`) of an action.
    Event { action: PlanActionId, event: usize },
}

/// What a causal link supports (an open condition that the link closed).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Consumer {
    /// Hold number `hold` (index into the task's `holds`) of an action.
    Hold { action: PlanActionId, hold: usize },
    /// The `from` value required by event number `event` of an action.
    EventFrom { action: PlanActionId, event: usize },
    /// A goal's `hold(attr(args): value, (st^g, et^g))`.
    Goal { goal: GoalId },
}

/// A causal link: `establisher --attr(args) = value--> consumer`, protected over `[from, to]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CausalLink {
    pub establisher: Establisher,
    pub consumer: Consumer,
    /// The attribute instance.
    pub attr: AttrId,
    pub args: Vec<PlanTerm>,
    /// The protected value.
    pub value: PlanTerm,
    /// Start of the protected interval (the establishing event's timepoint, or the origin).
    pub from: PlanTp,
    /// End of the protected interval (the consumer's last timepoint).
    pub to: PlanTp,
}

/// A goal of the problem and what the plan does about it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlanGoal {
    pub goal: GoalId,
    /// For printing: the goal's name.
    pub name: String,
    /// True when the plan achieves it (then `start` and `end` are set and a causal link supports it).
    pub achieved: bool,
    /// st^g, if the goal is in the network.
    pub start: Option<PlanTp>,
    /// et^g, if the goal is in the network.
    pub end: Option<PlanTp>,
    /// Why it is not achieved (rejected goal, flaw without resolver ...); `None` when achieved.
    pub reason: Option<String>,
}

impl Solution {
    /// The action with id `id`.
    pub fn action(&self, id: PlanActionId) -> Option<&PlanAction> {
        self.actions.iter().find(|a| a.id == id)
    }

    /// The timepoint `tp`.
    pub fn timepoint(&self, tp: PlanTp) -> Option<&Timepoint> {
        self.timepoints.get(tp.index())
    }

    /// The name of `tp` (`?` for an unknown index), for messages.
    pub fn tp_name(&self, tp: PlanTp) -> &str {
        self.timepoint(tp).map_or("?", |t| t.name.as_str())
    }

    /// Goals the plan does not achieve.
    pub fn unachieved(&self) -> impl Iterator<Item = &PlanGoal> {
        self.goals.iter().filter(|g| !g.achieved)
    }
}
