//! The temporal layer's tests: language, PDDL, planner, STN / STNU, plan checker.
//! One test binary for the crate (each module was a test crate of its own); helpers in `support`.

#[macro_use]
extern crate mavtempo_testkit;

mod forward_plateaus;
mod lang_domains;
mod lang_fixtures;
mod lang_fuzz;
mod lang_roundtrip;
mod pddl;
mod pddl_numeric;
mod plan_dc;
mod planner_domains;
mod planner_no_false_infeasible;
mod planner_reachability;
mod planner_search;
mod stn_props;
mod stnu_props;
mod validate;
