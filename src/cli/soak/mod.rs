//! `mavtempo soak --missions N [--seed S] [--domain rover|auv|all] [--json] [--trace]`: random missions (see
//! [`generate`]) each run through the whole stack — planner, executive, MAVLink link, the built-in SITL in
//! process, stepped, over real sockets — with the SITL's random faults and goals uploaded over MAVLink during
//! the run; every mission's report is checked against the [`invariants`]. Mission i uses seed S + i; a
//! violation names its seed, and `--missions 1 --seed <it> --trace` reruns that mission with its trace.

mod generate;
mod invariants;

use std::collections::BTreeMap;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::Args;
use serde::Serialize;

use self::generate::{Mission, SoakDomain, Upload};
use self::invariants::{reason_class, Violation, END_MARGIN_MS};
use super::demo::exec_config;
use super::mission_out::{initial_plan, TracePrinter};
use super::sitl_session::{SessionSpec, SitlSession};
use crate::cli::error::CliError;
use crate::cli::out::outln;
use crate::dispatch::PolicyKind;
use crate::exec::config::ExecConfig;
use crate::exec::executive::{Executive, Fate};
use crate::exec::mission::{run_mission, MissionOptions, MissionReport};
use crate::exec::pacer::StepGate;
use crate::exec::trace::CycleRecord;
use crate::lang;
use crate::vehicle::goal_client::{send_goals, GoalSendError, GoalSendReport};
use crate::vehicle::goals::GOAL_ATTRIBUTES_CMD;
use crate::vehicle::items::MissionItem;
use crate::vehicle::Enu;

const ROVER: &str = include_str!("../../../domains/rover/rover.ixt");
const AUV: &str = include_str!("../../../domains/auv/auv.ixt");
const AUV_CONFIG: &str = include_str!("../../../config/sitl-auv.toml");

#[derive(Args, Debug)]
pub struct SoakArgs {
    /// How many missions.
    #[arg(long, default_value_t = 20)]
    pub missions: u64,
    /// Mission i uses seed S + i.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Which missions: random rover or AUV ones, all (both), or shipped (the rover's own problems).
    #[arg(long, value_enum, default_value = "all")]
    pub domain: SoakDomain,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    /// Print each mission's per-cycle trace (with --missions 1 to rerun one seed).
    #[arg(long)]
    pub trace: bool,
    /// Print each mission's generated problem and scenario.
    #[arg(long)]
    pub show: bool,
    /// Write the last mission's report as JSON (with `--missions 1 --seed S`: that seed's mission), for
    /// `mavtempo report`.
    #[arg(long)]
    pub report: Option<std::path::PathBuf>,
    /// Run every mission under each of these dispatch policies (comma-separated: goal-driven, earliest,
    /// latest) and print them side by side: the dispatch experiment, live on the simulator. Default: goal-driven.
    #[arg(long, value_delimiter = ',', value_name = "POLICY")]
    pub dispatch: Vec<PolicyKind>,
}

