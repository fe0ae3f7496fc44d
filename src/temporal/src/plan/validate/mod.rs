//! The **independent plan checker** (planner issue, item 4): given a domain, a problem and a [`Solution`],
//! decide whether the flexible plan is correct, sharing no code with the planner's search or propagation.
//!
//! It trusts only the domain's task templates and the problem; from the solution it takes the structure
//! (which actions, their timepoints, variables, causal links, the network's constraints) and then:
//! 1. re-solves the plan's temporal network itself ([`network`], Bellman-Ford) and checks the reported
//!    windows against it; instantiates a schedule: the earliest times within the reported windows;
//! 2. instantiates the unbound variables by a small backtracking search over their domains respecting the
//!    plan's ≠ and the tasks' binding constraints ([`bind`]);
//! 3. checks the tasks' temporal constraints, the horizon and the goals' I^g / I^d ([`temporal`]);
//!    the numeric constraints within the reported bounds at that schedule ([`numeric`]);
//!    every event's `from`, every hold, causal link and achieved goal over time ([`timeline`]);
//!    every resource level over time ([`resource`]).
//!
//! It reports **all** violations it finds ([`Rejected`]). Value semantics (IxTeT's piecewise-constant
//! attributes): an event at t sets the value from t on (its `from` is the value just before t); an
//! action's `hold(v, (a, b))` requires the value v on [a, b[ (on {a} when a = b), so a hold may end exactly
//! where the next event changes the value; a goal's hold (and a causal link to a goal) requires it on the
//! closed [st^g, et^g]; two changes of one attribute instance at the same instant are a violation (their
//! order is undefined). These are the semantics the planner documents in `crate::plan`.

mod bind;
mod network;
mod numeric;
mod resource;
mod structure;
mod temporal;
mod timeline;
mod violation;

pub use violation::{Lapse, LinkFault, NumericFault, Rejected, Violation};

use crate::model::{Domain, ObjectId, Problem, Term, Time, TimeInterval, TpId, Value};
use crate::plan::solution::{PlanAction, PlanTerm, PlanTp, Solution};

/// What the checker instantiated for an accepted plan.
#[derive(Debug, Clone, PartialEq)]
pub struct Checked {
    /// One time per plan timepoint (ms after the origin): the earliest schedule within the windows.
    pub schedule: Vec<Time>,
    /// One object per plan variable.
    pub bindings: Vec<ObjectId>,
}

/// Checks `solution` against `domain` and `problem`; `Err` lists every violation found.
pub fn validate(
    domain: &Domain,
    problem: &Problem,
    solution: &Solution,
) -> Result<Checked, Rejected> {
    let mut found = structure::check(domain, problem, solution);
    if !found.is_empty() {
        return Err(Rejected { violations: found });
    }
    let Some(schedule) = temporal::schedule(solution, &mut found) else {
        return Err(Rejected { violations: found });
    };
    let bindings = bind::instantiate(domain, problem, solution, &mut found);
    let cx = Ctx {
        d: domain,
        p: problem,
        s: solution,
        sched: schedule,
        vals: bindings,
    };
    temporal::check(&cx, &mut found);
    let quantities = numeric::check(&cx, &mut found);
    timeline::check(&cx, &mut found);
    resource::check(&cx, &quantities, &mut found);
    if found.is_empty() {
        Ok(Checked {
            schedule: cx.sched,
            bindings: cx.vals,
        })
    } else {
        Err(Rejected { violations: found })
    }
}

/// A structurally sound plan with its schedule and instantiation: what every later check reads.
pub(super) struct Ctx<'a> {
    pub d: &'a Domain,
    pub p: &'a Problem,
    pub s: &'a Solution,
    /// Time of each plan timepoint.
    pub sched: Vec<Time>,
    /// Object chosen for each plan variable.
    pub vals: Vec<ObjectId>,
}

impl Ctx<'_> {
    /// `a3 (move)`.
    pub fn label(&self, a: &PlanAction) -> String {
        format!("{} ({})", a.name, self.d.task(a.task).name)
    }

    pub fn time(&self, tp: PlanTp) -> Time {
        self.sched.get(tp.index()).copied().unwrap_or(0)
    }

    /// Time of the action's task timepoint `tp`.
    pub fn at(&self, a: &PlanAction, tp: TpId) -> Time {
        a.tp(tp).map_or(0, |t| self.time(t))
    }

    /// The instantiated value of a plan term.
    pub fn value(&self, t: PlanTerm) -> Value {
        match t {
            PlanTerm::Obj(o) => Value::Obj(o),
            PlanTerm::Var(v) => self
                .vals
                .get(v.index())
                .map_or(Value::Unknown, |&o| Value::Obj(o)),
            PlanTerm::Unknown => Value::Unknown,
        }
    }

    /// The instantiated value of a task term inside action `a`.
    pub fn term(&self, a: &PlanAction, t: Term) -> Value {
        match t {
            Term::Obj(o) => Value::Obj(o),
            Term::Unknown => Value::Unknown,
            Term::Var(v) => a.arg(v).map_or(Value::Unknown, |pt| self.value(pt)),
        }
    }

    pub fn value_name(&self, v: Value) -> String {
        match v {
            Value::Obj(o) => self.p.object_name(o).to_string(),
            Value::Unknown => "+oo".to_string(),
        }
    }

    /// `PICTURE(p1)`.
    pub fn instance_name(&self, attr: crate::model::AttrId, args: &[Value]) -> String {
        let args: Vec<String> = args.iter().map(|&v| self.value_name(v)).collect();
        format!("{}({})", self.d.attr(attr).name, args.join(", "))
    }
}

/// `[a, b]`, `]a, +oo[` ... for messages.
pub(super) fn show_interval(i: &TimeInterval) -> String {
    crate::model::show_bounds(&i.lb, &i.ub)
}

/// `[lb, ub]` with `None` as infinite.
pub(super) fn show_window(lb: Option<Time>, ub: Option<Time>) -> String {
    let l = lb.map_or("-oo".to_string(), |v| v.to_string());
    let u = ub.map_or("+oo".to_string(), |v| v.to_string());
    format!("[{l}, {u}]")
}
