//! A minimal MAVLink ground station for the socket tests: its own TCP/UDP socket, frames via the
//! `mavlink` crate only (no sitl types), bounded waits with deadlines.
#![allow(dead_code, deprecated)]

use std::net::SocketAddr;
use std::time::Duration;

use mavlink::dialects::ardupilotmega::*;
use mavlink::{MavHeader, MavlinkVersion, Message};
use tokio::io::AsyncWriteExt;
use tokio::net::tcp::OwnedWriteHalf;
use tokio::net::TcpStream;
use tokio::sync::mpsc;

pub const WAIT: Duration = Duration::from_secs(5);

/// `$gcs.expect` of the next `$variant` message (bounded wait, as [`Gcs::expect`]): a future of its data.
#[allow(unused_macros)]
macro_rules! expect_msg {
    ($gcs:expr, $variant:ident) => {
        $gcs.expect(stringify!($variant), |m| match m {
            MavMessage::$variant(d) => Some(d.clone()),
            _ => None,
        })
    };
}
#[allow(unused_imports)]
pub(crate) use expect_msg;

pub struct Gcs {
    wr: OwnedWriteHalf,
    rx: mpsc::UnboundedReceiver<(MavlinkVersion, MavHeader, MavMessage)>,
    /// Version and header of the last frame `expect` looked at.
    pub last_version: Option<MavlinkVersion>,
    pub last_header: Option<MavHeader>,
    /// Messages `expect` passed over, oldest first (taken by `sync` and `seen`).
    backlog: Vec<(MavlinkVersion, MavHeader, MavMessage)>,
    seq: u8,
    pub version: MavlinkVersion,
    pub sysid: u8,
    pub compid: u8,
}

impl Gcs {
    pub async fn connect(addr: SocketAddr) -> Self {
        let stream = TcpStream::connect(addr).await.expect("connect to sim");
        let (rd, wr) = stream.into_split();
        let (tx, rx) = mpsc::unbounded_channel();
        tokio::spawn(async move {
            let mut reader = mavlink::AsyncMavlinkReader::new(rd);
            loop {
                match reader.read_any_raw_message::<MavMessage>().await {
                    Ok(raw) => {
                        let Ok(m) =
                            MavMessage::parse(raw.version(), raw.message_id(), raw.payload())
                        else {
                            continue;
                        };
                        let h = MavHeader {
                            system_id: raw.system_id(),
                            component_id: raw.component_id(),
                            sequence: raw.sequence(),
                        };
                        if tx.send((raw.version(), h, m)).is_err() {
                            break;
                        }
                    }
                    Err(mavlink::error::MessageReadError::Parse(_)) => continue,
                    Err(_) => break,
                }
            }
        });
        Self {
            wr,
            rx,
            last_version: None,
            last_header: None,
            backlog: Vec::new(),
            seq: 0,
            version: MavlinkVersion::V2,
            sysid: 255,
            compid: 190,
        }
    }

    pub async fn send(&mut self, m: MavMessage) {
        let header = MavHeader {
            system_id: u32::from(self.sysid),
            component_id: self.compid,
            sequence: self.seq,
        };
        self.seq = self.seq.wrapping_add(1);
        let mut buf = Vec::new();
        mavlink::write_versioned_msg(&mut buf, self.version, header, &m).expect("encode");
        self.wr.write_all(&buf).await.expect("write");
    }

    /// REQUEST_DATA_STREAM(ALL, stop): every data stream off.
    pub async fn stop_all_streams(&mut self) {
        self.send(MavMessage::REQUEST_DATA_STREAM(REQUEST_DATA_STREAM_DATA {
            req_message_rate: 0,
            target_system: 1,
            target_component: 1,
            req_stream_id: MavDataStream::MAV_DATA_STREAM_ALL,
            start_stop: 0,
        }))
        .await;
    }

