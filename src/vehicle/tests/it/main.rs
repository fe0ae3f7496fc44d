//! The vehicle layer's tests: bindings, goal intake and files, the MAVLink link, the mock, against the SITL.
//! One test binary for the crate (each module was a test crate of its own); helpers in `support`.

#[macro_use]
extern crate mavtempo_testkit;

mod support;

mod vehicle_bindings;
mod vehicle_files;
mod vehicle_gcs_missions;
mod vehicle_gcs_port;
mod vehicle_goal_cancel_link;
mod vehicle_intake;
mod vehicle_link;
mod vehicle_mock;
mod vehicle_sitl;
