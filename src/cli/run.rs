//! `mavtempo run --config FILE DOMAIN PROBLEM [--vehicle ADDR] [--goals FILE] [--gcs ADDR] [--tlog FILE]
//! [--report FILE]`: plans the problem, then executes it live against a MAVLink vehicle, with goal uploads
//! from ground stations decided by the executive. SIGINT / SIGTERM stop it safely (see [`super::shutdown`]).
//! Wiring and printing only.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

use clap::Args;

use super::error::CliError;
use super::mission_out::{initial_plan, print_summary, MissionOutArgs, TracePrinter};
use super::shutdown::Signals;
use crate::cli::out::outln;
use crate::exec::config::ExecConfig;
use crate::exec::executive::Executive;
use crate::exec::interrupt::Interrupt;
use crate::exec::mission::{run_mission, MissionEnd, MissionOptions, MissionReport};
use crate::exec::pacer::LivePacer;
use crate::exec::trace::CycleRecord;
use crate::lang;
use crate::model::Problem;
use crate::vehicle::config::VehicleConfig;
use crate::vehicle::geo::Home;
use crate::vehicle::goal_files;
use crate::vehicle::goals::{items_to_goals, KnownLocations};
use crate::vehicle::link::{Decider, LinkOptions};
use crate::vehicle::{Enu, GoalRequest, MavlinkVehicle, Vehicle};

#[derive(Args, Debug)]
pub struct RunArgs {
    /// Vehicle configuration (TOML: link, home, modes, resources, action bindings; optional [exec] table
    /// with timestep_ms, repair_share, replan_slack_ms).
    #[arg(long)]
    pub config: PathBuf,
    /// The domain file (e.g. domains/rover/rover.ixt).
    pub domain: PathBuf,
    /// The problem file (e.g. domains/rover/problems/fig2.ixt).
    pub problem: PathBuf,
    /// The vehicle's address, overriding the config's link.address (e.g. tcpout:127.0.0.1:5760).
    #[arg(long)]
    pub vehicle: Option<String>,
    /// Goals requested at the start, from a QGroundControl .plan or .waypoints file.
    #[arg(long)]
    pub goals: Option<PathBuf>,
    /// Where ground stations connect to upload goals (e.g. udpin:0.0.0.0:14551).
    #[arg(long)]
    pub gcs: Option<String>,
    /// Record every MAVLink frame to this .tlog.
    #[arg(long)]
    pub tlog: Option<PathBuf>,
    /// Wall seconds to wait for the vehicle's first heartbeat and clock; during the mission, the vehicle
    /// silent (no heartbeat) this long is lost: the mission ends with that verdict (exit 1, report written).
    #[arg(long, default_value_t = 30)]
    pub link_timeout: u64,
    /// How fast the vehicle's clock runs (a SITL at N× real time): the executive sleeps 1/N of a wall
    /// second per vehicle second.
    #[arg(long, default_value_t = 1.0)]
    pub speedup: f64,
    /// When actions start: earliest, latest or goal-driven[:search|:marking] (overrides [exec] dispatch).
    #[arg(long, value_name = "POLICY")]
    pub dispatch: Option<crate::dispatch::PolicyKind>,
    #[command(flatten)]
    pub out: MissionOutArgs,
    #[command(flatten)]
    pub http: super::http_arg::HttpArg,
}

/// The live page's runtime, kept serving after the mission.
struct LiveKeep {
    addr: std::net::SocketAddr,
    _rt: tokio::runtime::Runtime,
}

pub fn run(args: RunArgs) -> ExitCode {
    let signals = match super::shutdown::listen() {
        Ok(s) => s,
        Err(e) => {
            crate::cli::out::errln!("mavtempo run: {e}");
            return ExitCode::FAILURE;
        }
    };
    let interrupt = signals.interrupt.clone();
    match mission(&args, &signals) {
        Ok((report, live)) => {
            print_summary(&report);
            if let Err(e) = args.out.write(&report, "mavtempo run") {
                crate::cli::out::errln!("mavtempo run: {e}");
                return ExitCode::FAILURE;
            }
            if let Some(keep) = live {
                if !matches!(report.end, MissionEnd::Interrupted(_)) {
                    super::http_arg::linger(&keep.addr, &interrupt);
                }
            }
            match report.end {
                MissionEnd::Interrupted(_) => {
                    super::shutdown::exit_code(&interrupt).unwrap_or(ExitCode::FAILURE)
                }
                MissionEnd::VehicleLost { .. } => ExitCode::FAILURE,
                _ => ExitCode::SUCCESS,
            }
        }
        Err(e) => {
            crate::cli::out::errln!("mavtempo run: {e}");
            super::shutdown::exit_code(&interrupt).unwrap_or(ExitCode::FAILURE)
        }
    }
}

/// Stops the start-up when a signal came before the mission began: nothing was sent to the vehicle.
fn not_interrupted(interrupt: &Interrupt) -> Result<(), CliError> {
    match interrupt.signal_name() {
        Some(name) => Err(CliError::Interrupted(name)),
        None => Ok(()),
    }
}

