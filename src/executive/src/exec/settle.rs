//! Settling what repair cannot fix (the executive's side of [`super::failures`]): an action instance's
//! k-th same failure bans it and rejects the goals that depended on it; too many plan changes in a minute
//! reject a goal; a replanning's plan that needs a banned instance is not adopted.

use super::executive::{Executive, Fate};
use super::failures::{dependent_goals, Instance, PlanChangeKind};
use super::outcome::{AbortReason, FateReason, PlanChurn};
use super::trace::TraceEvent;
use mavtempo_temporal::model::{GoalId, Time};
use mavtempo_temporal::plan::{ActionId, PartialPlan, STerm};

/// Why a replanning's plan cannot be adopted: it needs a banned instance.
pub struct BannedInPlan {
    pub action: ActionId,
    pub reason: String,
    /// The goals of that plan that depend on the action.
    pub goals: Vec<GoalId>,
}

impl Executive {
    /// Action `a` failed at `now` (`what`: how, e.g. "failed: not visible"). Call before the failure's
    /// effects are integrated (the goals that depended on the action are found through its causal links).
    pub fn action_failed(&mut self, a: ActionId, what: &str, now: Time) {
        let inst = Instance::of(&self.plan, a);
        let Some(reason) = self.failures.failed(&inst, what, now) else {
            return;
        };
        for g in dependent_goals(&self.plan, a) {
            self.reject_goal(
                g,
                FateReason::InstanceBanned {
                    ban: reason.clone(),
                },
            );
        }
        // The plan (repaired) would insert the same instance again: a complete replanning, which does not
        // adopt a plan needing it, settles the rest.
        self.abort_with(AbortReason::InstanceBanned { ban: reason });
    }

    /// A nominal completion of action `a`.
    pub fn action_succeeded(&mut self, a: ActionId) {
        let inst = Instance::of(&self.plan, a);
        self.failures.succeeded(&inst);
    }

    /// Why action `a` must not be launched (a banned instance), if it must not.
    pub fn launch_banned(&self, a: ActionId) -> Option<AbortReason> {
        self.failures
            .banned_action(&self.plan, a)
            .map(|(i, r)| AbortReason::LaunchBanned {
                instance: i.to_string(),
                ban: r.to_string(),
            })
    }

    /// A plan change (repair or complete replanning) at `now`; past the per-minute bound, the goals served by
    /// the most failing instance (else the lowest-priority, least flexible goal) are rejected and execution
    /// aborted so that a replanning without them follows.
    pub fn plan_changed(&mut self, now: Time, kind: PlanChangeKind) {
        let Some(n) = self.failures.plan_changed(now, kind) else {
            return;
        };
        let mut churn = PlanChurn {
            changes: n,
            failing: None,
            how: "failed".to_string(),
        };
        let mut goals = Vec::new();
        // The instance that churns: the one failing most, else the one relaunched most; only its goals
        // are rejected.
        let culprit = self
            .failures
            .most_failing()
            .map(|(i, k)| (i, k, "failed"))
            .or_else(|| {
                self.failures
                    .most_relaunched(now)
                    .map(|(i, k)| (i, k, "launched"))
            });
        if let Some((inst, k, how)) = culprit {
            churn.failing = Some((inst.to_string(), k));
            churn.how = how.to_string();
            for a in self.plan.live_actions().collect::<Vec<_>>() {
                if inst.possibly(&self.plan, a) {
                    goals.extend(dependent_goals(&self.plan, a));
                }
            }
        }
        if goals.is_empty() {
            goals.extend(super::replan::goal_to_reject(&self.plan));
        }
        goals.sort();
        goals.dedup();
        for g in goals {
            self.reject_goal(g, FateReason::PlanChurn(churn.clone()));
        }
        self.abort_with(AbortReason::PlanChurn(churn));
    }

    /// A plan from complete replanning that needs a banned instance: first, the instances it may still
    /// avoid (an unbound argument) are kept apart from the banned values; then the first action that is
    /// necessarily banned, if any.
    pub fn banned_in_plan(&self, plan: &mut PartialPlan) -> Option<BannedInPlan> {
        if !self.failures.any_banned() {
            return None;
        }
        let actions: Vec<ActionId> = plan.live_actions().collect();
        for &a in &actions {
            if let Some((_, r)) = self.failures.banned_action(plan, a) {
                return Some(BannedInPlan {
                    action: a,
                    reason: r.to_string(),
                    goals: dependent_goals(plan, a),
                });
            }
            let maybe: Vec<(Instance, String)> = self
                .failures
                .possibly_banned(plan, a)
                .map(|(i, r)| (i.clone(), r.to_string()))
                .collect();
            for (inst, reason) in maybe {
                if !avoid(plan, a, &inst) {
                    return Some(BannedInPlan {
                        action: a,
                        reason,
                        goals: dependent_goals(plan, a),
                    });
                }
            }
        }
        None
    }

    /// Rejects goal `g` (once) with `reason`.
    pub fn reject_goal(&mut self, g: GoalId, reason: FateReason) {
        if self.goals.fate(g).is_some_and(|f| f.fate != Fate::Pending) {
            return;
        }
        let name = self.plan.problem().goals[g.index()].name.clone();
        self.set_fate(g, Fate::Rejected, Some(reason.clone()));
        self.trace(TraceEvent::GoalRejected { goal: name, reason });
    }
}

/// Keeps action `a` apart from instance `inst` by separating one unbound argument from its banned value.
fn avoid(plan: &mut PartialPlan, a: ActionId, inst: &Instance) -> bool {
    let act = plan.action(a);
    let n = plan.domain().task(act.task).n_params;
    let vars: Vec<_> = act.vars[..n].to_vec();
    for (v, name) in vars.into_iter().zip(&inst.args) {
        let Some(o) = plan.problem().object_id(name) else {
            continue;
        };
        if plan
            .bindings()
            .necessarily_equal(STerm::Var(v), STerm::Obj(o))
        {
            continue;
        }
        let level = plan.save();
        if plan.keep_var_off(v, o).is_ok() && plan.flaws().is_empty() {
            return true;
        }
        plan.restore(level);
    }
    false
}
