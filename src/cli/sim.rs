//! `mavtempo sim`: the built-in SITL vehicle on a socket, until SIGINT (Ctrl-C) or SIGTERM. Wiring only.

use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

use crate::cli::out::outln;
use clap::Args;

#[derive(Args, Debug)]
pub struct SimArgs {
    /// tcpin:HOST:PORT, udpin:HOST:PORT, tcpout:HOST:PORT or udpout:HOST:PORT (port 0: any free port).
    #[arg(long, default_value = "tcpin:127.0.0.1:5760")]
    pub listen: String,
    /// Sim seconds per wall second.
    #[arg(long, default_value_t = 1.0)]
    pub speedup: f64,
    /// rover or auv.
    #[arg(long, default_value = "rover")]
    pub vehicle: String,
    /// Home as LAT,LON in degrees.
    #[arg(long)]
    pub home: Option<String>,
    /// Scenario file (TOML): world, parameters, faults.
    #[arg(long)]
    pub scenario: Option<PathBuf>,
    /// Seed for picture sizes and link faults.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Autopilot behaviours: default, ardupilot (as a real ArduPilot Rover) or px4 (as a real PX4 SIH
    /// rover). Replaces the scenario's `[autopilot] profile` (and the one `--config` gives); the
    /// scenario's other `[autopilot]` keys still apply.
    #[arg(long)]
    pub profile: Option<String>,
    /// Instead of a scenario, the nominal world of a mission, as `demo` runs one without a scenario: no
    /// fault; the card, pictures, capture time, speed and battery follow the vehicle configuration, the
    /// domain and the problem; home is the problem's, else the configuration's.
    #[arg(long, num_args = 3, value_names = ["CONFIG", "DOMAIN", "PROBLEM"], conflicts_with = "scenario")]
    pub nominal_for: Option<Vec<PathBuf>>,
    /// A vehicle configuration (config/*.toml): the simulator behaves as its `autopilot` (ardupilot or
    /// px4) and boots at its `[home]`, unless `--profile` / `--home` say otherwise.
    #[arg(long)]
    pub config: Option<PathBuf>,
}

