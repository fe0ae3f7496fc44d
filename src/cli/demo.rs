//! `mavtempo demo [--speedup N] [--report FILE]`: seed 1 §4's exploration rover (Fig. 2) executed by the
//! executive against the built-in SITL, in process, over real sockets. The faults come from the SITL's
//! scenario (sitl/scenarios/fig2.toml): e1 the first picture fails, e2 the camera hangs on the picture of
//! p2, e5 a slow download, e6 a battery drop on the first move after 400 s; e3/e4, the new goals g6 and g7, are uploaded
//! over MAVLink by a simulated ground station while the first download runs. SIGINT / SIGTERM stop it
//! safely (see [`super::shutdown`]). Wiring and printing only.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Duration;

use clap::Args;

use super::error::CliError;
use super::mission_out::{initial_plan, print_summary, MissionOutArgs, TracePrinter};
use super::sitl_session::{SessionSpec, SitlSession};
use crate::cli::out::outln;
use crate::dispatch::PolicyKind;
use crate::exec::config::ExecConfig;
use crate::exec::executive::Executive;
use crate::exec::interrupt::Interrupt;
use crate::exec::mission::{run_mission, MissionEnd, MissionOptions, MissionReport, Pacer};
use crate::exec::pacer::{LivePacer, StepGate};
use crate::exec::trace::{CycleRecord, TraceEvent};
use crate::lang;
use crate::model::Problem;
use crate::vehicle::goal_client::{send_goals, GoalSendError, GoalSendReport};
use crate::vehicle::goals::GOAL_ATTRIBUTES_CMD;
use crate::vehicle::items::MissionItem;
use crate::vehicle::Enu;

const DOMAIN: &str = include_str!("../../domains/rover/rover.ixt");
const FIG2: &str = include_str!("../../domains/rover/problems/fig2.ixt");
const SCENARIO: &str = include_str!("../../sitl/scenarios/fig2.toml");

/// The scenario of a problem without one: no fault, and the payload the domain and configuration say.
const NOMINAL: &str =
    "(nominal world: card, pictures, speed and battery from the domain and the configuration)";

/// e3/e4: the ground station's new picture goals (local metres from home), uploaded during the download.
const NEW_GOALS: [(f64, f64); 2] = [(30.0, -8.0), (46.0, 4.0)];

#[derive(Args, Debug)]
pub struct DemoArgs {
    /// Run the simulator paced at N sim seconds per wall second; without it the simulator is stepped by the
    /// executive's clock, as fast as the machine goes (deterministic).
    #[arg(long)]
    pub speedup: Option<f64>,
    /// A problem instead of the built-in rover story (domains/rover/problems/fig2.ixt).
    #[arg(long)]
    pub problem: Option<PathBuf>,
    /// The problem's domain (default: the built-in rover domain, domains/rover/rover.ixt).
    #[arg(long)]
    pub domain: Option<PathBuf>,
    /// The vehicle configuration (default: the built-in config/demo-rover.toml).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// The SITL scenario (faults, world). Default: sitl/scenarios/fig2.toml for the built-in problem; for `--problem
    /// P.ixt`, sitl/scenarios/P.toml when it exists, else a nominal world without faults whose card,
    /// pictures, capture time, speed and battery follow the domain and the configuration.
    #[arg(long)]
    pub scenario: Option<PathBuf>,
    /// The simulated vehicle: rover or auv.
    #[arg(long, default_value = "rover")]
    pub vehicle: sitl::VehicleKind,
    /// Do not upload the two new picture goals during the first download (only the built-in story uploads them).
    #[arg(long)]
    pub no_upload: bool,
    /// A ground station also uploads the goals of this `.plan`/`.waypoints` file, at `--upload-at`.
    #[arg(long)]
    pub upload: Option<PathBuf>,
    /// When the `--upload` file is uploaded: seconds of mission time.
    #[arg(long, default_value_t = 100.0)]
    pub upload_at: f64,
    /// Seeds the simulator's picture sizes and link faults (loss, duplication, reordering).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub dispatch: super::dispatch_arg::DispatchArg,
    #[command(flatten)]
    pub out: MissionOutArgs,
    #[command(flatten)]
    pub http: super::http_arg::HttpArg,
}

