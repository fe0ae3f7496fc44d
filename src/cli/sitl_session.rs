//! The built-in SITL rover in process, linked to the executive over real sockets: what `demo` and
//! `bench cpu` share (spawn the simulator on a scenario, connect the MAVLink vehicle with its ground-station
//! endpoint, wait for telemetry, pace the mission by stepping the simulator).

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::error::CliError;
use crate::exec::pacer::StepGate;
use crate::exec::DomainMapping;
use crate::model::{Domain, Problem};
use crate::sitl_pacer::SitlStepPacer;
use crate::vehicle::config::VehicleConfig;
use crate::vehicle::geo::Home;
use crate::vehicle::link::{Decider, LinkOptions};
use crate::vehicle::readiness::ReadyReport;
use crate::vehicle::{MavlinkVehicle, Vehicle};

const DEMO_CONFIG: &str = include_str!("../../config/demo-rover.toml");

/// A running SITL and the vehicle linked to it. Field order is drop order: the link closes before the
/// simulator and the runtime go.
pub struct SitlSession {
    pub vehicle: MavlinkVehicle,
    /// How the vehicle became ready (a fix, arming accepted) before the mission; `None`: not waited for.
    pub ready: Option<ReadyReport>,
    pub sim: Arc<sitl::SimHandle>,
    /// The effective home (the problem's, else the configuration's).
    pub home: Home,
    /// The configuration's `[mapping]`, resolved against the domain and problem.
    pub mapping: DomainMapping,
    /// Where ground stations connect (tcp).
    pub gcs: String,
    /// The vehicle time (ms) of the plan's origin.
    pub origin_ms: u64,
    /// Within this distance of the plan's place the vehicle is there (the moves' acceptance radius).
    pub start_radius_m: f64,
    /// Where the vehicle may go (`[limits]`).
    pub limits: Option<crate::vehicle::limits::Limits>,
    /// What the autopilot's fence, read at readiness, added to them (`None`: not read).
    pub fence: Option<String>,
    /// The configuration's `[resources]`: the levels reported, their resolution and tolerance.
    pub resources: crate::vehicle::config::ResourceNames,
    /// `[state] moving`: the attribute a motion's end makes still (src/executive/src/exec/still.rs).
    pub moving: Option<crate::vehicle::observed::Flag>,
    pub rt: tokio::runtime::Runtime,
}

/// What a session runs: the vehicle's configuration, the simulator's scenario and vehicle kind.
pub struct SessionSpec {
    pub config: VehicleConfig,
    pub scenario: sitl::Scenario,
    pub vehicle: sitl::VehicleKind,
    /// Paced at this speed-up; stepped by the executive's clock when `None`.
    pub speedup: Option<f64>,
    /// Goals uploaded by ground stations are numbered from here.
    pub first_goal_number: u32,
    /// Seeds the simulator's picture sizes and link faults.
    pub seed: u64,
    /// The simulated vehicle starts this far (east, north metres) from the problem's home.
    pub vehicle_offset_m: (f64, f64),
}

impl SessionSpec {
    /// The demo's rover: config/demo-rover.toml with `scenario` (TOML text, `scenario_name` for messages).
    pub fn demo_rover(scenario: &str, scenario_name: &str) -> Result<SessionSpec, CliError> {
        Ok(SessionSpec {
            config: VehicleConfig::parse(DEMO_CONFIG, "config/demo-rover.toml")?,
            scenario: sitl::Scenario::parse(scenario, scenario_name)?,
            vehicle: sitl::VehicleKind::Rover,
            speedup: None,
            first_goal_number: 1,
            seed: 1,
            vehicle_offset_m: (0.0, 0.0),
        })
    }
}

