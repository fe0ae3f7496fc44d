//! `mavtempo bench sim`: the speed-up the simulator achieves on a real socket while a client runs
//! a mission on it (the 10-waypoint mission of the issue, at the requested speed-up), and the
//! ceiling of the machine.

use std::time::{Duration, Instant};

use mavlink::dialects::ardupilotmega::*;
use mavlink::{MavHeader, MavlinkVersion};
use serde::Serialize;
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;

use crate::config::{ClockMode, SimConfig};
use crate::error::SimError;
use crate::geo::LocalFrame;
use crate::sim::SimHandle;
use geodesy::deg_to_e7;

#[derive(Debug, Clone, Serialize)]
pub struct SpeedupReport {
    pub speedup_requested: f64,
    pub speedup_achieved: f64,
    /// Manual clock stepped flat out: how far this machine could go.
    pub speedup_ceiling: f64,
    pub waypoints: usize,
    pub leg_m: f64,
    pub sim_s: f64,
    pub wall_s: f64,
}

fn io(source: std::io::Error) -> SimError {
    SimError::Io {
        addr: "bench client".into(),
        source,
    }
}

struct Client {
    reader: mavlink::AsyncMavlinkReader<tokio::net::tcp::OwnedReadHalf>,
    writer: tokio::net::tcp::OwnedWriteHalf,
    seq: u8,
}

impl Client {
    async fn send(&mut self, m: MavMessage) -> Result<(), SimError> {
        let header = MavHeader {
            system_id: 255,
            component_id: 190,
            sequence: self.seq,
        };
        self.seq = self.seq.wrapping_add(1);
        let mut buf = Vec::new();
        mavlink::write_versioned_msg(&mut buf, MavlinkVersion::V2, header, &m)
            .map_err(|e| io(std::io::Error::other(e.to_string())))?;
        self.writer.write_all(&buf).await.map_err(io)
    }

    async fn until<T>(
        &mut self,
        mut f: impl FnMut(&MavMessage) -> Option<T>,
    ) -> Result<T, SimError> {
        loop {
            match self.reader.read_any_message::<MavMessage>().await {
                Ok((_, m)) => {
                    if let Some(t) = f(&m) {
                        return Ok(t);
                    }
                }
                Err(mavlink::error::MessageReadError::Parse(_)) => continue,
                Err(mavlink::error::MessageReadError::Io(e)) => return Err(io(e)),
            }
        }
    }

    async fn command(&mut self, command: MavCmd, p1: f32, p2: f32) -> Result<MavResult, SimError> {
        self.send(MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            param1: p1,
            param2: p2,
            command,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        }))
        .await?;
        self.until(|m| match m {
            MavMessage::COMMAND_ACK(a) if a.command == command => Some(a.result),
            _ => None,
        })
        .await
    }
}