/// The vehicle configuration and the optional `[exec]` table of the same file, both checked (errors at
/// `file:line:col`).
pub fn load_config(path: &Path) -> Result<(VehicleConfig, ExecConfig), CliError> {
    let both = crate::exec::config::MissionConfig::load(path)?;
    Ok((both.vehicle, both.exec))
}

fn load_problem(args: &RunArgs) -> Result<(Arc<crate::model::Domain>, Arc<Problem>), CliError> {
    let domain = Arc::new(lang::load_domain(&args.domain)?);
    let problem = lang::load_problem(&args.problem, &domain)?;
    Ok((domain, Arc::new(problem)))
}

/// The problem's located objects, so that uploaded positions name them; `home` is the effective home.
pub fn known_locations(home: Home, problem: &Problem) -> KnownLocations {
    let mut known = KnownLocations::new(home);
    for o in &problem.objects {
        if let Some((e, n, u)) = o.local(problem.home.as_ref()) {
            known.objects.push((o.name.clone(), Enu::new(e, n, u)));
        }
    }
    known
}

fn initial_goals(
    path: &Path,
    known: &KnownLocations,
    first: u32,
) -> Result<Vec<GoalRequest>, CliError> {
    let file = goal_files::load(path)?;
    for e in &file.skipped {
        tracing::warn!("{e}");
    }
    let list = items_to_goals(&file.items, known, first);
    for e in &list.skipped {
        tracing::warn!("{}: {e}", path.display());
    }
    Ok(list.requests())
}

