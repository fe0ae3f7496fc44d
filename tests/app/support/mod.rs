//! Helpers shared by this binary's tests.

pub mod live_run;
