//! The benchmarks behind `mavtempo bench …` (speed is measured here and in `benches/`, never in tests): each
//! measures one layer from outside it.

pub mod dispatch;
pub mod exec;
pub mod plan;
pub mod repair;
pub mod stn;
pub mod stnu;
pub mod suite;
pub mod vehicle;
