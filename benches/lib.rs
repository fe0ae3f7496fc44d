//! mavtempo's criterion benches (`stn.rs`, `stnu.rs`, `planner.rs`); this library is empty.
