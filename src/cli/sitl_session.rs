//! The built-in SITL rover in process, linked to the executive over real sockets: what `demo` and
//! `bench cpu` share (spawn the simulator on a scenario, connect the MAVLink vehicle with its ground-station
//! endpoint, wait for telemetry, pace the mission by stepping the simulator).

use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::exec::pacer::{SitlStepPacer, StepGate};
use crate::model::Problem;
use crate::vehicle::geo::Home;
use crate::vehicle::goals::KnownLocations;
use crate::vehicle::link::{Decider, LinkOptions};
use crate::vehicle::{Enu, MavlinkVehicle, Vehicle};

const CONFIG: &str = include_str!("../../config/demo-rover.toml");

/// The executive's `level_tolerance` against this SITL: it reports the battery in whole percents, and the
/// rover stops within its acceptance radius (1.5 m, 0.75 % of battery short of the planned distance).
pub const LEVEL_TOLERANCE: f64 = 2.0;

/// A running SITL and the vehicle linked to it. Field order is drop order: the link closes before the
/// simulator and the runtime go.
pub struct SitlSession {
    pub vehicle: MavlinkVehicle,
    pub sim: Arc<sitl::SimHandle>,
    /// Home of the vehicle configuration (config/demo-rover.toml).
    pub home: Home,
    /// Where ground stations connect (tcp).
    pub gcs: String,
    /// The vehicle time (ms) of the plan's origin.
    pub origin_ms: u64,
    pub rt: tokio::runtime::Runtime,
}

impl SitlSession {
    /// Spawns the SITL on `scenario` (TOML text, `scenario_name` for messages), paced at `speedup` or
    /// stepped, and links the vehicle; goals uploaded by ground stations are numbered from
    /// `first_goal_number`.
    pub fn start(
        problem: &Problem,
        scenario: &str,
        scenario_name: &str,
        speedup: Option<f64>,
        first_goal_number: u32,
    ) -> Result<SitlSession, String> {
        let rt = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .enable_all()
            .build()
            .map_err(|e| format!("tokio runtime: {e}"))?;
        let scenario = sitl::Scenario::parse(scenario, scenario_name).map_err(|e| e.to_string())?;
        let mut sim_cfg = sitl::SimConfig {
            listen: "tcpin:127.0.0.1:0".into(),
            scenario,
            seed: 1,
            ..sitl::SimConfig::for_tests()
        };
        if let Some(s) = speedup {
            sim_cfg.clock = sitl::ClockMode::Paced;
            sim_cfg.speedup = s;
        }
        sim_cfg.validate().map_err(|e| e.to_string())?;
        let sim = Arc::new(
            rt.block_on(sitl::spawn(sim_cfg))
                .map_err(|e| e.to_string())?,
        );
        let cfg = crate::vehicle::config::VehicleConfig::parse(CONFIG, "config/demo-rover.toml")
            .map_err(|e| e.to_string())?;
        let home = cfg.home;
        let mut known = KnownLocations::new(home);
        let geo_home = problem.home;
        for o in &problem.objects {
            if let Some((e, n, u)) = o.local(geo_home.as_ref()) {
                known.objects.push((o.name.clone(), Enu::new(e, n, u)));
            }
        }
        let opts = LinkOptions {
            address: Some(sim.client_address().to_string()),
            gcs: Some("tcpin:127.0.0.1:0".into()),
            known: Some(known),
            decider: Decider::Executive {
                timeout: Duration::from_secs(60),
            },
            first_goal_number,
            ..LinkOptions::default()
        };
        let vehicle = rt
            .block_on(MavlinkVehicle::connect(cfg, opts))
            .map_err(|e| e.to_string())?;
        let gcs = vehicle
            .gcs_addr()
            .ok_or("the ground-station endpoint has no address")?
            .to_string();
        let stepped = speedup.is_none();
        link_up(&rt, &sim, &vehicle, stepped)?;
        let origin_ms = if stepped {
            sim.now_ms()
        } else {
            vehicle.now_ms()
        };
        Ok(SitlSession {
            vehicle,
            sim,
            home,
            gcs,
            origin_ms,
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

/// Steps (or waits for) the simulator until the vehicle's clock runs: the link is up. Stepped, the
/// companion must be connected before the first step and every step settled, so that the mission starts
/// at the same sim time with the same telemetry run after run.
fn link_up(
    rt: &tokio::runtime::Runtime,
    sim: &Arc<sitl::SimHandle>,
    vehicle: &MavlinkVehicle,
    stepped: bool,
) -> Result<(), String> {
    if stepped {
        let deadline = Instant::now() + Duration::from_secs(10);
        while sim.peer_count() == 0 {
            if Instant::now() >= deadline {
                return Err("the vehicle link did not connect to the SITL".into());
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        let pacer = stepper(sim, rt.handle().clone(), sim.now_ms(), Arc::default());
        for _ in 0..200 {
            if vehicle.now_ms() > 0 && vehicle.target().is_some() {
                return Ok(());
            }
            // The events (link up, levels) stay for the executive's first cycle.
            pacer
                .step_settled(vehicle, 200)
                .map_err(|e| e.to_string())?;
        }
    } else {
        for _ in 0..200 {
            if vehicle.now_ms() > 0 && vehicle.target().is_some() {
                return Ok(());
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
    Err("no telemetry from the SITL rover".into())
}
