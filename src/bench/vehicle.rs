//! `mavtempo bench link`: mission upload time over loopback and telemetry throughput of the MAVLink vehicle.

use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use mavlink::dialects::ardupilotmega::{
    MavMessage, BATTERY_STATUS_DATA, GLOBAL_POSITION_INT_DATA, SYSTEM_TIME_DATA, SYS_STATUS_DATA,
};
use tokio::io::AsyncWriteExt;

use crate::vehicle::config::VehicleConfig;
use crate::vehicle::driver::COMPANION_COMPONENT;
use crate::vehicle::endpoint::{Address, Transport};
use crate::vehicle::frame::{rover_heartbeat, Encoder, FrameDecoder};
use crate::vehicle::items::MissionItem;
use crate::vehicle::link::{GoalServer, LinkOptions, MavlinkVehicle};
use crate::vehicle::mission_client::{MissionClient, MissionOutcome};

#[derive(Debug, Clone, serde::Serialize)]
pub struct LinkBench {
    /// Median over `upload_runs` uploads of 100 items (MISSION_COUNT → MISSION_ACK), TCP loopback.
    pub upload_100_items_ms: f64,
    pub upload_runs: usize,
    /// Telemetry frames decoded and integrated per second through a live MavlinkVehicle (TCP loopback).
    pub telemetry_msgs_per_s: f64,
    pub telemetry_msgs: u64,
}

#[derive(Debug, thiserror::Error)]
pub enum VehicleBenchError {
    #[error("{0}")]
    Io(#[from] std::io::Error),
    #[error("{0}")]
    Link(#[from] crate::vehicle::link::LinkError),
    #[error("{0}")]
    Config(#[from] crate::vehicle::config::ConfigError),
    #[error("{0}")]
    Protocol(String),
}

const BENCH_CONFIG: &str = include_str!("../../tests/fixtures/vehicle/bindings.toml");

pub fn run_link_bench(
    upload_runs: usize,
    telemetry_msgs: u64,
) -> Result<LinkBench, VehicleBenchError> {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()?;
    rt.block_on(async {
        let upload = bench_upload(upload_runs.max(1)).await?;
        let rate = bench_telemetry(telemetry_msgs).await?;
        Ok(LinkBench {
            upload_100_items_ms: upload,
            upload_runs: upload_runs.max(1),
            telemetry_msgs_per_s: rate,
            telemetry_msgs,
        })
    })
}

async fn bench_upload(runs: usize) -> Result<f64, VehicleBenchError> {
    let home = crate::vehicle::geo::Home {
        lat: 43.56,
        lon: 1.48,
        alt: 0.0,
    };
    let server = GoalServer::syntactic("tcpin:127.0.0.1:0", home).await?;
    let addr = server
        .local_addr
        .ok_or_else(|| VehicleBenchError::Protocol("no local address".into()))?;
    let mut transport = Transport::bind(Address::TcpOut(addr.to_string())).await?;
    let mut ep = transport.open().await?;
    let items: Vec<MissionItem> = (0..100)
        .map(|i| MissionItem::waypoint(43.56 + f64::from(i) * 1e-5, 1.48, 0.0))
        .collect();
    let mut enc = Encoder::new(255, 190, None);
    let mut dec = FrameDecoder::default();
    let mut buf = vec![0u8; 65536];
    let mut times = Vec::with_capacity(runs);
    let epoch = Instant::now();
    for _ in 0..runs {
        let mut client = MissionClient::new((1, COMPANION_COMPONENT), 1500, 5);
        let mut out = Vec::new();
        let t0 = Instant::now();
        client.upload(
            0,
            items.clone(),
            epoch.elapsed().as_millis() as u64,
            &mut out,
        );
        'run: loop {
            for m in out.drain(..) {
                ep.send(&enc.encode(&m, false)).await?;
            }
            let n = tokio::time::timeout(Duration::from_secs(5), ep.recv(&mut buf))
                .await
                .map_err(|_| VehicleBenchError::Protocol("upload stalled".into()))??;
            if n == 0 {
                return Err(VehicleBenchError::Protocol("server closed".into()));
            }
            dec.push(&buf[..n]);
            while let Some(f) = dec.next_frame() {
                let Some(msg) = f.parse() else { continue };
                if let Some((_, outcome)) =
                    client.handle(&msg, epoch.elapsed().as_millis() as u64, &mut out)
                {
                    match outcome {
                        MissionOutcome::Uploaded => break 'run,
                        other => {
                            return Err(VehicleBenchError::Protocol(format!(
                                "upload failed: {other:?}"
                            )))
                        }
                    }
                }
            }
        }
        times.push(t0.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    Ok(times[times.len() / 2])
}

fn telemetry_stream(n: u64) -> Vec<u8> {
    let mut enc = Encoder::new(1, 1, None);
    let mut bytes = enc.encode(&rover_heartbeat(4), false);
    for i in 0..n.saturating_sub(1) {
        let t = i as u32;
        let msg = match i % 4 {
            0 => MavMessage::GLOBAL_POSITION_INT(GLOBAL_POSITION_INT_DATA {
                time_boot_ms: t,
                lat: 435_616_000 + (i % 1000) as i32,
                lon: 14_847_000,
                alt: 150_000,
                ..Default::default()
            }),
            1 => MavMessage::SYS_STATUS(SYS_STATUS_DATA {
                battery_remaining: 90 - (i % 50) as i8,
                ..Default::default()
            }),
            2 => MavMessage::BATTERY_STATUS(BATTERY_STATUS_DATA {
                battery_remaining: 90 - (i % 50) as i8,
                ..Default::default()
            }),
            _ => MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
                time_unix_usec: 0,
                time_boot_ms: t,
            }),
        };
        bytes.extend(enc.encode(&msg, false));
    }
    bytes
}

async fn bench_telemetry(n: u64) -> Result<f64, VehicleBenchError> {
    let mut cfg = VehicleConfig::parse(BENCH_CONFIG, "tests/fixtures/vehicle/bindings.toml")?;
    cfg.link.address = "tcpin:127.0.0.1:0".into();
    let vehicle = MavlinkVehicle::connect(cfg, LinkOptions::default()).await?;
    let addr = vehicle
        .local_addr()
        .ok_or_else(|| VehicleBenchError::Protocol("no local address".into()))?;
    let stream = telemetry_stream(n);
    let mut sock = tokio::net::TcpStream::connect(addr).await?;
    let t0 = Instant::now();
    let writer = tokio::spawn(async move {
        let r = sock.write_all(&stream).await;
        (sock, r)
    });
    let deadline = t0 + Duration::from_secs(60);
    while vehicle.stats().frames_in.load(Ordering::Relaxed) < n {
        if Instant::now() > deadline {
            return Err(VehicleBenchError::Protocol(
                "telemetry not all processed within 60 s".into(),
            ));
        }
        tokio::time::sleep(Duration::from_micros(200)).await;
    }
    let elapsed = t0.elapsed().as_secs_f64();
    let (_sock, r) = writer
        .await
        .map_err(|e| VehicleBenchError::Protocol(e.to_string()))?;
    r?;
    Ok(n as f64 / elapsed)
}