fn mission(
    args: &RunArgs,
    signals: &Signals,
) -> Result<(MissionReport, Option<LiveKeep>), CliError> {
    let interrupt = &signals.interrupt;
    if !(args.speedup.is_finite() && args.speedup > 0.0) {
        return Err(CliError::Speedup(args.speedup));
    }
    // Before anything is planned or sent: outputs that cannot be written are found now, not after.
    args.out.check_writable()?;
    let (cfg, mut exec_cfg) = load_config(&args.config)?;
    exec_cfg.dispatch = args.dispatch.unwrap_or(exec_cfg.dispatch);
    let (domain, problem) = load_problem(args)?;
    // Before anything moves: a configuration that does not fit the domain is refused here.
    let checked = super::check::checked_config(&cfg, &domain, Some(&problem))?;
    let known = known_locations(checked.home, &problem);
    let first = problem.goals.len() as u32 + 1;
    let goals = match &args.goals {
        Some(p) => initial_goals(p, &known, first)?,
        None => Vec::new(),
    };
    outln!(
        "planning {} ({} goals)...",
        problem.name,
        problem.goals.len()
    );
    let plan = initial_plan(domain, problem.clone(), args.out.max_steps)?;
    outln!("initial plan: {} actions", plan.num_actions());
    not_interrupted(interrupt)?;
    let opts = LinkOptions {
        address: args.vehicle.clone(),
        tlog: args.tlog.clone(),
        gcs: args.gcs.clone(),
        known: Some(known),
        decider: Decider::Executive {
            timeout: Duration::from_secs(10),
        },
        first_goal_number: first + goals.len() as u32,
    };
    let ready_limit_s = checked.vehicle.ready.timeout_s;
    let start_radius_m = crate::vehicle::authority::start_radius_m(&checked.vehicle);
    let limits_cfg = checked.vehicle.limits.clone();
    let resources = checked.vehicle.resources.clone();
    let moving = checked
        .vehicle
        .state
        .moving
        .clone()
        .filter(|_| checked.vehicle.state.end_still);
    let stale_after = Duration::from_millis(checked.vehicle.link.heartbeat_timeout_ms);
    // The page's goal form signs its uploads as the companion requires (issue 31).
    let signing = crate::vehicle::link::signing_key(&checked.vehicle)?;
    let mut vehicle = MavlinkVehicle::connect_blocking(checked.vehicle, opts)?;
    if let Some(flush) = vehicle.tlog_flusher() {
        signals.before_exit_at_once(flush);
    }
    let deadline = Instant::now() + Duration::from_secs(args.link_timeout);
    while vehicle.target().is_none() || vehicle.now_ms() == 0 {
        not_interrupted(interrupt)?;
        if Instant::now() >= deadline {
            return Err(CliError::NoHeartbeat(args.link_timeout));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let mut ready = None;
    if ready_limit_s > 0.0 {
        outln!("vehicle up; waiting for a position fix and arming (at most {ready_limit_s} s)...");
        // The limit runs on the vehicle's clock; the wall bound only covers a clock that stops.
        let wall = Duration::from_secs_f64(ready_limit_s / args.speedup + 30.0);
        let report = vehicle.wait_ready((ready_limit_s * 1000.0) as u64, wall, &mut |_| {
            std::thread::sleep(Duration::from_millis(20));
            interrupt.signal_name().is_none()
        });
        not_interrupted(interrupt)?;
        if !report.ready {
            return Err(CliError::NotReady(report.why_not(ready_limit_s)));
        }
        outln!("{}", super::mission_out::ready_line(&report));
        ready = Some(report);
    }
    // `[limits]` and the autopilot's fence, read at readiness.
    let fence = vehicle.autopilot_fence();
    let (limits, said) =
        crate::vehicle::fence::limits_for(&limits_cfg, checked.home, fence.as_ref());
    if let Some(said) = said {
        outln!("{said}");
    }
    let origin = vehicle.now_ms();
    outln!("vehicle ready; mission starts at vehicle time {origin} ms");
    if let Some(a) = vehicle.gcs_addr() {
        // The bound address (with `--gcs udpin:…:0`, the port the system chose).
        outln!("goal intake listening on {a}");
    }
    let home = checked.home;
    let setup = crate::exec::builder::VehicleSetup {
        mapping: checked.mapping,
        resources: &resources,
        moving: moving.as_ref(),
        limits,
    };
    let mut ex = Executive::build(plan, exec_cfg, setup);
    // The plan starts where the vehicle is (issue 30): beyond the acceptance radius, from a new place.
    if let Some((e, n)) = vehicle.position() {
        if let Some(d) = ex.start_from(crate::vehicle::Enu::new(e, n, 0.0), start_radius_m, 0) {
            outln!("warning: the vehicle is {d:.0} m from the plan's start: planning again from where it is");
        }
    }
    let mut printer = TracePrinter::default();
    let quiet = args.out.quiet;
    let mut live = match args.http.spec() {
        Some(h) => Some(start_live(&h, args, &vehicle, home, signing)?),
        None => None,
    };
    let mut vehicle_trace = super::vehicle_trace::VehicleTrace::new(vehicle.status_probe());
    let mut observe = |ex: &Executive, c: &CycleRecord| {
        if !quiet {
            printer.cycle(c);
            if let Some(line) = vehicle_trace.line(c.time_ms) {
                outln!("{line}");
            }
        }
        if let Some((server, _)) = live.as_mut() {
            server.feed.observe(ex, c);
        }
    };
    let opts = MissionOptions {
        time_limit_ms: problem.horizon + 60_000,
        initial_goals: goals,
        max_cycles: None,
        interrupt: interrupt.clone(),
        vehicle_lost_after: Some(Duration::from_secs(args.link_timeout)),
    };
    let mut pacer = LivePacer::new(origin, args.speedup, stale_after);
    let mut report = run_mission(&mut ex, &mut vehicle, &mut pacer, &opts, &mut observe);
    report.ready = ready;
    if let Some(verdict) = report.end.vehicle_lost() {
        crate::cli::out::errln!("mavtempo run: {verdict}");
    }
    if matches!(report.end, MissionEnd::Interrupted(_)) {
        report.shutdown =
            Some(vehicle.safe_stop(&mut |_| std::thread::sleep(Duration::from_millis(20))));
    } else {
        // `[authority] at_end`: HOLD, then disarmed (by default); the commands need a moment to go out.
        vehicle.end_of_mission();
        std::thread::sleep(Duration::from_millis(200));
    }
    vehicle.flush_tlog();
    let keep = live.map(|(server, rt)| {
        server.feed.finish(&report);
        LiveKeep {
            addr: server.addr,
            _rt: rt,
        }
    });
    Ok((report, keep))
}

/// The live page on a runtime of its own; its goal form uploads to the `--gcs` endpoint.
fn start_live(
    h: &super::http_arg::HttpSpec,
    args: &RunArgs,
    vehicle: &MavlinkVehicle,
    home: Home,
    signing: Option<([u8; 32], u8)>,
) -> Result<(crate::report::live::LiveServer, tokio::runtime::Runtime), CliError> {
    let rt = super::runtime::multi_thread(Some(1), "live page runtime")?;
    let form = if h.goals {
        let (Some(gcs), Some(addr)) = (&args.gcs, vehicle.gcs_addr()) else {
            return Err(CliError::HttpGoalsWithoutGcs);
        };
        let transport = if gcs.starts_with("udp") {
            "udpout"
        } else {
            "tcpout"
        };
        let ip = if addr.ip().is_unspecified() {
            std::net::IpAddr::from([127, 0, 0, 1])
        } else {
            addr.ip()
        };
        let client = format!("{transport}:{}", std::net::SocketAddr::new(ip, addr.port()));
        Some(super::http_arg::goal_form(
            home,
            client,
            None,
            signing,
            Some(vehicle.goal_intake()),
        ))
    } else {
        None
    };
    let server =
        crate::report::live::start(rt.handle(), h.addr, form).map_err(|source| CliError::Http {
            addr: h.addr,
            source,
        })?;
    outln!("http listening on http://{}/", server.addr);
    let server = crate::report::live::LiveServer {
        feed: server
            .feed
            .with_position(vehicle.position_probe())
            .with_vehicle(vehicle.status_probe(), vehicle.goal_intake()),
        ..server
    };
    Ok((server, rt))
}
