//! What `run` and `demo` share: the initial plan, the per-cycle trace (like seed 1 Fig. 6), the final summary
//! and the `--report` JSON.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use clap::Args;

use super::error::CliError;
use crate::cli::out::outln;
use crate::exec::executive::Fate;
use crate::exec::mission::MissionReport;
use crate::exec::trace::{names, CycleRecord, TraceEvent};
use crate::model::{Domain, Problem};
use crate::plan::PartialPlan;
use crate::planner::{solve, Budget};

/// What `run` and `demo` plan with and write: the initial plan's budget, the trace, the report and its page.
#[derive(Args, Debug, Clone)]
pub struct MissionOutArgs {
    /// Planning steps for the initial plan.
    #[arg(long, default_value_t = 200_000)]
    pub max_steps: u64,
    /// Print only the summary, not the per-cycle trace.
    #[arg(long)]
    pub quiet: bool,
    /// Write the mission report (cycles, events, plan changes, goals with fates and reasons, resource
    /// levels vs bounds) as JSON.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Write the report's page (Gantt chart, resources against their bounds, map, goals) as one HTML file.
    #[arg(long)]
    pub html: Option<PathBuf>,
}

impl MissionOutArgs {
    /// Fails before the mission when the `--report` or `--html` file cannot be written (a missing or
    /// read-only directory): found after the whole mission, the mission's record would be lost.
    pub fn check_writable(&self) -> Result<(), CliError> {
        for path in self.report.iter().chain(&self.html) {
            write_atomic(path, None)?;
        }
        Ok(())
    }

    /// Writes the `--report` JSON and the `--html` page asked for (`title`: the page's), saying where.
    pub fn write(&self, r: &MissionReport, title: &str) -> Result<(), CliError> {
        if let Some(path) = &self.report {
            write_report(path, r)?;
            outln!("report written to {}", path.display());
        }
        if let Some(path) = &self.html {
            let charts = crate::report::charts_of(r)?;
            crate::report::write_page(path, title, &charts)?;
            outln!("page written to {}", path.display());
        }
        Ok(())
    }
}

/// The planner's plan for the initial problem.
pub fn initial_plan(
    domain: Arc<Domain>,
    problem: Arc<Problem>,
    max_steps: u64,
) -> Result<PartialPlan, CliError> {
    let name = problem.name.clone();
    solve(domain, problem, Budget::steps(max_steps))
        .map(|p| p.plan)
        .map_err(|failure| CliError::NoInitialPlan {
            problem: name,
            failure,
        })
}

/// The per-cycle trace: a cycle is printed when something happened in it; a postponed action is printed
/// when it starts being postponed, not again in every cycle that postpones it further.
#[derive(Default)]
pub struct TracePrinter {
    postponed: Vec<String>,
}

impl TracePrinter {
    pub fn cycle(&mut self, c: &CycleRecord) {
        let now_postponed: Vec<String> = c
            .events
            .iter()
            .filter_map(|e| match e {
                TraceEvent::Postponed { action } => Some(action.clone()),
                _ => None,
            })
            .collect();
        let lines: Vec<String> = c
            .events
            .iter()
            .filter(|e| match e {
                TraceEvent::Postponed { action } => !self.postponed.contains(action),
                _ => true,
            })
            .map(TraceEvent::line)
            .collect();
        self.postponed = now_postponed;
        if lines.is_empty() {
            return;
        }
        outln!(
            "[{:>8.1} s] cycle {} (sense {} µs, repair {} µs, act {} µs)",
            c.time_ms as f64 / 1000.0,
            c.index,
            c.sense_us,
            c.repair_us,
            c.act_us
        );
        for l in lines {
            outln!("             {l}");
        }
    }
}

