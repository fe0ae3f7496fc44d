//! The plan as a Simple Temporal Network with Uncertainty: the duration of each action whose task marks
//! it `contingent` is a contingent link (activation = its start, contingent timepoint = its end) over the
//! interval its task allows (the task's constraints alone, with the action's bindings: a move's distance
//! over the speed range) — not the interval propagation has left in the STN, which is exactly what can be
//! squeezed (seed 1 §5). Every other constraint of the STN is a requirement. [`PartialPlan::check_dc`]
//! decides dynamic controllability (Morris 2014, [`crate::stn::Stnu::check_dc`]).
//!
//! Executed timepoints stay as their execution constraints. A running action (start executed, end not)
//! keeps its link, its lower bound raised to the end's earliest time (the world has not ended it yet); an
//! action whose end is executed is no longer contingent.

use super::build::{numeric_constraints, stn_bounds};
use super::{ActionId, Numeric, Owner, PartialPlan, STerm};
use crate::stn::{ConstraintId, Dispatchable, NotDc, Stn, Stnu, Time, Timepoint, INF};

/// A contingent link of the plan.
#[derive(Copy, Clone, Eq, PartialEq, Debug)]
pub struct PlanLink {
    pub action: ActionId,
    pub lower: Time,
    pub upper: Time,
}

/// The plan's STNU: nodes are the STN's timepoint indices.
#[derive(Clone, Debug)]
pub struct PlanStnu {
    pub stnu: Stnu,
    /// One per link of `stnu`, in order.
    pub links: Vec<PlanLink>,
    /// The STN constraint behind each requirement of `stnu` (`None`: the implicit `t − origin ≥ 0`).
    pub requirements: Vec<Option<ConstraintId>>,
}

/// A dynamically controllable plan's dispatchable network.
#[derive(Clone, Debug)]
pub struct DcPlan {
    pub network: PlanStnu,
    pub dispatch: Dispatchable,
}

impl DcPlan {
    /// The waits on `tp`: `(action, delay)`, i.e. `tp` not before the action's start + delay unless its
    /// end has been observed.
    pub fn waits_on(&self, tp: Timepoint) -> impl Iterator<Item = (ActionId, Time)> + '_ {
        self.dispatch
            .waits_on(tp.index())
            .map(|w| (self.network.links[w.link].action, w.delay))
    }
}

/// No dynamically controllable execution of the plan: the durations the world decides can break it.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{text}")]
pub struct NotControllable {
    /// The actions whose contingent durations are in the conflict.
    pub actions: Vec<ActionId>,
    pub text: String,
}

/// How many constraints a failure names before "and N more".
const SHOWN: usize = 4;

impl PartialPlan {
    /// The duration the task of contingent action `a` allows, with the action's current bindings; `None`
    /// when it is unbounded or the task's constraints alone are contradictory.
    pub fn natural_duration(&self, a: ActionId) -> Option<(Time, Time)> {
        let act = self.action(a);
        let task = self.domain.task(act.task);
        let mut stn = Stn::new();
        let tps: Vec<Timepoint> = task
            .timepoints
            .iter()
            .map(|_| stn.add_timepoint())
            .collect();
        for c in &task.temporal {
            let (lo, hi) = stn_bounds(&c.interval);
            stn.add_constraint(tps[c.from.index()], tps[c.to.index()], lo, hi)
                .ok()?;
        }
        let mut num = Numeric::default();
        let nums: Vec<_> = task
            .num_vars
            .iter()
            .map(|v| num.new_var(v.domain.lo(), v.domain.hi()))
            .collect();
        let cons = numeric_constraints(task, &act.vars, &nums, &tps, &mut stn).ok()?;
        num.propagate(&cons, &self.bindings, &self.problem, &mut stn)
            .ok()?;
        let (lo, hi) = stn.delay_bounds(tps[task.start.index()], tps[task.end.index()]);
        (lo >= 0 && hi < INF).then_some((lo, hi))
    }

    /// The plan's STNU (see the module's documentation).
    pub fn stnu(&self) -> PlanStnu {
        let stn = &self.stn;
        let mut stnu = Stnu::new(stn.num_timepoints());
        let mut links = Vec::new();
        let mut requirements = Vec::new();
        let mut contingent_pairs = Vec::new();
        for (i, act) in self.actions.iter().enumerate() {
            let a = ActionId(i as u32);
            if act.removed || !self.domain.task(act.task).contingent || stn.is_executed(act.end) {
                continue;
            }
            let Some((mut lower, mut upper)) = self.natural_duration(a) else {
                continue;
            };
            if let Some(at) = stn.executed_at(act.start) {
                lower = lower.max(stn.lb(act.end) - at);
                upper = upper.max(lower);
            }
            // Node indices are the STN's and each end is contingent once: cannot fail.
            if stnu
                .add_contingent(act.start.index(), act.end.index(), lower, upper)
                .is_ok()
            {
                links.push(PlanLink {
                    action: a,
                    lower,
                    upper,
                });
                contingent_pairs.push((act.start, act.end));
            }
        }
        for (id, k) in stn.constraints() {
            let pair = (k.from, k.to);
            if contingent_pairs.contains(&pair) || contingent_pairs.contains(&(k.to, k.from)) {
                continue;
            }
            if stnu
                .add_requirement(k.from.index(), k.to.index(), k.lb, k.ub)
                .is_ok()
            {
                requirements.push(Some(id));
            }
        }
        for t in stn.timepoints().filter(|t| t.index() != 0) {
            if stnu.add_requirement(0, t.index(), 0, INF).is_ok() {
                requirements.push(None);
            }
        }
        PlanStnu {
            stnu,
            links,
            requirements,
        }
    }