impl SitlSession {
    /// What the session's vehicle configuration gives the executive ([`crate::exec::builder`]).
    pub fn vehicle_setup(&self) -> crate::exec::builder::VehicleSetup<'_> {
        crate::exec::builder::VehicleSetup {
            mapping: self.mapping.clone(),
            resources: &self.resources,
            moving: self.moving.as_ref(),
            limits: self.limits.clone(),
        }
    }

    /// Checks `spec`'s configuration against `domain` and `problem` (the home is the problem's when it
    /// has one), spawns the SITL there, paced or stepped, and links the vehicle to it over real sockets.
    pub fn start(
        domain: &Domain,
        problem: &Problem,
        spec: SessionSpec,
    ) -> Result<SitlSession, CliError> {
        let checked = super::check::checked_config(&spec.config, domain, Some(problem))?;
        let rt = super::runtime::multi_thread(Some(2), "tokio runtime")?;
        let home = checked.home;
        let mut cfg = checked.vehicle;
        // The simulator is frozen while the executive plans (stepped) or runs fast (paced): wall-clock
        // timeouts must not take a long planning for a lost link.
        cfg.link.heartbeat_timeout_ms = cfg.link.heartbeat_timeout_ms.max(60_000);
        let (sim_lat, sim_lon) = match spec.vehicle_offset_m {
            (0.0, 0.0) => (home.lat, home.lon),
            (east, north) => {
                let (lat, lon, _) = home.to_global(crate::vehicle::Enu::new(east, north, 0.0));
                (lat, lon)
            }
        };
        let start_radius_m = crate::vehicle::authority::start_radius_m(&cfg);
        let limits_cfg = cfg.limits.clone();
        let resources = cfg.resources.clone();
        let moving = cfg.state.moving.clone().filter(|_| cfg.state.end_still);
        let mut sim_cfg = sitl::SimConfig {
            listen: "tcpin:127.0.0.1:0".into(),
            scenario: spec.scenario,
            seed: spec.seed,
            vehicle: spec.vehicle,
            home: sitl::GeoPoint {
                lat: sim_lat,
                lon: sim_lon,
            },
            ..sitl::SimConfig::for_tests()
        };
        if let Some(s) = spec.speedup {
            sim_cfg.clock = sitl::ClockMode::Paced;
            sim_cfg.speedup = s;
        }
        sim_cfg.validate()?;
        let sim = Arc::new(rt.block_on(sitl::spawn(sim_cfg))?);
        let known = super::run::known_locations(home, problem);
        let opts = LinkOptions {
            address: Some(sim.client_address().to_string()),
            gcs: Some("tcpin:127.0.0.1:0".into()),
            known: Some(known),
            decider: Decider::Executive {
                timeout: Duration::from_secs(60),
            },
            first_goal_number: spec.first_goal_number,
            ..LinkOptions::default()
        };
        let ready_limit_s = cfg.ready.timeout_s;
        let vehicle = rt.block_on(MavlinkVehicle::connect(cfg, opts))?;
        let gcs = vehicle
            .gcs_addr()
            .ok_or(CliError::NoGcsAddress)?
            .to_string();
        let stepped = spec.speedup.is_none();
        link_up(&rt, &sim, &vehicle, stepped)?;
        let ready = wait_ready(&rt, &sim, &vehicle, spec.speedup, ready_limit_s)?;
        // `[limits]` and the autopilot's fence, read at readiness.
        let fence = vehicle.autopilot_fence();
        let (limits, said) = crate::vehicle::fence::limits_for(&limits_cfg, home, fence.as_ref());
        let origin_ms = if stepped {
            sim.now_ms()
        } else {
            vehicle.now_ms()
        };
        Ok(SitlSession {
            vehicle,
            ready,
            sim,
            home,
            mapping: checked.mapping,
            gcs,
            origin_ms,
            start_radius_m,
            limits,
            fence: said,
            resources,
            moving,
            rt,
        })
    }

    /// The pacer of a stepped session: steps of at most 500 ms of sim time; goal uploads announced to
    /// `gate` land before the next step.
    pub fn step_pacer(&self, gate: Arc<StepGate>) -> SitlStepPacer {
        stepper(&self.sim, self.rt.handle().clone(), self.origin_ms, gate)
    }
}

fn stepper(
    sim: &Arc<sitl::SimHandle>,
    runtime: tokio::runtime::Handle,
    origin_ms: u64,
    gate: Arc<StepGate>,
) -> SitlStepPacer {
    // Wall bound of each wait: the link settles in well under a millisecond, an upload in tens.
    SitlStepPacer::new(
        sim.clone(),
        runtime,
        origin_ms,
        500,
        Duration::from_secs(10),
        gate,
    )
}

/// Waits (stepping the simulator when stepped) for the vehicle to be ready: a fix, arming accepted, as
/// `run` does on a real autopilot; an error says why not, after `limit_s` of sim time.
fn wait_ready(
    rt: &tokio::runtime::Runtime,
    sim: &Arc<sitl::SimHandle>,
    vehicle: &MavlinkVehicle,
    speedup: Option<f64>,
    limit_s: f64,
) -> Result<Option<ReadyReport>, CliError> {
    if limit_s <= 0.0 {
        return Ok(None);
    }
    let limit_ms = (limit_s * 1000.0) as u64;
    let report = if speedup.is_none() {
        let pacer = stepper(sim, rt.handle().clone(), sim.now_ms(), Arc::default());
        vehicle.wait_ready(limit_ms, Duration::from_secs(60), &mut |v| match pacer
            .step_settled(v, 100)
        {
            Ok(_) => true,
            Err(e) => {
                tracing::warn!("sitl step: {e}");
                false
            }
        })
    } else {
        // Paced: the limit runs on the sim's clock; the wall bound only covers a clock that stops.
        let wall = Duration::from_secs_f64(limit_s / speedup.unwrap_or(1.0).max(0.01) + 30.0);
        vehicle.wait_ready(limit_ms, wall, &mut |_| {
            std::thread::sleep(Duration::from_millis(10));
            true
        })
    };
    if report.ready {
        Ok(Some(report))
    } else {
        Err(CliError::NotReady(report.why_not(limit_s)))
    }
}

/// Steps (or waits for) the simulator until the vehicle's clock runs: the link is up. Stepped, the
/// companion must be connected before the first step and every step settled, so that the mission starts
/// at the same sim time with the same telemetry run after run.
fn link_up(
    rt: &tokio::runtime::Runtime,
    sim: &Arc<sitl::SimHandle>,
    vehicle: &MavlinkVehicle,
    stepped: bool,
) -> Result<(), CliError> {
    if stepped {
        let deadline = Instant::now() + Duration::from_secs(10);
        while sim.peer_count() == 0 {
            if Instant::now() >= deadline {
                return Err(CliError::SitlNotConnected);
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        let pacer = stepper(sim, rt.handle().clone(), sim.now_ms(), Arc::default());
        for _ in 0..200 {
            if vehicle.now_ms() > 0 && vehicle.target().is_some() {
                return Ok(());
            }
            // The events (link up, levels) stay for the executive's first cycle.
            pacer.step_settled(vehicle, 200)?;
        }
    } else {
        for _ in 0..200 {
            if vehicle.now_ms() > 0 && vehicle.target().is_some() {
                return Ok(());
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
    Err(CliError::NoTelemetry)
}
