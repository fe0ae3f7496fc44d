//! Helpers shared by this crate's tests.

pub mod gcs_config;
pub mod reports;
