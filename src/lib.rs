//! mavtempo: IxTeT-eXeC style temporal planning, execution and plan repair for MAVLink vehicles.
//!
//! Data flow: `lang` → `model` → `planner` (over `plan`, `stn`) → `exec` → `dispatch` → `vehicle`.

pub mod cli;
pub mod dispatch;
pub mod exec;
pub mod fuzz;
pub mod lang;
pub mod model;
pub mod pddl;
pub mod plan;
pub mod planner;
pub mod report;
pub mod stn;
pub mod vehicle;
