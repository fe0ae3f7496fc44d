//! The executive's tests: its cycle on the mock vehicle and manual clock, dispatch, configuration checks.
//! One test binary for the crate (each module was a test crate of its own); helpers in `support`.

#[macro_use]
extern crate mavtempo_testkit;

mod support;

mod config_check;
mod config_errors;
mod config_reference;
mod dispatch_exec_scenarios;
mod dispatch_marking;
mod dispatch_plan_adapter;
mod dispatch_scenarios;
mod exec_cycle;
mod exec_dala;
mod exec_end_still;
mod exec_end_to_end;
mod exec_goal_cancel;
mod exec_goal_insertion;
mod exec_level_drain;
mod exec_level_resolution;
mod exec_mapping;
mod exec_mission;
mod exec_new_place;
mod exec_no_loop;
mod exec_repair_budget;
mod exec_replan;
mod exec_reserve;
mod exec_rover;
mod exec_rules;
mod exec_squeeze;
mod exec_wall_budget;
mod geodesy_one_model;