/// Connects to `sim`, uploads a `waypoints`-leg zig-zag (legs of `leg_m`), arms and sets AUTO.
async fn start_mission(
    sim: &SimHandle,
    frame: &LocalFrame,
    waypoints: usize,
    leg_m: f64,
) -> Result<Client, SimError> {
    let stream = TcpStream::connect(sim.local_addr()).await.map_err(io)?;
    stream.set_nodelay(true).map_err(io)?;
    let (rd, wr) = stream.into_split();
    let mut c = Client {
        reader: mavlink::AsyncMavlinkReader::new(rd),
        writer: wr,
        seq: 0,
    };
    // A zig-zag: each leg turns 90 degrees.
    let mut items = vec![nalgebra::Vector2::zeros()];
    for i in 0..waypoints {
        let last = items[items.len() - 1];
        let step = if i % 2 == 0 {
            nalgebra::Vector2::new(leg_m, 0.0)
        } else {
            nalgebra::Vector2::new(0.0, leg_m)
        };
        items.push(last + step);
    }
    c.send(MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
        count: items.len() as u16,
        target_system: 1,
        target_component: 1,
        ..Default::default()
    }))
    .await?;
    loop {
        let next = c
            .until(|m| match m {
                MavMessage::MISSION_REQUEST_INT(r) => Some(Ok(r.seq)),
                MavMessage::MISSION_ACK(a) => Some(Err(a.mavtype)),
                _ => None,
            })
            .await?;
        let seq = match next {
            Ok(seq) => seq,
            Err(MavMissionResult::MAV_MISSION_ACCEPTED) => break,
            // A late item crossing a re-request; the upload stays open.
            Err(MavMissionResult::MAV_MISSION_INVALID_SEQUENCE) => continue,
            Err(other) => {
                return Err(io(std::io::Error::other(format!(
                    "upload refused: {other:?}"
                ))))
            }
        };
        let p = frame.to_geo(items[usize::from(seq).min(items.len() - 1)]);
        c.send(MavMessage::MISSION_ITEM_INT(MISSION_ITEM_INT_DATA {
            seq,
            x: deg_to_e7(p.lat),
            y: deg_to_e7(p.lon),
            command: MavCmd::MAV_CMD_NAV_WAYPOINT,
            frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
            autocontinue: 1,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        }))
        .await?;
    }
    for (cmd, p1, p2) in [
        (MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0),
        (MavCmd::MAV_CMD_DO_SET_MODE, 1.0, 10.0),
    ] {
        let result = c.command(cmd, p1, p2).await?;
        if result != MavResult::MAV_RESULT_ACCEPTED {
            return Err(io(std::io::Error::other(format!(
                "{cmd:?} refused: {result:?}"
            ))));
        }
    }
    Ok(c)
}

fn bench_config(speedup: f64, clock: ClockMode) -> SimConfig {
    SimConfig {
        listen: "tcpin:127.0.0.1:0".into(),
        speedup,
        clock,
        ..SimConfig::default()
    }
}

/// Runs the mission at `speedup` and measures sim time over wall time from the AUTO acknowledgement
/// to the last MISSION_ITEM_REACHED; then the same mission on the manual clock stepped as fast as
/// possible (telemetry still encoded and sent), which is the ceiling of this machine.
pub async fn measure_speedup(
    speedup: f64,
    waypoints: usize,
    leg_m: f64,
) -> Result<SpeedupReport, SimError> {
    let cfg = bench_config(speedup, ClockMode::Paced);
    let frame = LocalFrame::new(cfg.home_point());
    let sim = crate::spawn(cfg).await?;
    let mut c = start_mission(&sim, &frame, waypoints, leg_m).await?;
    let (sim0, wall0) = (sim.now_ms(), Instant::now());
    let last = waypoints as u16;
    let wait =
        Duration::from_secs_f64((waypoints as f64 * leg_m / 2.0 / speedup).max(1.0) * 20.0 + 10.0);
    tokio::time::timeout(
        wait,
        c.until(|m| match m {
            MavMessage::MISSION_ITEM_REACHED(r) if r.seq == last => Some(()),
            _ => None,
        }),
    )
    .await
    .map_err(|_| io(std::io::Error::other("mission did not complete in time")))??;
    let wall_s = wall0.elapsed().as_secs_f64();
    let sim_s = (sim.now_ms() - sim0) as f64 / 1000.0;
    sim.stop().await;

    let cfg = bench_config(1.0, ClockMode::Manual);
    let sim = crate::spawn(cfg).await?;
    let c = start_mission(&sim, &frame, waypoints, leg_m).await?;
    let wall0 = Instant::now();
    while !sim.snapshot().mission_complete && sim.now_ms() < 3_600_000 {
        sim.step(Duration::from_secs(10)).await?;
    }
    let ceiling = sim.now_ms() as f64 / 1000.0 / wall0.elapsed().as_secs_f64().max(1e-9);
    drop(c);
    sim.stop().await;
    Ok(SpeedupReport {
        speedup_requested: speedup,
        speedup_achieved: sim_s / wall_s.max(1e-9),
        speedup_ceiling: ceiling,
        waypoints,
        leg_m,
        sim_s,
        wall_s,
    })
}
