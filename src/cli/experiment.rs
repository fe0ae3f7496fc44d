//! `mavtempo experiment dispatch [--seeds N] [--json]`: the dispatch policies compared on the shipped
//! missions with goals arriving at random (src/executive/src/dispatch/experiment). A progress bar on stderr; a table on
//! stdout, or one JSON object per scenario and policy with `--json`.

use std::io::Write;
use std::process::ExitCode;

use clap::{Args, Subcommand};

use crate::cli::out::outln;
use crate::dispatch::PolicyKind;
use crate::experiment::{self, ExperimentOptions, Row};

#[derive(Args, Debug)]
pub struct ExperimentArgs {
    #[command(subcommand)]
    pub what: Experiment,
}

#[derive(Subcommand, Debug)]
pub enum Experiment {
    /// earliest / latest / goal-driven dispatch under random goal arrivals.
    Dispatch(DispatchArgs),
}

#[derive(Args, Debug)]
pub struct DispatchArgs {
    /// Number of seeded runs per scenario and policy.
    #[arg(long, default_value_t = 20)]
    pub seeds: u64,
    /// The first seed (runs use seeds first..first+N).
    #[arg(long, default_value_t = 1)]
    pub first_seed: u64,
    /// Mean number of goals uploaded per hour (Poisson rate).
    #[arg(long, default_value_t = 0.4)]
    pub per_hour: f64,
    /// The executive's deterministic planning budget n: μ·n plan-repair steps per cycle, 40·n steps per
    /// complete-replanning attempt.
    #[arg(long, default_value_t = 10)]
    pub repair_steps: u64,
    /// Only these scenarios (auv, shopping); all by default.
    #[arg(long)]
    pub scenario: Vec<String>,
    /// Only these policies; earliest, latest and goal-driven by default.
    #[arg(long)]
    pub policy: Vec<PolicyKind>,
    /// One JSON object per scenario and policy instead of the table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: ExperimentArgs) -> ExitCode {
    let Experiment::Dispatch(a) = args.what;
    if !(a.per_hour.is_finite() && a.per_hour >= 0.0) {
        crate::cli::out::errln!(
            "mavtempo experiment dispatch: --per-hour must be a non-negative number"
        );
        return ExitCode::FAILURE;
    }
    let known = experiment::scenario_names();
    if let Some(bad) = a.scenario.iter().find(|s| !known.contains(&s.as_str())) {
        crate::cli::out::errln!(
            "mavtempo experiment dispatch: unknown scenario {bad:?} (known: {known:?})"
        );
        return ExitCode::FAILURE;
    }
    let mut opts = ExperimentOptions {
        seeds: a.seeds,
        first_seed: a.first_seed,
        scenarios: a.scenario.clone(),
        per_hour: a.per_hour,
        repair_steps: a.repair_steps.max(1),
        ..ExperimentOptions::default()
    };
    if !a.policy.is_empty() {
        opts.policies = a.policy.clone();
    }
    // A progress bar on a terminal only: redirected, stderr gets no carriage returns.
    let on_terminal = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let mut progress = |done: u64, total: u64| {
        if !on_terminal {
            return;
        }
        let width = 40;
        let filled = (done * width / total.max(1)) as usize;
        crate::cli::out::err!(
            "\r[{}{}] {done}/{total} missions",
            "#".repeat(filled),
            " ".repeat(width as usize - filled)
        );
        if done == total {
            crate::cli::out::errln!();
        }
        let _ = std::io::stderr().flush();
    };
    let rows = match experiment::run(&opts, &mut progress) {
        Ok(rows) => rows,
        Err(e) => {
            crate::cli::out::errln!("mavtempo experiment dispatch: {e}");
            return ExitCode::FAILURE;
        }
    };
    if a.json {
        return super::json_out::print_json_lines("mavtempo experiment dispatch", &rows);
    }
    print_table(&rows);
    ExitCode::SUCCESS
}

fn print_table(rows: &[Row]) {
    outln!(
        "| scenario | policy | seeds | arrived | achieved | rejected (reasons) | pending | mean time to achieve (min) | idle (h/mission) | distance (km/mission) | wasted (km/mission) | replans/mission | repairs/mission | mission goals achieved |"
    );
    outln!("|---|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for r in rows {
        let reasons: Vec<String> = r
            .rejected_reasons
            .iter()
            .map(|(k, v)| format!("{k} {v}"))
            .collect();
        let reasons = if reasons.is_empty() {
            String::new()
        } else {
            format!(" ({})", reasons.join(", "))
        };
        outln!(
            "| {} | {} | {} | {} | {} | {}{} | {} | {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {}/{} |",
            r.scenario,
            r.policy,
            r.seeds,
            r.arrived,
            r.achieved,
            r.rejected,
            reasons,
            r.pending,
            r.mean_time_to_achieve_min
                .map_or("-".to_string(), |m| format!("{m:.1}")),
            r.idle_h,
            r.distance_km,
            r.wasted_km,
            r.replans,
            r.repairs,
            r.mission_goals_achieved,
            r.mission_goals
        );
    }
}