pub fn run(args: DemoArgs) -> ExitCode {
    if let Err(e) = args.out.check_writable() {
        crate::cli::out::errln!("mavtempo demo: {e}");
        return ExitCode::FAILURE;
    }
    let interrupt = match super::shutdown::listen() {
        Ok(s) => s.interrupt,
        Err(e) => {
            crate::cli::out::errln!("mavtempo demo: {e}");
            return ExitCode::FAILURE;
        }
    };
    let setup = DemoSetup {
        problem: args.problem.clone(),
        domain: args.domain.clone(),
        config: args.config.clone(),
        scenario: args.scenario.clone(),
        vehicle: args.vehicle,
        speedup: args.speedup,
        upload: !args.no_upload,
        timed_upload: args.upload.clone().map(|file| TimedUpload {
            at_ms: (args.upload_at * 1000.0).round() as crate::model::Time,
            items: UploadItems::File(file),
        }),
        max_steps: args.out.max_steps,
        seed: args.seed,
        dispatch: args.dispatch.dispatch,
        interrupt: interrupt.clone(),
        http: args.http.spec(),
        vehicle_offset_m: (0.0, 0.0),
    };
    let mut printer = TracePrinter::default();
    let quiet = args.out.quiet;
    let result = run_demo(
        &setup,
        &mut |line: &str| {
            // Progress lines inside the trace are indented with it.
            if !(quiet && line.starts_with(' ')) {
                outln!("{line}");
            }
        },
        &mut |c: &CycleRecord| {
            if !quiet {
                printer.cycle(c);
            }
        },
    );
    match result {
        Ok(run) => {
            for u in run.upload.iter().chain(&run.timed_upload) {
                outln!("{u}");
            }
            print_summary(&run.report);
            if let Err(e) = args.out.write(&run.report, "mavtempo demo") {
                crate::cli::out::errln!("mavtempo demo: {e}");
                return ExitCode::FAILURE;
            }
            if let Some(hold) = run.hold {
                if !matches!(run.report.end, MissionEnd::Interrupted(_)) {
                    super::http_arg::linger(&hold.addr, &interrupt);
                }
            }
            match run.report.end {
                MissionEnd::Interrupted(_) => {
                    super::shutdown::exit_code(&interrupt).unwrap_or(ExitCode::FAILURE)
                }
                _ => ExitCode::SUCCESS,
            }
        }
        Err(e) => {
            crate::cli::out::errln!("mavtempo demo: {e}");
            super::shutdown::exit_code(&interrupt).unwrap_or(ExitCode::FAILURE)
        }
    }
}

/// What a demo run is given (the command line's flags).
#[derive(Clone, Debug)]
pub struct DemoSetup {
    /// A problem instead of the built-in Fig. 2.
    pub problem: Option<PathBuf>,
    /// Its domain instead of the built-in rover domain.
    pub domain: Option<PathBuf>,
    /// A vehicle configuration instead of the built-in config/demo-rover.toml.
    pub config: Option<PathBuf>,
    /// A SITL scenario (see [`DemoArgs::scenario`] for the default).
    pub scenario: Option<PathBuf>,
    pub vehicle: sitl::VehicleKind,
    /// Paced at N× instead of stepped.
    pub speedup: Option<f64>,
    /// The ground station uploads g6 and g7 when the download starts.
    pub upload: bool,
    /// Goals a ground station uploads at a given mission time.
    pub timed_upload: Option<TimedUpload>,
    /// Planning steps for the initial plan.
    pub max_steps: u64,
    /// Seeds the simulator's picture sizes and link faults.
    pub seed: u64,
    pub dispatch: PolicyKind,
    /// Stops the mission when requested (a signal); the vehicle is then made safe.
    pub interrupt: Interrupt,
    /// Serve the live page (`--http ADDR`, `--http-goals`).
    pub http: Option<super::http_arg::HttpSpec>,
    /// The simulated vehicle starts this far (east, north metres) from the problem's home.
    pub vehicle_offset_m: (f64, f64),
}

impl Default for DemoSetup {
    /// The built-in Fig. 2 story, stepped (deterministic), with the upload.
    fn default() -> Self {
        DemoSetup {
            problem: None,
            domain: None,
            config: None,
            scenario: None,
            vehicle: sitl::VehicleKind::Rover,
            speedup: None,
            upload: true,
            timed_upload: None,
            max_steps: 200_000,
            seed: 1,
            dispatch: PolicyKind::default(),
            interrupt: Interrupt::default(),
            http: None,
            vehicle_offset_m: (0.0, 0.0),
        }
    }
}

/// An upload at a given mission time (`--upload FILE --upload-at S`).
#[derive(Clone, Debug)]
pub struct TimedUpload {
    /// Mission time, ms: uploaded at the first cycle at or after it.
    pub at_ms: crate::model::Time,
    pub items: UploadItems,
}

