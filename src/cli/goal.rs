//! `mavtempo goal send FILE --to ADDR` (a small ground station) and `mavtempo goal serve --listen ADDR`
//! (a goal intake answering uploads to component 191 with the default syntactic decider).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::{Args, Subcommand};

use crate::cli::out::outln;
use crate::vehicle::config::VehicleConfig;
use crate::vehicle::geo::Home;
use crate::vehicle::goal_client::{send_goals_signed, GoalSendError, GCS_SYSTEM_ID};
use crate::vehicle::goal_files;
use crate::vehicle::goals::{KnownLocations, SyntacticDecider};
use crate::vehicle::link::{signing_key, Decider, GoalServer};

#[derive(Args, Debug)]
pub struct GoalArgs {
    #[command(subcommand)]
    pub command: GoalCommand,
}

#[derive(Subcommand, Debug)]
pub enum GoalCommand {
    /// Upload the goals of a QGroundControl .plan or a .waypoints file to a companion (component 191).
    Send {
        /// The goal list: a QGroundControl `.plan` or a `.waypoints` file.
        file: PathBuf,
        /// Where the companion's goal intake listens, e.g. udpout:127.0.0.1:14551 or tcpout:HOST:PORT.
        #[arg(long)]
        to: String,
        /// Seconds to wait for the companion's heartbeat.
        #[arg(long, default_value_t = 5)]
        timeout: u64,
        /// The companion's vehicle configuration: when its `[link]` has a `signing_key`, every frame is
        /// signed with it (MAVLink2 signing; a companion with a key ignores unsigned stations).
        #[arg(long)]
        config: Option<PathBuf>,
    },
    /// Check a goal file and print the goal requests it maps to.
    Check {
        /// The goal list: a QGroundControl `.plan` or a `.waypoints` file.
        file: PathBuf,
    },
    /// Answer goal uploads (syntactic checks only; `mavtempo run` lets the executive decide).
    Serve {
        /// e.g. udpin:127.0.0.1:0 (the bound address is printed on stdout).
        #[arg(long)]
        listen: String,
        /// Home as LAT,LON (positions become local coordinates around it).
        #[arg(long, default_value = "0,0")]
        home: String,
        /// The MAVLink system id it answers as (the vehicle's).
        #[arg(long, default_value_t = 1)]
        system_id: u8,
        /// Record every frame to this .tlog.
        #[arg(long)]
        tlog: Option<PathBuf>,
        /// A vehicle configuration: with a `[link] signing_key`, only signed uploads are taken.
        #[arg(long)]
        config: Option<PathBuf>,
    },
}

pub fn run(args: GoalArgs) -> ExitCode {
    let rt = match super::runtime::multi_thread(Some(1), "tokio runtime") {
        Ok(rt) => rt,
        Err(e) => {
            crate::cli::out::errln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    match args.command {
        GoalCommand::Send {
            file,
            to,
            timeout,
            config,
        } => match signing_of(config.as_deref()) {
            Ok(key) => rt.block_on(send(file, to, timeout, key)),
            Err(code) => code,
        },
        GoalCommand::Check { file } => check(file),
        GoalCommand::Serve {
            listen,
            home,
            system_id,
            tlog,
            config,
        } => match signing_of(config.as_deref()) {
            Ok(key) => rt.block_on(serve(listen, home, system_id, tlog, key)),
            Err(code) => code,
        },
    }
}

/// The signing key and link id of the configuration at `path` (none without a path or a key); an
/// unreadable configuration or key is an error, printed.
fn signing_of(path: Option<&std::path::Path>) -> Result<Option<([u8; 32], u8)>, ExitCode> {
    let Some(path) = path else { return Ok(None) };
    let key = VehicleConfig::load(path)
        .map_err(|e| e.to_string())
        .and_then(|cfg| signing_key(&cfg).map_err(|e| e.to_string()));
    key.map_err(|e| {
        crate::cli::out::errln!("error: {e}");
        ExitCode::FAILURE
    })
}

fn check(file: PathBuf) -> ExitCode {
    let parsed = match goal_files::load(&file) {
        Ok(p) => p,
        Err(e) => {
            crate::cli::out::errln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let home = parsed.home.unwrap_or(Home {
        lat: 0.0,
        lon: 0.0,
        alt: 0.0,
    });
    for e in &parsed.skipped {
        crate::cli::out::errln!("warning: {e}");
    }
    let list = crate::vehicle::goals::items_to_goals(&parsed.items, &KnownLocations::new(home), 1);
    for e in &list.skipped {
        crate::cli::out::errln!("warning: {}: {e}", file.display());
    }
    for g in list.requests() {
        outln!(
            "{}: {} priority {} window [{}, {}] s duration [{}, {}] s d_achiev {} s",
            g.name,
            g.proposition,
            g.priority,
            g.start_window_s.0,
            g.start_window_s.1,
            g.duration_s.0,
            g.duration_s.1,
            g.d_achiev_s
        );
    }
    ExitCode::SUCCESS
}

async fn send(
    file: PathBuf,
    to: String,
    timeout: u64,
    signing: Option<([u8; 32], u8)>,
) -> ExitCode {
    let parsed = match goal_files::load(&file) {
        Ok(p) => p,
        Err(e) => {
            crate::cli::out::errln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    for e in &parsed.skipped {
        crate::cli::out::errln!("warning: {e}");
    }
    let timeout = Duration::from_secs(timeout);
    match send_goals_signed(GCS_SYSTEM_ID, signing, &to, parsed.items, timeout).await {
        Ok(report) => {
            for t in &report.texts {
                outln!("{t}");
            }
            match report.failure {
                None => {
                    outln!("upload accepted");
                    ExitCode::SUCCESS
                }
                Some(f) => {
                    crate::cli::out::errln!("error: {f}");
                    ExitCode::FAILURE
                }
            }
        }
        Err(e @ GoalSendError::NoCompanion(_)) if signing.is_none() => {
            crate::cli::out::errln!(
                "error: {e} (a companion that requires MAVLink2 signing ignores unsigned stations: \
                 give its configuration with --config)"
            );
            ExitCode::FAILURE
        }
        Err(e) => {
            crate::cli::out::errln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

async fn serve(
    listen: String,
    home: String,
    system_id: u8,
    tlog: Option<PathBuf>,
    signing: Option<([u8; 32], u8)>,
) -> ExitCode {
    let parsed: Option<(f64, f64)> = home
        .split_once(',')
        .and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)));
    let Some((lat, lon)) = parsed else {
        crate::cli::out::errln!("error: --home: expected LAT,LON, got `{home}`");
        return ExitCode::FAILURE;
    };
    let known = KnownLocations::new(Home { lat, lon, alt: 0.0 });
    let server = match GoalServer::start_signed(
        &listen,
        system_id,
        known,
        Decider::Local(Box::new(SyntacticDecider)),
        tlog,
        signing,
    )
    .await
    {
        Ok(s) => s,
        Err(e) => {
            crate::cli::out::errln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    match server.local_addr {
        Some(a) => outln!("listening on {a}"),
        None => outln!("listening on {listen}"),
    }
    // Decided locally: the server's event channel stays empty; keep the server alive until Ctrl-C.
    let _ = tokio::signal::ctrl_c().await;
    drop(server);
    ExitCode::SUCCESS
}
