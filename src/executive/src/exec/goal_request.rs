//! Goal request acceptance (seed 1 §3.3 "Goal request"): a goal g is rejected if
//! `{t^g − st^g ∈ I^d, st^g − origin ∈ I^g, st^g − origin ≥ t + d_achiev}` is not consistent with the plan at
//! the current time t. An accepted goal is constrained after each running action whose propositions its own
//! proposition threatens, and enters the plan as an open condition.

use std::sync::Arc;

use mavtempo_temporal::model::{Goal, GoalId, Time};
use mavtempo_temporal::plan::{ActionId, CondKind, PartialPlan, PlanError};

/// Why a goal was rejected.
#[derive(Clone, Debug, PartialEq, thiserror::Error, serde::Serialize, serde::Deserialize)]
#[serde(tag = "test", rename_all = "snake_case")]
pub enum Rejection {
    #[error("duration or start window inconsistent with the plan: {error}")]
    Window { error: String },
    #[error(
        "cannot start at least d_achiev = {achiev_ms} ms after now ({now_ms} ms) within its window"
    )]
    TooLate { now_ms: Time, achiev_ms: Time },
    #[error("conflicts with a running action: {error}")]
    Running { error: String },
}

/// Adds `goal` to the plan if the acceptance test passes; on rejection the plan is left as it was.
pub fn request(
    plan: &mut PartialPlan,
    goal: Goal,
    t: Time,
    running: &[ActionId],
) -> Result<GoalId, Rejection> {
    let old_problem = plan.problem().clone();
    let level = plan.save();
    let mut problem = (*old_problem).clone();
    let g = GoalId::from_index(problem.goals.len());
    let achiev = goal.achieve;
    problem.goals.push(goal);
    plan.set_problem(Arc::new(problem));
    let result = (|| {
        let cond = plan.add_goal(g).map_err(|e| Rejection::Window {
            error: e.to_string(),
        })?;
        let st = plan.cond(cond).from;
        plan.not_before(st, t.saturating_add(achiev))
            .map_err(|_| Rejection::TooLate {
                now_ms: t,
                achiev_ms: achiev,
            })?;
        order_after_threatened(plan, cond, running).map_err(|e| Rejection::Running {
            error: e.to_string(),
        })?;
        Ok(g)
    })();
    if result.is_err() {
        plan.restore(level);
        plan.set_problem(old_problem);
    }
    result
}

/// "The goal is constrained to occur after each running action a such that the goal proposition threatens
/// a proposition in a": same attribute, possibly the same instance, a value possibly different.
fn order_after_threatened(
    plan: &mut PartialPlan,
    cond: mavtempo_temporal::plan::CondId,
    running: &[ActionId],
) -> Result<(), PlanError> {
    let c = plan.cond(cond).clone();
    for &a in running {
        let act = plan.action(a);
        let end = act.end;
        let threatens = act.conds.iter().any(|&k| {
            let h = plan.cond(k);
            matches!(h.kind, CondKind::Hold { .. })
                && h.attr == c.attr
                && h.args
                    .iter()
                    .zip(&c.args)
                    .all(|(&x, &y)| plan.bindings().possibly_equal(x, y))
                && !plan.bindings().necessarily_equal(h.value, c.value)
        });
        if threatens {
            plan.order(end, c.from)?;
        }
    }
    Ok(())
}