/// What a [`TimedUpload`] sends.
#[derive(Clone, Debug)]
pub enum UploadItems {
    /// A `.plan` or `.waypoints` file.
    File(PathBuf),
    /// Picture goals (priority 1, start window [0, 30 min], d_achiev 60 s) at these (east, north) metres
    /// from the session's home.
    PicturesAt(Vec<(f64, f64)>),
}

impl UploadItems {
    fn items(&self, home: crate::vehicle::geo::Home) -> Result<Vec<MissionItem>, CliError> {
        match self {
            UploadItems::File(p) => Ok(crate::vehicle::goal_files::load(p)?.items),
            UploadItems::PicturesAt(places) => Ok(picture_items(home, places)),
        }
    }
}

/// What a demo run leaves.
pub struct DemoRun {
    pub report: MissionReport,
    /// The ground station's account of its upload, if it uploaded.
    pub upload: Option<String>,
    /// The same for the timed upload.
    pub timed_upload: Option<String>,
    /// How the vehicle became ready before the mission (`None`: `[ready] timeout_s = 0`).
    pub ready: Option<crate::vehicle::readiness::ReadyReport>,
    /// What the autopilot's fence, read at readiness, added to the vehicle's limits.
    pub fence: Option<String>,
    /// The live page and the session it runs on, kept after the mission (`--http`).
    pub(crate) hold: Option<LiveHold>,
}

/// The live page kept serving the mission's final state.
pub(crate) struct LiveHold {
    pub addr: std::net::SocketAddr,
    _session: SitlSession,
}

fn read(path: &Path) -> Result<String, CliError> {
    Ok(srctext::read(path)?)
}

fn load(setup: &DemoSetup) -> Result<(Arc<crate::model::Domain>, Arc<Problem>), CliError> {
    let domain = match &setup.domain {
        Some(p) => lang::load_domain(p)?,
        None => lang::parse_domain("domains/rover/rover.ixt", DOMAIN)?,
    };
    let domain = Arc::new(domain);
    let (name, text) = match &setup.problem {
        Some(p) => (p.display().to_string(), read(p)?),
        None => (
            "domains/rover/problems/fig2.ixt".to_string(),
            FIG2.to_string(),
        ),
    };
    let problem = lang::parse_problem(&name, &text, &domain)?;
    Ok((domain, Arc::new(problem)))
}

/// The session's configuration and scenario from the setup (see [`DemoArgs::scenario`]).
fn session_spec(
    setup: &DemoSetup,
    domain: &crate::model::Domain,
    problem: &Problem,
) -> Result<(SessionSpec, String, ExecConfig), CliError> {
    let (scenario, scenario_name) = match (&setup.scenario, &setup.problem) {
        (Some(p), _) => (read(p)?, p.display().to_string()),
        (None, None) => (SCENARIO.to_string(), "sitl/scenarios/fig2.toml".to_string()),
        (None, Some(problem)) => {
            let beside = problem.file_stem().map(|s| {
                PathBuf::from("sitl/scenarios")
                    .join(s)
                    .with_extension("toml")
            });
            match beside.filter(|p| p.is_file()) {
                Some(p) => (read(&p)?, p.display().to_string()),
                None => (String::new(), NOMINAL.to_string()),
            }
        }
    };
    let mut spec = SessionSpec::demo_rover(&scenario, &scenario_name)?;
    let mut exec = exec_config();
    if let Some(p) = &setup.config {
        // The whole file is checked; the keys its `[exec]` table writes replace the demo's own.
        let (text, origin) = (read(p)?, p.display().to_string());
        spec.config = crate::exec::config::MissionConfig::parse(&text, &origin)?.vehicle;
        exec = ExecConfig::over(&exec, &text, &origin)?;
    }
    if scenario_name == NOMINAL {
        spec.scenario = super::nominal_world::nominal_scenario(domain, problem, &spec.config);
    }
    spec.vehicle = setup.vehicle;
    spec.speedup = setup.speedup;
    spec.seed = setup.seed;
    spec.vehicle_offset_m = setup.vehicle_offset_m;
    spec.first_goal_number = problem.goals.len() as u32 + 1;
    Ok((spec, scenario_name, exec))
}

/// The demo's executive parameters where the configuration's `[exec]` table says nothing.
pub fn exec_config() -> ExecConfig {
    ExecConfig {
        // Seed 1 §4: ts = 1.3 s; μ = 61 %. Budgets in planning steps keep the run deterministic.
        timestep_ms: 1_300,
        repair_share: 0.61,
        replan_slack_ms: 2_000,
        repair_max_steps: Some(300),
        ..ExecConfig::default()
    }
}