/// What one mission gave.
struct Outcome {
    report: Option<MissionReport>,
    /// Goals with their fates (all rejected when there was no initial plan).
    /// Each goal's name, fate, reason and the reason's class.
    goals: Vec<(String, Fate, String, &'static str)>,
    /// The names of the problem's goals (the others were uploaded).
    held: Vec<String>,
    violations: Vec<Violation>,
    /// Metres driven (the report's track).
    distance_m: f64,
    /// Battery spent, in the battery resource's unit (percent for the rover): the sum of its reported drops.
    battery_used: Option<f64>,
}

/// Goals achieved among those of missions with a given fault (or none).
#[derive(Clone, Debug, Default, Serialize)]
struct Share {
    missions: u64,
    goals: u64,
    achieved: u64,
    share: f64,
}

#[derive(Clone, Debug, Serialize)]
struct Rejection {
    seed: u64,
    goal: String,
    reason: String,
}

#[derive(Debug, Default, Serialize)]
struct Summary {
    /// The dispatch policy the missions ran under.
    policy: String,
    missions: u64,
    first_seed: u64,
    domain: String,
    rover_missions: u64,
    auv_missions: u64,
    goals: u64,
    achieved: u64,
    rejected: BTreeMap<String, u64>,
    /// Every rejected goal: its mission's seed, its name and the reason given.
    rejections: Vec<Rejection>,
    /// Missions the planner could not plan at all (their goals are rejected with its reason).
    unplanned: u64,
    by_fault: BTreeMap<String, Share>,
    violations_by_invariant: BTreeMap<String, u64>,
    violations: Vec<Violation>,
    repairs: u64,
    replans: u64,
    /// Kilometres driven over all missions.
    distance_km: f64,
    /// Battery spent over all rover missions (percent points; the AUV domain has no battery).
    battery_used: f64,
    /// Goals of the missions' problems (not uploaded) and how many of them were achieved.
    held_goals: u64,
    held_achieved: u64,
    /// Missions that ended with every goal rejected.
    all_rejected: u64,
    /// `--domain shipped`: missions that achieved every problem goal the same mission without its uploads
    /// achieves (each mission is also run without them).
    #[serde(skip_serializing_if = "Option::is_none")]
    kept_goals: Option<u64>,
    /// The signal (SIGINT, SIGTERM) that stopped the soak: the figures are those of the missions done
    /// before it (`missions`), the one it cut is left out.
    #[serde(skip_serializing_if = "Option::is_none")]
    interrupted: Option<String>,
    wall_s: f64,
}

pub fn run(args: SoakArgs) -> ExitCode {
    let wall = Instant::now();
    // SIGINT / SIGTERM stop the mission under way; the summary of those done is still printed.
    let signals = match super::shutdown::listen() {
        Ok(s) => s,
        Err(e) => {
            crate::cli::out::errln!("mavtempo soak: {e}");
            return ExitCode::FAILURE;
        }
    };
    let interrupt = signals.interrupt.clone();
    // A progress bar on a terminal only: redirected, stderr gets no bar.
    let on_terminal = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let bar = (!args.trace && !args.show && on_terminal).then(|| {
        let bar = indicatif::ProgressBar::new(args.missions);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "soak [{bar:30}] {pos}/{len} missions, {msg} ({elapsed}, eta {eta})",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    });
    let policies: Vec<PolicyKind> = if args.dispatch.is_empty() {
        vec![exec_config().dispatch]
    } else {
        args.dispatch.clone()
    };
    let mut sums: Vec<Summary> = policies
        .iter()
        .map(|p| Summary {
            policy: p.to_string(),
            missions: args.missions,
            first_seed: args.seed,
            domain: format!("{:?}", args.domain).to_lowercase(),
            ..Summary::default()
        })
        .collect();
    'missions: for i in 0..args.missions {
        let m = generate::mission(args.seed + i, args.domain);
        if args.show {
            outln!(
                "== mission seed {} ==\n{}\n-- scenario --\n{}",
                m.seed,
                m.problem,
                m.scenario
            );
        }
        for (&policy, sum) in policies.iter().zip(sums.iter_mut()) {
            let outcome = run_guarded(&m, policy, args.trace, &interrupt);
            let cut = outcome
                .report
                .as_ref()
                .is_some_and(|r| matches!(r.end, crate::exec::mission::MissionEnd::Interrupted(_)));
            if !cut {
                tally(sum, &m, &outcome);
            }
            if let Some(signal) = interrupt.signal_name() {
                for s in sums.iter_mut() {
                    s.missions = i + u64::from(!cut && s.policy == policy.to_string());
                    s.interrupted = Some(signal.clone());
                }
                break 'missions;
            }
            if let (Some(path), Some(r)) = (&args.report, &outcome.report) {
                if let Err(e) = super::mission_out::write_report(path, r) {
                    crate::cli::out::errln!("mavtempo soak: {e}");
                    return ExitCode::FAILURE;
                }
            }
            if m.domain == SoakDomain::Shipped {
                let without = Mission {
                    uploads: Vec::new(),
                    ..m.clone()
                };
                let baseline = run_guarded(&without, policy, false, &interrupt);
                let achieved = |g: &str| {
                    outcome
                        .goals
                        .iter()
                        .any(|(h, f, _, _)| h == g && *f == Fate::Achieved)
                };
                let kept = baseline.violations.is_empty()
                    && baseline
                        .goals
                        .iter()
                        .all(|(g, fate, _, _)| *fate != Fate::Achieved || achieved(g));
                *sum.kept_goals.get_or_insert(0) += u64::from(kept);
            }
        }
        if let Some(bar) = &bar {
            let sum = &sums[0];
            bar.set_message(format!(
                "{} of {} goals achieved, {} violations",
                sum.achieved,
                sum.goals,
                sum.violations.len()
            ));
            bar.inc(1);
        }
    }
    if let Some(bar) = bar {
        bar.finish();
    }
    let wall_s = wall.elapsed().as_secs_f64();
    for sum in sums.iter_mut() {
        for s in sum.by_fault.values_mut() {
            s.share = if s.goals == 0 {
                1.0
            } else {
                s.achieved as f64 / s.goals as f64
            };
        }
        sum.wall_s = wall_s;
    }
    let printed = match (args.json, sums.as_slice()) {
        (true, [one]) => super::json_out::print_json_pretty("mavtempo soak", one),
        (true, many) => super::json_out::print_json_pretty("mavtempo soak", &many),
        (false, [one]) => {
            print_summary(one);
            ExitCode::SUCCESS
        }
        (false, many) => {
            for s in many {
                outln!("== dispatch {} ==", s.policy);
                print_summary(s);
            }
            print_side_by_side(many);
            ExitCode::SUCCESS
        }
    };
    if printed != ExitCode::SUCCESS {
        return printed;
    }
    if let Some(code) = super::shutdown::exit_code(&interrupt) {
        return code;
    }
    if sums.iter().all(|s| s.violations.is_empty()) {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}

/// One mission under `policy`; a panic is a violation of its own.
fn run_guarded(
    m: &Mission,
    policy: PolicyKind,
    trace: bool,
    interrupt: &crate::exec::interrupt::Interrupt,
) -> Outcome {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        run_one(m, policy, trace, interrupt)
    }))
    .unwrap_or_else(|p| {
        let what = p
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default();
        failed(m, "no_panic", format!("panicked: {what}"))
    })
}

