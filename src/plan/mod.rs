//! The plan: the planner's output ([`solution`]) and its independent checker ([`validate`]).

pub mod solution;
pub mod validate;
