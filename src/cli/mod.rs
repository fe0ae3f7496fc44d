//! Command line: clap subcommands, wiring only. Each subcommand lives in its own file.

mod bench;
mod bench_cpu;
mod bench_ipc;
mod bench_suite;
mod check;
mod check_pddl;
pub mod demo;
mod dispatch_arg;
pub mod error;
mod experiment;
mod fuzz;
mod goal;
mod groups;
mod help_texts;
pub mod http_arg;
mod json_out;
mod mission_out;
mod nominal_world;
pub mod out;
mod plan;
mod plan_pddl;
mod report;
mod run;
mod runtime;
mod shutdown;
mod sim;
mod sitl_session;
mod soak;
mod vehicle_trace;

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

#[derive(Parser, Debug)]
#[command(
    name = "mavtempo",
    version,
    about = "Temporal planning, execution and plan repair for MAVLink vehicles"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Plan a mission and carry it out live on a MAVLink vehicle, repairing the plan as it runs.
    Run(run::RunArgs),
    /// Run the built-in simulated vehicle (behaves like ArduPilot Rover, or an AUV) on a socket.
    Sim(sim::SimArgs),
    /// Plan a problem and print the flexible plan (--json, --dot), checked by the independent checker.
    Plan(plan::PlanArgs),
    /// Check domain, problem and vehicle configuration files; errors as file:line:col, warnings for likely mistakes.
    Check(check::CheckArgs),
    /// Goal lists for a companion: send a .plan / .waypoints file, or serve goal uploads.
    Goal(goal::GoalArgs),
    /// Pictures of a mission report: Gantt chart, resources against their bounds, track map, HTML page.
    Report(report::ReportArgs),
    /// A mission on the built-in simulated vehicle: by default the rover story with five faults and two goals uploaded mid-mission.
    Demo(demo::DemoArgs),
    /// Measure performance; prints one JSON object per line with --json.
    Bench(bench::BenchArgs),
    /// Random missions with random faults on the built-in simulated vehicle; invariants checked.
    Soak(soak::SoakArgs),
    /// Fuzz the parsers and the goal intake with seeded mutations of the shipped files; failing inputs saved.
    Fuzz(fuzz::FuzzArgs),
    /// Experiments: `experiment dispatch` compares the dispatch policies under random goal arrivals.
    Experiment(experiment::ExperimentArgs),
}

/// Entry point of the binary: parses arguments, sets up logging, runs the subcommand.
pub fn main() -> ExitCode {
    let matches = groups::grouped(Cli::command()).get_matches();
    let cli = match Cli::from_arg_matches(&matches) {
        Ok(c) => c,
        Err(e) => e.exit(),
    };
    init_tracing();
    out::on_closed(match cli.command {
        // These drive or serve a vehicle: a closed stdout must not end them.
        Command::Demo(_) | Command::Run(_) | Command::Sim(_) | Command::Goal(_) => {
            out::OnClosed::KeepRunning
        }
        _ => out::OnClosed::Exit,
    });
    match cli.command {
        Command::Bench(args) => bench::run(args),
        Command::Check(args) => check::run(args),
        Command::Plan(args) => plan::run(args),
        Command::Demo(args) => demo::run(args),
        Command::Experiment(args) => experiment::run(args),
        Command::Fuzz(args) => fuzz::run(args),
        Command::Goal(args) => goal::run(args),
        Command::Report(args) => report::run(args),
        Command::Run(args) => run::run(args),
        Command::Sim(args) => sim::run(args),
        Command::Soak(args) => soak::run(args),
    }
}

fn init_tracing() {
    use std::io::IsTerminal;
    let filter = tracing_subscriber::EnvFilter::try_from_default_env()
        // The config check's warnings are printed by the subcommands themselves (check, run, demo): once.
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(DEFAULT_LOG_FILTER));
    // A second init (tests calling main twice) is harmless: ignore the error.
    let _ = tracing_subscriber::fmt()
        .with_env_filter(filter)
        // Colours only on a terminal: a log redirected to a file stays plain text.
        .with_ansi(std::io::stderr().is_terminal())
        .with_writer(std::io::stderr)
        .try_init();
}

/// The log's filter when `RUST_LOG` says nothing: warnings, but not the configuration check's, which the
/// subcommands print themselves.
const DEFAULT_LOG_FILTER: &str = "warn,mavtempo_executive::config_check=error";