    /// COMMAND_LONG arm addressed to `target_system`, sent without waiting for any answer.
    pub async fn send_arm_to(&mut self, target_system: u8) {
        self.send(MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            param1: 1.0,
            command: MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
            target_system,
            target_component: 1,
            ..Default::default()
        }))
        .await;
    }

    /// The first message satisfying `f`: from the backlog, else waiting (wall time, bounded).
    pub async fn expect<T>(
        &mut self,
        what: &str,
        mut f: impl FnMut(&MavMessage) -> Option<T>,
    ) -> T {
        for i in 0..self.backlog.len() {
            if let Some(t) = f(&self.backlog[i].2) {
                self.backlog.remove(i);
                return t;
            }
        }
        let deadline = tokio::time::Instant::now() + WAIT;
        loop {
            match tokio::time::timeout_at(deadline, self.rx.recv()).await {
                Ok(Some((v, h, m))) => {
                    self.last_version = Some(v);
                    self.last_header = Some(h);
                    if let Some(t) = f(&m) {
                        return t;
                    }
                    self.backlog.push((v, h, m));
                }
                Ok(None) => panic!("link closed while waiting for {what}"),
                Err(_) => panic!("timed out waiting for {what}"),
            }
        }
    }

    /// Round trip: returns every message the sim sent before answering a REQUEST_MESSAGE, so
    /// that nothing it produced earlier is still in flight.
    pub async fn sync(&mut self) -> Vec<MavMessage> {
        self.sync_inner().await;
        std::mem::take(&mut self.backlog)
            .into_iter()
            .map(|f| f.2)
            .collect()
    }

    async fn sync_inner(&mut self) {
        self.send(MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            command: MavCmd::MAV_CMD_REQUEST_MESSAGE,
            target_system: 1,
            target_component: 1,
            ..Default::default()
        }))
        .await;
        self.expect("sync ACK", |m| match m {
            MavMessage::COMMAND_ACK(a) if a.command == MavCmd::MAV_CMD_REQUEST_MESSAGE => Some(()),
            _ => None,
        })
        .await;
    }

    /// As `sync`, with each frame's version and header.
    pub async fn sync_frames(&mut self) -> Vec<(MavlinkVersion, MavHeader, MavMessage)> {
        self.sync_inner().await;
        std::mem::take(&mut self.backlog)
    }

    /// The STATUSTEXTs among `msgs`.
    pub fn texts(msgs: &[MavMessage]) -> Vec<String> {
        Self::texts_with_severity(msgs)
            .into_iter()
            .map(|(_, t)| t)
            .collect()
    }

    /// The STATUSTEXTs among `msgs` with their severity.
    pub fn texts_with_severity(msgs: &[MavMessage]) -> Vec<(MavSeverity, String)> {
        msgs.iter()
            .filter_map(|m| match m {
                MavMessage::STATUSTEXT(t) => Some((
                    t.severity,
                    t.text
                        .to_str()
                        .unwrap_or("")
                        .trim_end_matches('\0')
                        .to_string(),
                )),
                _ => None,
            })
            .collect()
    }

    /// Everything received so far with its header.
    pub fn drain_frames(&mut self) -> Vec<(MavlinkVersion, MavHeader, MavMessage)> {
        self.backlog.clear();
        let mut v = Vec::new();
        while let Ok(f) = self.rx.try_recv() {
            v.push(f);
        }
        v
    }

    /// Everything received so far (including what `expect` passed over).
    pub fn drain(&mut self) -> Vec<MavMessage> {
        let mut v: Vec<MavMessage> = std::mem::take(&mut self.backlog)
            .into_iter()
            .map(|f| f.2)
            .collect();
        while let Ok((_, _, m)) = self.rx.try_recv() {
            v.push(m);
        }
        v
    }

    pub async fn command_long(&mut self, command: MavCmd, p: [f32; 7]) -> (MavResult, u8) {
        self.send(MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            param1: p[0],
            param2: p[1],
            param3: p[2],
            param4: p[3],
            param5: p[4],
            param6: p[5],
            param7: p[6],
            command,
            target_system: 1,
            target_component: 1,
            confirmation: 0,
        }))
        .await;
        self.ack_of(command).await
    }

    /// COMMAND_LONG `command` with its first params `p` (the others 0); the ACK's result.
    pub async fn command(&mut self, command: MavCmd, p: &[f32]) -> MavResult {
        let mut params = [0.0; 7];
        params[..p.len()].copy_from_slice(p);
        self.command_long(command, params).await.0
    }

    /// REQUEST_MESSAGE for message `id`; the ACK's result.
    pub async fn request_message(&mut self, id: u32) -> MavResult {
        self.command(MavCmd::MAV_CMD_REQUEST_MESSAGE, &[id as f32])
            .await
    }

    pub async fn command_int(
        &mut self,
        command: MavCmd,
        p: [f32; 4],
        x: i32,
        y: i32,
        z: f32,
    ) -> (MavResult, u8) {
        self.command_int_in(MavFrame::MAV_FRAME_GLOBAL, command, p, (x, y, z))
            .await
    }

    /// COMMAND_INT in `frame` at `xyz` (lat/lon ×1e7, altitude); the ACK's result and progress.
    pub async fn command_int_in(
        &mut self,
        frame: MavFrame,
        command: MavCmd,
        p: [f32; 4],
        (x, y, z): (i32, i32, f32),
    ) -> (MavResult, u8) {
        self.send(MavMessage::COMMAND_INT(COMMAND_INT_DATA {
            param1: p[0],
            param2: p[1],
            param3: p[2],
            param4: p[3],
            x,
            y,
            z,
            command,
            target_system: 1,
            target_component: 1,
            frame,
            current: 0,
            autocontinue: 0,
        }))
        .await;
        self.ack_of(command).await
    }

    /// `MAV_CMD_DO_REPOSITION` over COMMAND_INT to `wp` at altitude `z`; `switch_mode` sets param2 bit 1
    /// (switch to GUIDED).
    pub async fn reposition(
        &mut self,
        wp: &MISSION_ITEM_INT_DATA,
        switch_mode: bool,
        z: f32,
    ) -> (MavResult, u8) {
        let flags = if switch_mode { 1.0 } else { 0.0 };
        self.command_int(
            MavCmd::MAV_CMD_DO_REPOSITION,
            [-1.0, flags, 0.0, 0.0],
            wp.x,
            wp.y,
            z,
        )
        .await
    }

    pub async fn ack_of(&mut self, command: MavCmd) -> (MavResult, u8) {
        self.expect("COMMAND_ACK", |m| match m {
            MavMessage::COMMAND_ACK(a) if a.command == command => Some((a.result, a.progress)),
            _ => None,
        })
        .await
    }

    /// IMAGE_START_CAPTURE with p1 camera id, p2 interval, p3 count; the result.
    pub async fn image_start_capture(&mut self, p: [f32; 3]) -> MavResult {
        self.command(MavCmd::MAV_CMD_IMAGE_START_CAPTURE, &p).await
    }

    pub async fn set_mode(&mut self, mode: u32) -> MavResult {
        self.command(MavCmd::MAV_CMD_DO_SET_MODE, &[1.0, mode as f32])
            .await
    }

    pub async fn arm(&mut self) -> MavResult {
        self.command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, &[1.0])
            .await
    }

    /// Uploads `items` (seq 0 is a placeholder for home) with MISSION_ITEM_INT; returns the ACK.
    pub async fn upload(&mut self, items: &[MISSION_ITEM_INT_DATA]) -> MavMissionResult {
        self.upload_with(items.len() as u16, |seq| {
            let mut it = items[usize::from(seq)].clone();
            it.seq = seq;
            it.target_system = 1;
            it.target_component = 1;
            MavMessage::MISSION_ITEM_INT(it)
        })
        .await
    }

    /// Uploads `count` items, answering each request with `item(seq)`; returns the final ACK.
    pub async fn upload_with(
        &mut self,
        count: u16,
        item: impl Fn(u16) -> MavMessage,
    ) -> MavMissionResult {
        self.send(MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
            count,
            target_system: 1,
            target_component: 1,
            mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
            opaque_id: 0,
        }))
        .await;
        loop {
            let next = self
                .expect("MISSION_REQUEST or ACK", |m| match m {
                    MavMessage::MISSION_REQUEST_INT(r) => Some(Ok(r.seq)),
                    MavMessage::MISSION_REQUEST(r) => Some(Ok(r.seq)),
                    MavMessage::MISSION_ACK(a) => Some(Err(a.mavtype)),
                    _ => None,
                })
                .await;
            match next {
                Ok(seq) => self.send(item(seq)).await,
                // A late item crossing a re-request is answered INVALID_SEQUENCE while the
                // upload stays open (as on ArduPilot): keep going.
                Err(MavMissionResult::MAV_MISSION_INVALID_SEQUENCE) => continue,
                Err(result) => return result,
            }
        }
    }
}