/// Why `sim` cannot start: the simulator's own reasons, or the vehicle configuration's.
#[derive(Debug, thiserror::Error)]
enum SimCliError {
    #[error(transparent)]
    Sim(#[from] sitl::SimError),
    #[error(transparent)]
    Config(#[from] crate::vehicle::config::ConfigError),
}

pub fn run(args: SimArgs) -> ExitCode {
    let nominal = match args.nominal_for.as_deref().map(nominal_world).transpose() {
        Ok(n) => n,
        Err(e) => {
            crate::cli::out::errln!("mavtempo sim: {e}");
            return ExitCode::from(2);
        }
    };
    match configure(&args, nominal) {
        Ok(config) => serve(config),
        Err(e) => {
            crate::cli::out::errln!("mavtempo sim: {e}");
            ExitCode::from(2)
        }
    }
}

/// `--nominal-for CONFIG DOMAIN PROBLEM`: the world `demo` runs that mission in without a scenario.
fn nominal_world(paths: &[PathBuf]) -> Result<sitl::Scenario, super::error::CliError> {
    let [config, domain, problem] = paths else {
        return Err(super::error::CliError::NominalFor(paths.len()));
    };
    let cfg = crate::vehicle::config::VehicleConfig::load(config)?;
    let domain = crate::lang::load_domain(domain)?;
    let problem = crate::lang::load_problem(problem, &domain)?;
    let mut world = super::nominal_world::nominal_scenario(&domain, &problem, &cfg);
    let home = problem
        .home
        .map_or((cfg.home.lat, cfg.home.lon), |h| (h.lat, h.lon));
    world.home = Some(sitl::HomeParams {
        lat: home.0,
        lon: home.1,
    });
    Ok(world)
}

fn configure(
    args: &SimArgs,
    nominal: Option<sitl::Scenario>,
) -> Result<sitl::SimConfig, SimCliError> {
    let mut config = sitl::SimConfig {
        listen: args.listen.clone(),
        speedup: args.speedup,
        vehicle: args.vehicle.parse()?,
        seed: args.seed,
        ..sitl::SimConfig::default()
    };
    if let Some(path) = &args.scenario {
        config.scenario = sitl::Scenario::load(path)?;
    }
    if let Some(world) = nominal {
        config.scenario = world;
    }
    if let Some(path) = &args.config {
        use crate::vehicle::config::{Autopilot, VehicleConfig};
        let vc = VehicleConfig::load(path)?;
        config.scenario.autopilot.profile = match vc.autopilot {
            Autopilot::Ardupilot => sitl::Profile::Ardupilot,
            Autopilot::Px4 => sitl::Profile::Px4,
        };
        config.home = sitl::parse_home(&format!("{},{}", vc.home.lat, vc.home.lon))?;
        config.scenario.home = None;
    }
    if let Some(home) = &args.home {
        config.home = sitl::parse_home(home)?;
        // The command line wins over the scenario's [home].
        config.scenario.home = None;
    }
    if let Some(profile) = &args.profile {
        config.scenario.autopilot.profile = profile.parse()?;
    }
    config.validate()?;
    Ok(config)
}

fn serve(config: sitl::SimConfig) -> ExitCode {
    let rt = match super::runtime::multi_thread(None, "cannot start the runtime") {
        Ok(rt) => rt,
        Err(e) => {
            crate::cli::out::errln!("mavtempo sim: {e}");
            return ExitCode::FAILURE;
        }
    };
    rt.block_on(async move {
        let sim = match sitl::spawn(config).await {
            Ok(sim) => sim,
            Err(e) => {
                crate::cli::out::errln!("mavtempo sim: {e}");
                return ExitCode::FAILURE;
            }
        };
        // Scripts read this line to learn the port when they asked for port 0.
        outln!(
            "sitl listening on {} (connect with {})",
            sim.local_addr(),
            sim.client_address()
        );
        let _ = std::io::stdout().flush();
        stopped().await;
        sim.stop().await;
        ExitCode::SUCCESS
    })
}

/// Until SIGINT or SIGTERM (a service manager's stop): either stops the simulator cleanly.
async fn stopped() {
    use tokio::signal::unix::{signal, SignalKind};
    match signal(SignalKind::terminate()) {
        Ok(mut term) => {
            tokio::select! {
                _ = tokio::signal::ctrl_c() => {}
                _ = term.recv() => {}
            }
        }
        Err(_) => {
            let _ = tokio::signal::ctrl_c().await;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(profile: Option<&str>, home: Option<&str>) -> SimArgs {
        SimArgs {
            listen: "tcpin:127.0.0.1:0".into(),
            speedup: 1.0,
            vehicle: "rover".into(),
            home: home.map(String::from),
            scenario: Some(
                [
                    env!("CARGO_MANIFEST_DIR"),
                    "sitl/scenarios/ardupilot-rover.toml",
                ]
                .iter()
                .collect(),
            ),
            seed: 0,
            profile: profile.map(String::from),
            nominal_for: None,
            config: None,
        }
    }

    #[test]
    fn profile_and_home_on_the_command_line_win_over_the_scenario() {
        let cfg = configure(&args(None, None), None).expect("valid");
        assert_eq!(cfg.scenario.autopilot.profile, sitl::Profile::Ardupilot);
        assert_eq!(cfg.home_point().lat, 43.5616);
        let cfg = configure(&args(Some("default"), Some("43.5,1.25")), None).expect("valid");
        assert_eq!(cfg.scenario.autopilot.profile, sitl::Profile::Default);
        assert_eq!((cfg.home_point().lat, cfg.home_point().lon), (43.5, 1.25));
        let err = configure(&args(Some("betaflight"), None), None).expect_err("unknown profile");
        assert!(
            matches!(&err, SimCliError::Sim(sitl::SimError::UnknownProfile(p)) if p == "betaflight"),
            "{err}"
        );
    }

    /// `--nominal-for`: the first mission's world, as `demo` builds it, at the configuration's home.
    #[test]
    fn the_nominal_world_of_a_mission_replaces_the_scenario() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let paths: Vec<PathBuf> = [
            "config/sitl-vehicle.toml",
            "domains/vehicle/vehicle.ixt",
            "domains/vehicle/problems/first.ixt",
        ]
        .iter()
        .map(|p| root.join(p))
        .collect();
        let world = nominal_world(&paths).expect("the first mission's world");
        let mut a = args(None, None);
        a.scenario = None;
        let cfg = configure(&a, Some(world)).expect("valid");
        let camera = &cfg.scenario.camera;
        assert_eq!(camera.storage_capacity_mib, 10.0);
        assert_eq!((camera.size_min_mib, camera.size_max_mib), (1.0, 1.0));
        assert_eq!(camera.capture_time_s, 6.0);
        assert_eq!(cfg.scenario.vehicle.speed_mps, 1.0);
        assert_eq!(cfg.scenario.battery.drain_pct_per_km, 10.0);
        assert_eq!(cfg.home_point().lat, 43.5615);
        assert!(cfg.scenario.faults.is_empty());
        // With a scenario too, the command line is refused, not one of them silently dropped.
        let both = <super::super::Cli as clap::Parser>::try_parse_from([
            "mavtempo",
            "sim",
            "--scenario",
            "s.toml",
            "--nominal-for",
            "c",
            "d",
            "p",
        ]);
        assert!(both.is_err());
    }

    #[test]
    fn a_px4_vehicle_configuration_selects_the_px4_profile_and_its_home() {
        let mut a = args(None, None);
        a.config = Some(
            [env!("CARGO_MANIFEST_DIR"), "config/px4-rover.toml"]
                .iter()
                .collect(),
        );
        let cfg = configure(&a, None).expect("valid");
        assert_eq!(cfg.scenario.autopilot.profile, sitl::Profile::Px4);
        assert_eq!(
            (cfg.home_point().lat, cfg.home_point().lon),
            (47.397742, 8.545594)
        );
        // --profile still wins.
        a.profile = Some("default".into());
        let cfg = configure(&a, None).expect("valid");
        assert_eq!(cfg.scenario.autopilot.profile, sitl::Profile::Default);
        a.config = Some("no/such/config.toml".into());
        assert!(matches!(configure(&a, None), Err(SimCliError::Config(_))));
    }
}
