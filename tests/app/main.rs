//! The application's tests in process, across the layers: the demo on the built-in SITL, the live page, the reports, the experiment, the fuzz targets.
//! One test binary (each module was a test crate of its own); helpers in `support`.

mod support;

mod bench_generators;
mod demo_deterministic;
mod demo_far_goal;
mod demo_lossy_link;
mod dispatch_experiment;
mod dispatch_fig2_reservoirs;
mod exec_limits;
mod exec_outputs;
mod exec_start_offset;
mod fuzz_smoke;
mod live_ardupilot;
mod live_copter;
mod live_domains;
mod live_fence;
mod live_page;
mod live_page_limits;
mod live_page_origin;
mod live_px4;
mod report_charts;
mod vehicle_authority;
