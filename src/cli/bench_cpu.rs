//! `mavtempo bench cpu [--json]`: the executive's CPU over a Dala-length mission (seed 1 §5: the run lasted
//! 1,285 s; IxTeT-eXeC used 541 s of CPU on Dala's computer). domains/rover/problems/dala.ixt is executed
//! against the in-process SITL on sitl/scenarios/dala.toml, stepped by the executive's clock, to the mission's
//! end (its horizon is 25 min: the paper's 1,285 s run did not wait out the final home goal); the
//! executive's time is divided by the mission's. The goals' fates are printed with the figures.

use std::process::ExitCode;
use std::sync::Arc;

use serde::Serialize;

use super::demo::exec_config;
use super::error::CliError;
use super::mission_out::initial_plan;
use super::sitl_session::{SessionSpec, SitlSession};
use crate::cli::out::outln;
use crate::exec::executive::Executive;
use crate::exec::mission::{run_mission, MissionOptions};
use crate::lang;
use crate::model::Time;

const DOMAIN: &str = include_str!("../../domains/rover/rover.ixt");
const DALA: &str = include_str!("../../domains/rover/problems/dala.ixt");
const SCENARIO: &str = include_str!("../../sitl/scenarios/dala.toml");

/// Past the problem's horizon, a mission still running is cut here (ms).
const END_MARGIN_MS: Time = 60_000;

#[derive(Clone, Debug, Serialize)]
pub struct CpuFigures {
    pub problem: String,
    /// How the mission ended (`finished`, `time_limit`, ...).
    pub end: String,
    /// Simulated mission time, s.
    pub mission_s: f64,
    pub cycles: usize,
    /// The cycle's configuration: timestep ts and repair share μ.
    pub timestep_ms: Time,
    pub repair_share: f64,
    /// Sum of the cycles' sense + repair + act times (measured around each part), s.
    pub cycle_cpu_s: f64,
    /// `cycle_cpu_s` over the mission time, in percent of one core (target < 1 %).
    pub cpu_percent_of_core: f64,
    /// CPU of the thread running the executive (cycles, complete replanning, and the pacer's polling of
    /// the link), s; from /proc/thread-self/schedstat where available.
    pub thread_cpu_s: Option<f64>,
    /// CPU of the whole process, the SITL and the MAVLink link tasks included, s.
    pub process_cpu_s: Option<f64>,
    pub repairs: u64,
    pub replans: u64,
    /// Each goal's fate and why.
    pub goals: Vec<crate::exec::executive::GoalFate>,
    /// Most launches in a row of one action instance without a nominal completion (its retries).
    pub max_launches_of_one_action: usize,
    /// Wall time of the run, s.
    pub wall_s: f64,
}

/// Runs the Dala mission for at most `limit_ms` of mission time (to its end when `None`) and measures it.
pub fn measure(limit_ms: Option<Time>) -> Result<CpuFigures, CliError> {
    let domain = Arc::new(lang::parse_domain("domains/rover/rover.ixt", DOMAIN)?);
    let problem = Arc::new(lang::parse_problem(
        "domains/rover/problems/dala.ixt",
        DALA,
        &domain,
    )?);
    let plan = initial_plan(domain.clone(), problem.clone(), 200_000)?;
    let spec = SessionSpec::demo_rover(SCENARIO, "sitl/scenarios/dala.toml")?;
    let mut session = SitlSession::start(&domain, &problem, spec)?;
    let cfg = exec_config();
    let (timestep_ms, repair_share) = (cfg.timestep_ms, cfg.repair_share);
    let mut ex = Executive::build(plan, cfg, session.vehicle_setup());
    let opts = MissionOptions {
        time_limit_ms: limit_ms.unwrap_or(problem.horizon + END_MARGIN_MS),
        ..MissionOptions::default()
    };
    let mut pacer = session.step_pacer(Arc::default());
    let (thread0, process0) = (thread_cpu_ns(), process_cpu_ns());
    let wall = std::time::Instant::now();
    let report = run_mission(
        &mut ex,
        &mut session.vehicle,
        &mut pacer,
        &opts,
        &mut |_, _| {},
    );
    let wall_s = wall.elapsed().as_secs_f64();
    let thread = thread_cpu_ns().zip(thread0).map(|(b, a)| b - a);
    let process = process_cpu_ns().zip(process0).map(|(b, a)| b - a);
    drop(session);
    let mission_s = report.duration_ms as f64 / 1_000.0;
    if mission_s <= 0.0 {
        return Err(CliError::NoMission);
    }
    let cycle_cpu_s = report.cycle_times.total_us as f64 / 1e6;
    Ok(CpuFigures {
        problem: problem.name.clone(),
        end: serde_json::to_value(&report.end)
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_else(|| format!("{:?}", report.end)),
        mission_s,
        cycles: report.cycle_times.count,
        timestep_ms,
        repair_share,
        cycle_cpu_s,
        cpu_percent_of_core: 100.0 * cycle_cpu_s / mission_s,
        thread_cpu_s: thread.map(|ns| ns as f64 / 1e9),
        process_cpu_s: process.map(|ns| ns as f64 / 1e9),
        repairs: report.counters.repairs,
        replans: report.counters.replans,
        max_launches_of_one_action: report.launches_in_a_row().into_values().max().unwrap_or(0),
        goals: report.goals.clone(),
        wall_s,
    })
}

