//! From a sequential ground plan to a flexible partial plan of the model: each step inserted as an
//! instance of its task with its parameters bound, the deordered precedences ([`super::deorder`]) added
//! between steps, and the POCL search ([`crate::planner::Search`]) left to do the rest — link each
//! condition to its establisher, order the threats, settle the resources — from that root. The steps
//! already say which actions are needed, so the search mostly links and orders; the STN schedules the
//! durations. The plan found is an ordinary plan of the planner, checked like any other.

use std::sync::Arc;

use super::{deorder, GroundTask};
use crate::model::{Domain, Problem, TaskId};
use crate::plan::{ActionId, PartialPlan};
use crate::planner::{Budget, FailReason, Planned, Search, StepOutcome};
use crate::stn::INF;

/// Why a sequential plan could not be made a plan of the model.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EmbedError {
    #[error("invalid problem: {0}")]
    Root(String),
    /// No task of the model takes the step with its arguments (an action the translation dropped).
    #[error("no task of the model is ({0})")]
    NoTask(String),
    #[error("the deordered precedences are inconsistent with the model's durations: {0}")]
    Order(String),
    #[error("the partial plan was not completed: {0}")]
    Search(FailReason),
}

/// The partial plan of `steps` (indices into `task.actions`), completed by the POCL search within
/// `max_steps` planning steps.
pub fn embed(
    domain: Arc<Domain>,
    problem: Arc<Problem>,
    task: &GroundTask,
    steps: &[u32],
    max_steps: u64,
) -> Result<Planned, EmbedError> {
    let mut plan = PartialPlan::new(domain.clone(), problem.clone())
        .map_err(|e| EmbedError::Root(e.to_string()))?;
    let mut actions: Vec<ActionId> = Vec::with_capacity(steps.len());
    for &s in steps {
        let Some(ga) = task.actions.get(s as usize) else {
            return Err(EmbedError::NoTask(format!("step {s}")));
        };
        let text = || format!("{} {}", ga.name, ga.args.join(" "));
        let objects: Option<Vec<_>> = ga.args.iter().map(|a| problem.object_id(a)).collect();
        let objects = objects.ok_or_else(|| EmbedError::NoTask(text()))?;
        // An action whose duration depends on its parameters has one task per combination: the first
        // whose bindings admit the arguments.
        let found = domain
            .tasks
            .iter()
            .enumerate()
            .filter(|(_, t)| t.name == ga.name && t.n_params == objects.len())
            .find_map(|(i, _)| {
                let level = plan.save();
                let inserted = plan.insert_action(TaskId(i as u32)).and_then(|a| {
                    let vars = plan.action(a).vars.clone();
                    for (v, o) in vars.iter().zip(&objects) {
                        plan.bind_var(*v, *o)?;
                    }
                    Ok(a)
                });
                match inserted {
                    Ok(a) => Some(a),
                    Err(_) => {
                        plan.restore(level);
                        None
                    }
                }
            });
        actions.push(found.ok_or_else(|| EmbedError::NoTask(text()))?);
    }
    for (i, j) in deorder::precedences(task, steps) {
        let (before, after) = (plan.action(actions[i]).end, plan.action(actions[j]).start);
        plan.constrain(before, after, 1, INF)
            .map_err(|e| EmbedError::Order(e.to_string()))?;
    }
    let mut search = Search::new(plan);
    match search.run(Budget::steps(max_steps)) {
        StepOutcome::Solved => Ok(Planned {
            steps: search.steps(),
            backtracks: search.backtracks(),
            not_controllable: search.not_controllable().cloned(),
            plan: search.into_plan(),
        }),
        StepOutcome::Failed(r) => Err(EmbedError::Search(r)),
        StepOutcome::Progress => Err(EmbedError::Search(FailReason::Deadline {
            steps: search.steps(),
        })),
    }
}