/// The policies side by side (seed 2's experiment): one row per policy.
fn print_side_by_side(sums: &[Summary]) {
    outln!(
        "{:<20} {:>9} {:>9} {:>9} {:>9} {:>8} {:>9} {:>9}  rejected by class",
        "dispatch",
        "goals",
        "achieved",
        "uploaded",
        "achieved",
        "km",
        "battery %",
        "replans"
    );
    for s in sums {
        outln!(
            "{:<20} {:>9} {:>9} {:>9} {:>9} {:>8.2} {:>9.0} {:>9}  {:?}",
            s.policy,
            s.goals,
            s.achieved,
            s.goals - s.held_goals,
            s.achieved - s.held_achieved,
            s.distance_km,
            s.battery_used,
            s.replans,
            s.rejected
        );
    }
}

fn failed(m: &Mission, invariant: &'static str, detail: String) -> Outcome {
    Outcome {
        report: None,
        goals: Vec::new(),
        held: Vec::new(),
        violations: vec![Violation {
            invariant,
            seed: m.seed,
            detail,
        }],
        distance_m: 0.0,
        battery_used: None,
    }
}

fn tally(sum: &mut Summary, m: &Mission, o: &Outcome) {
    match m.domain {
        SoakDomain::Auv => sum.auv_missions += 1,
        _ => sum.rover_missions += 1,
    }
    let achieved = o.goals.iter().filter(|g| g.1 == Fate::Achieved).count() as u64;
    let total = o.goals.len() as u64;
    sum.goals += total;
    sum.achieved += achieved;
    for (goal, fate, reason, class) in &o.goals {
        if *fate == Fate::Rejected {
            *sum.rejected.entry((*class).into()).or_default() += 1;
            sum.rejections.push(Rejection {
                seed: m.seed,
                goal: goal.clone(),
                reason: reason.clone(),
            });
        }
    }
    if o.report.is_none() && o.violations.is_empty() {
        sum.unplanned += 1;
    }
    let classes: Vec<&str> = if m.faults.is_empty() {
        vec!["none"]
    } else {
        m.faults.clone()
    };
    for f in classes {
        let s = sum.by_fault.entry(f.into()).or_default();
        s.missions += 1;
        s.goals += total;
        s.achieved += achieved;
    }
    let held: Vec<&(String, Fate, String, &str)> =
        o.goals.iter().filter(|g| o.held.contains(&g.0)).collect();
    sum.held_goals += held.len() as u64;
    sum.held_achieved += held.iter().filter(|g| g.1 == Fate::Achieved).count() as u64;
    if !o.goals.is_empty() && o.goals.iter().all(|g| g.1 == Fate::Rejected) {
        sum.all_rejected += 1;
    }
    if let Some(r) = &o.report {
        sum.repairs += r.counters.repairs;
        sum.replans += r.counters.replans;
    }
    sum.distance_km += o.distance_m / 1000.0;
    sum.battery_used += o.battery_used.unwrap_or(0.0);
    for v in &o.violations {
        *sum.violations_by_invariant
            .entry(v.invariant.into())
            .or_default() += 1;
        sum.violations.push(v.clone());
    }
}