/// Nanoseconds on CPU of the calling thread (Linux schedstat).
fn thread_cpu_ns() -> Option<u64> {
    schedstat_ns("/proc/thread-self/schedstat")
}

/// Nanoseconds on CPU of every thread of the process (Linux schedstat).
fn process_cpu_ns() -> Option<u64> {
    let tasks = std::fs::read_dir("/proc/self/task").ok()?;
    let mut total = 0;
    for t in tasks.flatten() {
        // A thread that ended meanwhile is simply not counted.
        total += schedstat_ns(t.path().join("schedstat")).unwrap_or(0);
    }
    Some(total)
}

fn schedstat_ns(path: impl AsRef<std::path::Path>) -> Option<u64> {
    let text = std::fs::read_to_string(path).ok()?;
    text.split_whitespace().next()?.parse().ok()
}

pub fn run(json: bool) -> ExitCode {
    let figures = measure(None).map(|f| vec![f]);
    super::bench::show("bench cpu", json, figures, |figures| {
        for f in figures {
            print_figures(f);
        }
    })
}

fn print_figures(f: &CpuFigures) {
    let s = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3} s"));
    outln!(
        "{}: {:.1} s of mission ({}), {} cycles at ts {} ms, μ {}: executive {:.3} s = {:.3} % of a core \
         (thread {}, process with SITL {}), {} repairs, {} replans, {:.1} s wall",
        f.problem,
        f.mission_s,
        f.end,
        f.cycles,
        f.timestep_ms,
        f.repair_share,
        f.cycle_cpu_s,
        f.cpu_percent_of_core,
        s(f.thread_cpu_s),
        s(f.process_cpu_s),
        f.repairs,
        f.replans,
        f.wall_s
    );
    for g in &f.goals {
        outln!("  {:<12} {:?} {}", g.name, g.fate, g.reason_text());
    }
    outln!(
        "most launches of one action: {}",
        f.max_launches_of_one_action
    );
}

#[cfg(test)]
mod tests {
    /// A minute of the Dala mission: the figures are there and consistent (no timing asserted).
    #[test]
    fn a_short_dala_run_reports_its_figures() {
        let f = super::measure(Some(60_000)).expect("the Dala mission runs on the SITL");
        assert!(f.mission_s > 0.0 && f.mission_s <= 61.0, "{f:?}");
        assert!(f.cycles > 0, "{f:?}");
        assert!(
            (f.cpu_percent_of_core - 100.0 * f.cycle_cpu_s / f.mission_s).abs() < 1e-9,
            "{f:?}"
        );
        let v = serde_json::to_value(&f).expect("serialises");
        for key in ["cpu_percent_of_core", "mission_s", "cycles", "timestep_ms"] {
            assert!(v.get(key).is_some(), "{key} missing in {v}");
        }
    }

    /// Seed 1 §5's Dala mission to its end, live on the SITL over sockets: every goal achieved, the
    /// slow move stopped and repaired, few repairs, no action launched more than twice.
    #[test]
    fn the_dala_mission_achieves_every_goal() {
        let f = super::measure(None).expect("the Dala mission runs on the SITL");
        assert_eq!(f.end, "finished", "{f:?}");
        assert_eq!(f.goals.len(), 7);
        for g in &f.goals {
            assert_eq!(g.fate, crate::exec::executive::Fate::Achieved, "{g:?}");
        }
        assert!((1..=6).contains(&f.repairs), "{} repairs", f.repairs);
        assert!(f.max_launches_of_one_action <= 2, "{f:?}");
    }
}
