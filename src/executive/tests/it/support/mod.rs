//! Helpers shared by this crate's tests.

pub mod mission;
pub mod picture_goal;
pub mod rover_mock;
pub mod shopping;
