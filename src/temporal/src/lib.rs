//! The temporal core (seed 1 §2): what is planned and how. No I/O beyond reading domain files, no vehicle.
//!
//! Data flow: `lang` / `pddl` (text) → `model` (domains, problems) → `planner` (a lifted partial-order
//! causal-link search over `plan`, partial plans whose time is an `stn` and whose variables a binding CSP).
//! `plan::validate` is the independent plan checker: it reads a plan and the model and depends on no search.

pub mod lang;
pub mod model;
pub mod pddl;
pub mod plan;
pub mod planner;
pub mod stn;