pub fn print_summary(r: &MissionReport) {
    outln!();
    outln!(
        "mission ended ({}) at {:.1} s after {} cycles",
        r.end,
        r.duration_ms as f64 / 1000.0,
        r.cycle_times.count
    );
    for g in &r.goals {
        let fate = match g.fate {
            Fate::Achieved => "achieved",
            Fate::Rejected => "REJECTED",
            Fate::Pending => "pending",
            Fate::Cancelled => "cancelled",
        };
        match &g.reason {
            None => outln!("  {:<6} {fate}", g.name),
            Some(reason) => outln!("  {:<6} {fate}: {}", g.name, reason.operator_text()),
        }
    }
    for rp in &r.replannings {
        let rejected: Vec<String> = rp.rejected.iter().map(|x| x.goal.clone()).collect();
        outln!(
            "complete replanning at {:.1} s after \"{}\": {} ({} attempts, {} steps); kept: {}; rejected: {}",
            rp.time_ms as f64 / 1000.0,
            rp.abort,
            rp.error.as_deref().unwrap_or(&rp.outcome.to_string()),
            rp.attempts.len(),
            rp.steps,
            names(&rp.kept),
            names(&rejected)
        );
    }
    outln!(
        "plan repairs: {} ({} repair steps), complete replannings: {}, actions launched: {}",
        r.counters.repairs,
        r.counters.repair_steps,
        r.counters.replans,
        r.counters.launches
    );
    outln!(
        "cycle time (executive CPU): p50 {} µs, p99 {} µs, max {} µs over {} cycles",
        r.cycle_times.p50_us,
        r.cycle_times.p99_us,
        r.cycle_times.max_us,
        r.cycle_times.count
    );
    if let Some(s) = &r.shutdown {
        outln!(
            "shutdown: {} ({} mode {}; actions ended: {}; ACK {}; last mode {})",
            s.outcome,
            s.action,
            s.mode.map_or("none".to_string(), |m| m.to_string()),
            if s.stopped.is_empty() {
                "none".to_string()
            } else {
                s.stopped.join(", ")
            },
            s.ack.as_deref().unwrap_or("none"),
            s.last_mode.map_or("none".to_string(), |m| m.to_string())
        );
    }
}

pub fn write_report(path: &Path, r: &MissionReport) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(r)?;
    write_atomic(path, Some(text.as_bytes()))
}

/// Writes `bytes` to `path` through a temporary file in the same directory, renamed over `path` once
/// whole: a full disk or a crash leaves the previous file or none, never a truncated one. With `None`, only
/// checks that it could (the temporary file is created and removed).
pub fn write_atomic(path: &Path, bytes: Option<&[u8]>) -> Result<(), CliError> {
    let failed = |source| CliError::Write {
        path: path.display().to_string(),
        source,
    };
    let name = path
        .file_name()
        .ok_or_else(|| failed(std::io::Error::other("not a file name")))?;
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".{}.tmp", std::process::id()));
    let tmp = path.with_file_name(tmp_name);
    let written = (|| {
        use std::io::Write;
        let mut f = std::fs::File::create(&tmp)?;
        if let Some(b) = bytes {
            f.write_all(b)?;
            f.sync_all()?;
        }
        Ok(())
    })();
    let done = written.and_then(|()| match bytes {
        Some(_) => std::fs::rename(&tmp, path),
        None => std::fs::remove_file(&tmp),
    });
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done.map_err(failed)
}

/// One line on how the vehicle became ready (`run`, `demo`).
pub fn ready_line(r: &crate::vehicle::readiness::ReadyReport) -> String {
    let secs =
        |ms: Option<u64>| ms.map_or("?".to_string(), |m| format!("{:.1}", m as f64 / 1000.0));
    let mut line = format!(
        "position fix after {} s, armed after {} s ({} ARM attempts), navigating after {} s",
        secs(r.fix_after_ms),
        secs(r.armed_after_ms),
        r.arm_attempts,
        secs(r.navigation_after_ms)
    );
    if r.arm_attempts > 1 {
        if let Some(last) = r.refusals.last() {
            line.push_str(&format!("; refused before: {last}"));
        }
    }
    line
}