fn print_summary(s: &Summary) {
    if let Some(signal) = &s.interrupted {
        outln!("soak interrupted by {signal}: the summary of the missions done before it");
    }
    outln!(
        "soak: {} missions ({} rover, {} auv) from seed {}, {:.0} s",
        s.missions,
        s.rover_missions,
        s.auv_missions,
        s.first_seed,
        s.wall_s
    );
    outln!(
        "goals: {} of {} achieved; rejected by class: {:?}; unplanned missions: {}",
        s.achieved,
        s.goals,
        s.rejected,
        s.unplanned
    );
    outln!(
        "dispatch {}: plan repairs {}, complete replannings {}, {:.2} km driven, {:.0} % of battery spent",
        s.policy,
        s.repairs,
        s.replans,
        s.distance_km,
        s.battery_used
    );
    outln!(
        "problem goals: {} of {} achieved; missions with every goal rejected: {}",
        s.held_achieved,
        s.held_goals,
        s.all_rejected
    );
    if let Some(k) = s.kept_goals {
        outln!(
            "missions achieving every problem goal their run without uploads achieves: {k} of {}",
            s.missions
        );
    }
    for (f, sh) in &s.by_fault {
        outln!(
            "  fault {f:<14} {:>4} missions, {:>4} of {:>4} goals achieved ({:.0} %)",
            sh.missions,
            sh.achieved,
            sh.goals,
            sh.share * 100.0
        );
    }
    if s.violations.is_empty() {
        outln!("invariants: no violation");
    } else {
        outln!("invariants: {} violations", s.violations.len());
        for v in &s.violations {
            outln!(
                "  {} (seed {}): {}  — rerun: mavtempo soak --missions 1 --seed {} --trace",
                v.invariant,
                v.seed,
                v.detail,
                v.seed
            );
        }
    }
}

/// Runs one mission through the whole stack.
fn run_one(
    m: &Mission,
    policy: PolicyKind,
    trace: bool,
    interrupt: &crate::exec::interrupt::Interrupt,
) -> Outcome {
    let (domain_text, domain_name) = match m.domain {
        SoakDomain::Auv => (AUV, "domains/auv/auv.ixt"),
        _ => (ROVER, "domains/rover/rover.ixt"),
    };
    let name = format!("soak seed {}", m.seed);
    let domain = match lang::parse_domain(domain_name, domain_text) {
        Ok(d) => Arc::new(d),
        Err(e) => return failed(m, "no_error_exit", e.to_string()),
    };
    let problem = match lang::parse_problem(&name, &m.problem, &domain) {
        Ok(p) => Arc::new(p),
        Err(e) => return failed(m, "no_error_exit", format!("generated problem: {e}")),
    };
    let plan = match initial_plan(domain.clone(), problem.clone(), 50_000) {
        Ok(p) => p,
        Err(e) => {
            // Not the executive's failure: the mission's goals are all rejected with the planner's reason.
            return Outcome {
                report: None,
                goals: problem
                    .goals
                    .iter()
                    .map(|g| {
                        (
                            g.name.clone(),
                            Fate::Rejected,
                            e.to_string(),
                            "no_initial_plan",
                        )
                    })
                    .collect(),
                held: problem.goals.iter().map(|g| g.name.clone()).collect(),
                violations: Vec::new(),
                distance_m: 0.0,
                battery_used: None,
            };
        }
    };
    let spec = match session_spec(m, problem.goals.len() as u32 + 1) {
        Ok(s) => s,
        Err(e) => return failed(m, "no_error_exit", e.to_string()),
    };
    let battery = spec.config.resources.battery.clone();
    let mut session = match SitlSession::start(&domain, &problem, spec) {
        Ok(s) => s,
        Err(e) => return failed(m, "no_error_exit", format!("SITL session: {e}")),
    };
    let config = ExecConfig {
        dispatch: policy,
        ..exec_config()
    };
    let mut ex = Executive::build(plan, config, session.vehicle_setup());
    let (home, gcs) = (session.home, session.gcs.clone());
    let rt = session.rt.handle().clone();
    let mut pending: Vec<&Upload> = m.uploads.iter().collect();
    let mut sent: Vec<tokio::task::JoinHandle<Result<GoalSendReport, GoalSendError>>> = Vec::new();
    let mut printer = TracePrinter::default();
    let gate = Arc::new(StepGate::default());
    let mut observe = |_: &Executive, c: &CycleRecord| {
        if trace {
            printer.cycle(c);
        }
        let due: Vec<&Upload> = pending
            .iter()
            .copied()
            .filter(|u| (u.at_s * 1000.0) as i64 <= c.time_ms)
            .collect();
        if due.is_empty() {
            return;
        }
        pending.retain(|u| (u.at_s * 1000.0) as i64 > c.time_ms);
        let items = upload_items(home, &due);
        let addr = format!("tcpout:{gcs}");
        // The simulator waits for the batch to reach the executive: the mission is reproducible.
        gate.expect_goal_batch();
        let gate = gate.clone();
        sent.push(rt.spawn(async move {
            let r = send_goals(&addr, items, Duration::from_secs(30)).await;
            if r.is_err() {
                gate.cancel_goal_batch();
            }
            r
        }));
    };
    let horizon_ms = problem.horizon;
    let opts = MissionOptions {
        time_limit_ms: horizon_ms + END_MARGIN_MS,
        // Ten cycles per second of mission on average is a loop, not a mission (ts is 1.3 s).
        max_cycles: Some((horizon_ms / 100).max(10_000) as usize),
        interrupt: interrupt.clone(),
        ..MissionOptions::default()
    };
    let mut pacer = session.step_pacer(gate.clone());
    let report = run_mission(
        &mut ex,
        &mut session.vehicle,
        &mut pacer,
        &opts,
        &mut observe,
    );
    for h in sent {
        // An upload still in flight when the mission ended is not an error of the mission.
        let _ = session
            .rt
            .block_on(async { tokio::time::timeout(Duration::from_secs(5), h).await });
    }
    if trace {
        super::mission_out::print_summary(&report);
    }
    let goals = report
        .goals
        .iter()
        .map(|g| {
            let class = reason_class(g.reason.as_ref());
            (g.name.clone(), g.fate.clone(), g.reason_text(), class)
        })
        .collect();
    let violations = invariants::check(m.seed, &report, horizon_ms);
    drop(session);
    Outcome {
        distance_m: driven_m(&report),
        battery_used: battery.map(|b| spent(&report, &b)),
        report: Some(report),
        goals,
        held: problem.goals.iter().map(|g| g.name.clone()).collect(),
        violations,
    }
}