    /// Whether the plan is dynamically controllable; its dispatchable network if it is, else which
    /// contingent durations can break which constraints.
    pub fn check_dc(&self) -> Result<DcPlan, NotControllable> {
        let network = self.stnu();
        match network.stnu.check_dc() {
            Ok(dispatch) => Ok(DcPlan { network, dispatch }),
            Err(e) => Err(self.not_controllable(&network, &e)),
        }
    }

    /// The dispatchable network the executive follows: on a DC plan, [`Self::check_dc`]'s; otherwise the
    /// waits of every part the check gets through, with why the plan is not DC.
    pub fn dispatch_network(&self) -> (DcPlan, Option<NotControllable>) {
        let network = self.stnu();
        let (dispatch, conflict) = network.stnu.dispatch_best_effort();
        let why = conflict.map(|e| self.not_controllable(&network, &e));
        (DcPlan { network, dispatch }, why)
    }

    fn not_controllable(&self, network: &PlanStnu, e: &NotDc) -> NotControllable {
        let actions: Vec<ActionId> = e.links.iter().map(|&k| network.links[k].action).collect();
        let durations: Vec<String> = e
            .links
            .iter()
            .map(|&k| {
                let l = network.links[k];
                format!(
                    "{} [{}, {}]",
                    self.action_text(l.action),
                    secs(l.lower),
                    secs(l.upper)
                )
            })
            .collect();
        let cons: Vec<String> = e
            .requirements
            .iter()
            .filter_map(|&r| network.requirements[r])
            .map(|c| {
                let k = self.stn.constraint(c);
                format!(
                    "{} − {} in [{}, {}]",
                    self.tp_text(k.to),
                    self.tp_text(k.from),
                    secs(k.lb),
                    secs(k.ub)
                )
            })
            .collect();
        let mut shown = cons
            .iter()
            .take(SHOWN)
            .cloned()
            .collect::<Vec<_>>()
            .join("; ");
        if cons.len() > SHOWN {
            shown += &format!("; and {} more", cons.len() - SHOWN);
        }
        let text = if durations.is_empty() {
            format!("not dynamically controllable: inconsistent constraints ({shown})")
        } else {
            format!(
                "not dynamically controllable: the world decides the duration of {}, and some durations \
                 it may choose break {}",
                durations.join(", "),
                if shown.is_empty() { "the plan".into() } else { shown }
            )
        };
        NotControllable { actions, text }
    }

    /// The action's name with its parameters, e.g. `move(base, p1)`.
    pub fn action_text(&self, a: ActionId) -> String {
        let act = self.action(a);
        let task = self.domain.task(act.task);
        let args: Vec<String> = act.vars[..task.n_params.min(act.vars.len())]
            .iter()
            .map(|&v| self.term_name(STerm::Var(v)))
            .collect();
        format!("{}({})", task.name, args.join(", "))
    }

    /// What a timepoint is, for messages: `start of move(base, p1)`, `end of goal g1`, `origin`.
    pub fn tp_text(&self, tp: Timepoint) -> String {
        if tp.index() == 0 {
            return "origin".into();
        }
        for (i, act) in self.actions.iter().enumerate() {
            let which = if act.start == tp {
                "start"
            } else if act.end == tp {
                "end"
            } else if act.tps.contains(&tp) {
                "a timepoint"
            } else {
                continue;
            };
            return format!("{which} of {}", self.action_text(ActionId(i as u32)));
        }
        for g in &self.goals {
            let which = if g.st == tp {
                "start"
            } else if g.et == tp {
                "end"
            } else {
                continue;
            };
            return format!("{which} of {}", self.owner_text(Owner::Goal(g.goal)));
        }
        format!("timepoint {}", tp.index())
    }
}

/// Milliseconds as seconds for messages (`+oo` / `-oo` for the infinities).
fn secs(ms: Time) -> String {
    if ms >= INF {
        "+oo".into()
    } else if ms <= -INF {
        "-oo".into()
    } else {
        format!("{} s", ms as f64 / 1000.0)
    }
}
