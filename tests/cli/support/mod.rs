//! Helpers shared by this binary's tests.

pub mod child;
pub mod demo_report;