/// A NAV_WAYPOINT at metres north/east of `home` (the Earth model the SITL uses).
pub fn waypoint(home: (f64, f64), north: f64, east: f64) -> MISSION_ITEM_INT_DATA {
    let frame = geodesy::LocalFrame::new(geodesy::Geodetic::new(home.0, home.1, 0.0));
    let p = frame.to_geodetic(geodesy::Enu::new(east, north, 0.0));
    MISSION_ITEM_INT_DATA {
        x: geodesy::deg_to_e7(p.lat),
        y: geodesy::deg_to_e7(p.lon),
        command: MavCmd::MAV_CMD_NAV_WAYPOINT,
        frame: MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
        autocontinue: 1,
        ..Default::default()
    }
}

pub fn item(command: MavCmd, p: [f32; 4]) -> MISSION_ITEM_INT_DATA {
    MISSION_ITEM_INT_DATA {
        command,
        param1: p[0],
        param2: p[1],
        param3: p[2],
        param4: p[3],
        frame: MavFrame::MAV_FRAME_MISSION,
        autocontinue: 1,
        ..Default::default()
    }
}

pub const HOME: (f64, f64) = (43.5615, 1.4778);

/// Steps the manual clock in 100 ms slices until `pred` holds on the snapshot (bounded in sim time).
pub async fn run_until(
    sim: &sitl::SimHandle,
    max_s: u64,
    pred: impl Fn(&sitl::Snapshot) -> bool,
) -> sitl::Snapshot {
    for _ in 0..max_s * 10 {
        sim.step(Duration::from_millis(100)).await.expect("step");
        let s = sim.snapshot();
        if pred(&s) {
            return s;
        }
    }
    panic!(
        "condition not reached within {max_s} sim seconds: {:?}",
        sim.snapshot()
    );
}

