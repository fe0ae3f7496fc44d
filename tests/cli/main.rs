//! The application's tests through its executable (`mavtempo …` as a user runs it).
//! One test binary (each module was a test crate of its own); helpers in `support`.

mod support;

mod cli_check;
mod cli_check_pddl;
mod cli_closed_stdout;
mod cli_demo;
mod cli_fig2_upload;
mod cli_goal;
mod cli_goal_signing;
mod cli_outputs;
mod cli_shutdown;
mod cli_sim;
mod cli_soak_dispatch;
mod cli_soak_signal;
mod cli_stderr;
mod cli_vehicle_lost;
mod demo_nominal;
mod operator_words;
