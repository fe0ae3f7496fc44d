//! Instantiation at start: the planner leaves variables unbound where any value works (least commitment);
//! an action can only be sent to the vehicle with every argument known. Before its start timepoint is
//! executed, each argument still unbound is bound to the first value of its domain that keeps the binding
//! CSP and the STN consistent and adds no flaw (so the executing plan stays a solution plan).

use mavtempo_temporal::plan::{ActionId, PartialPlan, STerm};

/// Why an action's argument could not be bound at its start.
#[derive(Clone, Debug, PartialEq, thiserror::Error, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InstantiateError {
    /// No value of the argument's domain is consistent with the plan.
    #[error("no value of {var} fits")]
    NoValue { var: String },
    /// The value chosen earlier was consistent but binding it failed.
    #[error("binding {var} failed")]
    BindingFailed { var: String },
}

/// Binds the unbound arguments of `a`; `Err` names the argument no value fits.
pub fn instantiate_at_start(plan: &mut PartialPlan, a: ActionId) -> Result<(), InstantiateError> {
    let vars = plan.action(a).vars.clone();
    for v in vars {
        if plan.bindings().value(STerm::Var(v)).is_some() {
            continue;
        }
        let flaws_before = plan.flaws().len();
        let candidates = plan.bindings().domain(v).to_vec();
        let mut fallback = None;
        let mut chosen = false;
        for o in candidates {
            let level = plan.save();
            let ok = plan.bind_var(v, o).is_ok();
            if ok && plan.flaws().len() <= flaws_before {
                chosen = true;
                break;
            }
            if ok && fallback.is_none() {
                fallback = Some(o);
            }
            plan.restore(level);
        }
        if chosen {
            continue;
        }
        // No value keeps the plan flawless: the first consistent one, plan repair handles the new flaws.
        let Some(o) = fallback else {
            return Err(InstantiateError::NoValue {
                var: plan.term_name(STerm::Var(v)),
            });
        };
        let ok = plan.bind_var(v, o).is_ok();
        if !ok {
            return Err(InstantiateError::BindingFailed {
                var: plan.term_name(STerm::Var(v)),
            });
        }
    }
    Ok(())
}