/// Runs the demo mission: `say` gets the progress lines, `observe` each cycle as it ends. Stepped (no
/// speed-up), two runs of the same setup give the same cycles, events and figures.
pub fn run_demo(
    setup: &DemoSetup,
    say: &mut dyn FnMut(&str),
    observe: &mut dyn FnMut(&CycleRecord),
) -> Result<DemoRun, CliError> {
    let (domain, problem) = load(setup)?;
    say(&format!(
        "planning {} ({} goals)...",
        problem.name,
        problem.goals.len()
    ));
    let plan = initial_plan(domain.clone(), problem.clone(), setup.max_steps)?;
    say(&format!("initial plan: {} actions", plan.num_actions()));
    let (spec, scenario_name, exec) = session_spec(setup, &domain, &problem)?;
    say(&format!("SITL scenario: {scenario_name}"));
    let mut session = SitlSession::start(&domain, &problem, spec)?;
    if let Some(r) = &session.ready {
        say(&format!(
            "vehicle ready: {}",
            super::mission_out::ready_line(r)
        ));
    }
    if let Some(f) = &session.fence {
        say(f);
    }
    let fence = session.fence.clone();
    let (home, gcs, origin, rt) = (session.home, &session.gcs, session.origin_ms, &session.rt);
    say(&format!(
        "SITL vehicle at {}, ground station endpoint tcp {gcs}; mission starts at vehicle time {origin} ms",
        session.sim.client_address()
    ));
    let exec = ExecConfig {
        dispatch: setup.dispatch,
        ..exec
    };
    let mut ex = Executive::build(plan, exec, session.vehicle_setup());
    // The plan starts where the vehicle is (issue 30): beyond the acceptance radius, from a new place.
    if let Some((e, n)) = crate::vehicle::Vehicle::position(&session.vehicle) {
        ex.start_from(Enu::new(e, n, 0.0), session.start_radius_m, 0);
    }
    // Stepped, the simulator waits for the upload to reach the executive: it lands at a fixed sim time.
    let gate = Arc::new(StepGate::default());
    let mut live = match &setup.http {
        Some(h) => {
            let form = h.goals.then(|| {
                // The built-in simulator does not sign: neither does the demo's companion, nor its form.
                super::http_arg::goal_form(
                    home,
                    format!("tcpout:{gcs}"),
                    Some(gate.clone()),
                    None,
                    Some(session.vehicle.goal_intake()),
                )
            });
            let server =
                crate::report::live::start(rt.handle(), h.addr, form).map_err(|source| {
                    CliError::Http {
                        addr: h.addr,
                        source,
                    }
                })?;
            say(&format!("http listening on http://{}/", server.addr));
            let probe = session.vehicle.position_probe();
            Some(crate::report::live::LiveServer {
                feed: server.feed.with_position(probe).with_vehicle(
                    session.vehicle.status_probe(),
                    session.vehicle.goal_intake(),
                ),
                ..server
            })
        }
        None => None,
    };
    let timed_items = match &setup.timed_upload {
        Some(t) => Some((t.at_ms, t.items.items(home)?)),
        None => None,
    };
    let start_upload = |items: Vec<MissionItem>| {
        let addr = format!("tcpout:{gcs}");
        gate.expect_goal_batch();
        let gate = gate.clone();
        rt.spawn(async move {
            let r = send_goals(&addr, items, Duration::from_secs(60)).await;
            if r.is_err() {
                // Failed before or after the batch reached the executive: the pacer stops waiting.
                gate.cancel_goal_batch();
            }
            r
        })
    };
    let mut upload: Option<UploadTask> = None;
    let mut timed: Option<UploadTask> = None;
    let mut on_cycle = |ex: &Executive, c: &CycleRecord| {
        observe(c);
        if let Some(l) = live.as_mut() {
            l.feed.observe(ex, c);
        }
        let download = c.events.iter().any(
            |e| matches!(e, TraceEvent::Launch { action, .. } if action.starts_with("download_images")),
        );
        // The Fig. 2 story's e3/e4: only on the built-in problem.
        if download && upload.is_none() && setup.upload && setup.problem.is_none() {
            say("             ground station: uploading g6, g7 (pictures of new targets)");
            upload = Some(start_upload(picture_items(home, &NEW_GOALS)));
        }
        if let Some((at, items)) = timed_items.as_ref().filter(|(at, _)| c.time_ms >= *at) {
            if timed.is_none() {
                say(&format!(
                    "             ground station: uploading {} items at {:.1} s (due at {:.1} s)",
                    items.len(),
                    c.time_ms as f64 / 1000.0,
                    *at as f64 / 1000.0
                ));
                timed = Some(start_upload(items.clone()));
            }
        }
    };
    let opts = MissionOptions {
        time_limit_ms: problem_horizon(&problem),
        interrupt: setup.interrupt.clone(),
        ..MissionOptions::default()
    };
    // Stepped by the executive's clock, or paced at N× wall time.
    let (mut stepped, mut live_pacer);
    let pacer: &mut dyn Pacer<_> = match setup.speedup {
        None => {
            stepped = session.step_pacer(gate.clone());
            &mut stepped
        }
        Some(speedup) => {
            // The simulator runs in this process: its clock never goes stale.
            live_pacer = LivePacer::new(origin, speedup, Duration::MAX);
            &mut live_pacer
        }
    };
    let mut report = run_mission(&mut ex, &mut session.vehicle, pacer, &opts, &mut on_cycle);
    let interrupted = matches!(report.end, MissionEnd::Interrupted(_));
    if interrupted {
        // Stepped, the simulator moves only when stepped: the HOLD shows in its heartbeat after a few steps.
        report.shutdown = Some(match setup.speedup {
            None => {
                let pacer = session.step_pacer(gate.clone());
                session.vehicle.safe_stop(&mut |v| {
                    if let Err(e) = pacer.step_settled(v, 100) {
                        tracing::warn!("sitl step: {e}");
                    }
                })
            }
            Some(_) => session
                .vehicle
                .safe_stop(&mut |_| std::thread::sleep(Duration::from_millis(20))),
        });
    }
    if interrupted {
        for h in upload.iter().chain(&timed) {
            h.abort();
        }
    }
    let upload = upload.map(|h| upload_account(rt, h));
    let timed_upload = timed.map(|h| upload_account(rt, h));
    let ready = session.ready.clone();
    report.ready = ready.clone();
    let hold = match live {
        Some(l) => {
            l.feed.finish(&report);
            Some(LiveHold {
                addr: l.addr,
                _session: session,
            })
        }
        None => None,
    };
    Ok(DemoRun {
        report,
        upload,
        timed_upload,
        ready,
        fence,
        hold,
    })
}