/// Metres along the report's track.
fn driven_m(r: &MissionReport) -> f64 {
    r.track
        .windows(2)
        .map(|w| (w[1].east - w[0].east).hypot(w[1].north - w[0].north))
        .sum()
}

/// The sum of the drops in `resource`'s reported level (a recharge does not give back what was spent).
fn spent(r: &MissionReport, resource: &str) -> f64 {
    let levels: Vec<f64> = r
        .resources
        .iter()
        .filter(|s| s.resource == resource)
        .filter_map(|s| s.reported)
        .collect();
    levels.windows(2).map(|w| (w[0] - w[1]).max(0.0)).sum()
}

fn session_spec(m: &Mission, first_goal_number: u32) -> Result<SessionSpec, CliError> {
    let mut spec = SessionSpec::demo_rover(&m.scenario, "soak scenario")?;
    if m.domain == SoakDomain::Auv {
        spec.config =
            crate::vehicle::config::VehicleConfig::parse(AUV_CONFIG, "config/sitl-auv.toml")?;
        spec.vehicle = sitl::VehicleKind::Auv;
    }
    spec.seed = m.seed;
    spec.first_goal_number = first_goal_number;
    Ok(spec)
}

/// The ground station's items: each goal's attributes (priority, start window, d_achiev 30 s), then the
/// goal item at its position.
fn upload_items(home: crate::vehicle::geo::Home, uploads: &[&Upload]) -> Vec<MissionItem> {
    let mut items = Vec::new();
    for u in uploads {
        items.push(MissionItem {
            command: GOAL_ATTRIBUTES_CMD,
            frame: 2,
            params: [u.priority as f32, 0.0, u.window_end_s as f32, 0.0],
            x: 30.0,
            y: 0.0,
            z: 0.0,
            autocontinue: true,
        });
        let (lat, lon, alt) = home.to_global(Enu::new(u.east, u.north, u.up));
        let mut it = MissionItem::waypoint(lat, lon, alt as f32);
        it.command = u.command;
        items.push(it);
    }
    items
}