/// What the sim sends over the next `d` of sim time (what was in flight before is dropped first).
pub async fn sent_over(sim: &sitl::SimHandle, gcs: &mut Gcs, d: Duration) -> Vec<MavMessage> {
    gcs.sync().await;
    sim.step(d).await.expect("step");
    gcs.sync().await
}

/// A sim on port 0 with the manual clock and `scenario` (TOML text), plus a connected client.
pub async fn start(scenario: &str) -> (sitl::SimHandle, Gcs) {
    let mut cfg = sitl::SimConfig::for_tests();
    cfg.scenario = sitl::Scenario::parse(scenario, "test").expect("scenario");
    start_with(cfg).await
}

/// A sim spawned from `cfg`, plus a client connected over TCP.
pub async fn start_with(cfg: sitl::SimConfig) -> (sitl::SimHandle, Gcs) {
    let sim = sitl::spawn(cfg).await.expect("spawn");
    let gcs = Gcs::connect(sim.local_addr()).await;
    (sim, gcs)
}

/// IMAGE_START_CAPTURE of one picture with the default camera; it must be accepted.
pub async fn capture(gcs: &mut Gcs) {
    let r = gcs.image_start_capture([0.0, 0.0, 1.0]).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
}

/// One picture (as [`capture`]), then what the sim sends until `d` of sim time later (the capture's ACK
/// aside).
pub async fn shoot(sim: &sitl::SimHandle, gcs: &mut Gcs, d: Duration) -> Vec<MavMessage> {
    capture(gcs).await;
    sim.step(d).await.expect("step");
    gcs.sync().await
}

/// Uploads a mission through `gcs` and checks it is accepted.
pub async fn upload_ok(gcs: &mut Gcs, items: &[MISSION_ITEM_INT_DATA]) {
    assert_eq!(
        gcs.upload(items).await,
        MavMissionResult::MAV_MISSION_ACCEPTED
    );
}

/// Uploads `items` through `gcs`, arms and switches to AUTO (mode 10), each step accepted.
pub async fn start_auto(gcs: &mut Gcs, items: &[MISSION_ITEM_INT_DATA]) {
    upload_ok(gcs, items).await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(gcs.set_mode(10).await, MavResult::MAV_RESULT_ACCEPTED);
}