type UploadTask = tokio::task::JoinHandle<Result<GoalSendReport, GoalSendError>>;

/// The ground station's account of its upload: the MISSION_ACK outcome and the goals' verdicts.
fn upload_account(rt: &tokio::runtime::Runtime, h: UploadTask) -> String {
    // The verdicts all came before the mission ended (it waits for every insertion); the bound is for a
    // ground station that lost its link.
    match rt.block_on(async { tokio::time::timeout(Duration::from_secs(30), h).await }) {
        Ok(Err(e)) if e.is_cancelled() => {
            "ground station: upload abandoned (mission interrupted)".into()
        }
        Ok(Ok(Ok(r))) => format!(
            "ground station: upload {}; {}",
            r.failure.as_deref().unwrap_or("accepted"),
            r.texts.join("; ")
        ),
        Ok(Ok(Err(e))) => format!("ground station: upload failed: {e}"),
        Ok(Err(e)) => format!("ground station: upload task: {e}"),
        Err(_) => "ground station: no answer within 30 s".into(),
    }
}

fn problem_horizon(p: &Problem) -> crate::model::Time {
    // A little past the horizon: goals still pending then are reported as such.
    p.horizon + 60_000
}

/// Picture goals at (east, north) metres from home, each a goal-attributes item (priority 1, start window
/// [0, 30 min], d_achiev 60 s) then a picture item: g6, g7 of the story.
pub fn picture_items(home: crate::vehicle::geo::Home, places: &[(f64, f64)]) -> Vec<MissionItem> {
    places
        .iter()
        .flat_map(|&(east, north)| picture_goal(home, east, north, 1_800.0, 60.0))
        .collect()
}

/// One picture goal at (east, north) metres from home: a goal-attributes item (priority 1, start window
/// [0, `window_end_s`], d_achiev) then the picture item.
pub fn picture_goal(
    home: crate::vehicle::geo::Home,
    east: f64,
    north: f64,
    window_end_s: f64,
    d_achiev_s: f64,
) -> [MissionItem; 2] {
    let attributes = MissionItem {
        command: GOAL_ATTRIBUTES_CMD,
        frame: 2,
        params: [1.0, 0.0, window_end_s as f32, 0.0],
        x: d_achiev_s,
        y: 0.0,
        z: 0.0,
        autocontinue: true,
    };
    let (lat, lon, _) = home.to_global(Enu::new(east, north, 0.0));
    let mut pic = MissionItem::waypoint(lat, lon, 0.0);
    pic.command = 2000; // MAV_CMD_IMAGE_START_CAPTURE: a picture goal
    [attributes, pic]
}
