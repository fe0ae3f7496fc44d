//! Mission store and the mission protocol as ArduPilot runs it: item 0 is home, one uploader at a
//! time, re-request after ~1 s, cancel after 8 s, wrong seq answered with INVALID_SEQUENCE while the
//! upload stays open, legacy MISSION_ITEM / MISSION_REQUEST accepted, clear refused in AUTO. The fence
//! list (`mission_type` = FENCE, src/fence.rs) goes through the same protocol, without a home item.

use std::time::Instant;

use mavlink::dialects::ardupilotmega::*;

use super::{Autopilot, Dest, Mode, Sender};
use crate::config::MissionRequestKind;
use geodesy::deg_to_e7;

/// Largest mission accepted (ArduPilot's storage holds a few hundred on small boards).
const MAX_ITEMS: u16 = 700;

/// One stored mission item, in MISSION_ITEM_INT units.
#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    pub frame: MavFrame,
    pub command: MavCmd,
    pub autocontinue: u8,
    pub p: [f32; 4],
    pub x: i32,
    pub y: i32,
    pub z: f32,
    /// param5 as sent, for commands that carry a number there rather than a latitude
    /// (DO_DIGICAM_CONTROL's shooting command).
    pub param5: f32,
}

impl Item {
    fn from_int(m: &MISSION_ITEM_INT_DATA) -> Self {
        Self {
            frame: m.frame,
            command: m.command,
            autocontinue: m.autocontinue,
            p: [m.param1, m.param2, m.param3, m.param4],
            x: m.x,
            y: m.y,
            z: m.z,
            param5: m.x as f32,
        }
    }

    fn from_float(m: &MISSION_ITEM_DATA) -> Self {
        let global = is_global(m.frame);
        let conv = |v: f32| {
            if global {
                deg_to_e7(f64::from(v))
            } else {
                (f64::from(v) * 1e4).round() as i32
            }
        };
        Self {
            frame: m.frame,
            command: m.command,
            autocontinue: m.autocontinue,
            p: [m.param1, m.param2, m.param3, m.param4],
            x: conv(m.x),
            y: conv(m.y),
            z: m.z,
            param5: m.x,
        }
    }

    pub fn is_nav(&self) -> bool {
        (self.command as u32) <= 95
    }
}

/// The error for an item position that cannot be a place: latitude beyond ±90°, longitude beyond ±180° (in
/// global frames), or a non-finite coordinate; `None` when it can be one.
pub(super) fn absurd_position(global: bool, x: f64, y: f64, z: f32) -> Option<MavMissionResult> {
    if !x.is_finite() || (global && x.abs() > 90.0) {
        Some(MavMissionResult::MAV_MISSION_INVALID_PARAM5_X)
    } else if !y.is_finite() || (global && y.abs() > 180.0) {
        Some(MavMissionResult::MAV_MISSION_INVALID_PARAM6_Y)
    } else if !z.is_finite() {
        Some(MavMissionResult::MAV_MISSION_INVALID_PARAM7)
    } else {
        None
    }
}

/// MISSION_ITEM_INT -> legacy MISSION_ITEM: degrees in global frames, metres (x 1e-4) otherwise.
fn to_float(m: &MISSION_ITEM_INT_DATA) -> MISSION_ITEM_DATA {
    let scale = if is_global(m.frame) { 1e-7 } else { 1e-4 };
    MISSION_ITEM_DATA {
        param1: m.param1,
        param2: m.param2,
        param3: m.param3,
        param4: m.param4,
        x: (f64::from(m.x) * scale) as f32,
        y: (f64::from(m.y) * scale) as f32,
        z: m.z,
        seq: m.seq,
        command: m.command,
        target_system: m.target_system,
        target_component: m.target_component,
        frame: m.frame,
        current: m.current,
        autocontinue: m.autocontinue,
        mission_type: m.mission_type,
    }
}

pub fn is_global(f: MavFrame) -> bool {
    matches!(
        f,
        MavFrame::MAV_FRAME_GLOBAL
            | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT
            | MavFrame::MAV_FRAME_GLOBAL_INT
            | MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT_INT
            | MavFrame::MAV_FRAME_GLOBAL_TERRAIN_ALT
            | MavFrame::MAV_FRAME_GLOBAL_TERRAIN_ALT_INT
            | MavFrame::MAV_FRAME_MISSION
    )
}

/// An upload in progress.
#[derive(Debug)]
pub struct Upload {
    pub from: Sender,
    /// The mission or the fence list.
    pub mission_type: MavMissionType,
    pub count: u16,
    pub next: u16,
    pub items: Vec<Item>,
    pub last_request: Instant,
    pub last_activity: Instant,
}

impl Autopilot {
    pub(super) fn home_item(&self) -> Item {
        let home = self.frame.origin();
        Item {
            frame: MavFrame::MAV_FRAME_GLOBAL,
            command: MavCmd::MAV_CMD_NAV_WAYPOINT,
            autocontinue: 1,
            p: [0.0; 4],
            x: deg_to_e7(home.lat),
            y: deg_to_e7(home.lon),
            z: 0.0,
            param5: 0.0,
        }
    }

    fn mission_ack(&mut self, from: Sender, result: MavMissionResult) {
        self.mission_ack_of(from, result, MavMissionType::MAV_MISSION_TYPE_MISSION);
    }

    fn mission_ack_of(&mut self, from: Sender, result: MavMissionResult, mt: MavMissionType) {
        self.send_to(
            from.peer,
            MavMessage::MISSION_ACK(MISSION_ACK_DATA {
                target_system: from.sysid,
                target_component: from.compid,
                mavtype: result,
                mission_type: mt,
                opaque_id: 0,
            }),
        );
    }

    fn send_request(&mut self, from: Sender, seq: u16, mission_type: MavMissionType) {
        let msg = match self.mission_request {
            MissionRequestKind::Int => MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
                seq,
                target_system: from.sysid,
                target_component: from.compid,
                mission_type,
            }),
            MissionRequestKind::Legacy => MavMessage::MISSION_REQUEST(MISSION_REQUEST_DATA {
                seq,
                target_system: from.sysid,
                target_component: from.compid,
                mission_type,
            }),
        };
        self.send_to(from.peer, msg);
    }

    pub(super) fn on_mission_count(&mut self, from: Sender, m: &MISSION_COUNT_DATA) {
        let fence = m.mission_type == MavMissionType::MAV_MISSION_TYPE_FENCE;
        if m.mission_type != MavMissionType::MAV_MISSION_TYPE_MISSION && !fence {
            self.mission_ack_of(
                from,
                MavMissionResult::MAV_MISSION_UNSUPPORTED,
                m.mission_type,
            );
            return;
        }
        // One uploader at a time.
        if self.refused_for_another_upload(from, MavMissionResult::MAV_MISSION_DENIED) {
            return;
        }
        if m.count > MAX_ITEMS {
            self.mission_ack(from, MavMissionResult::MAV_MISSION_NO_SPACE);
            return;
        }
        if m.count == 0 {
            self.upload = None;
            if fence {
                self.fence.clear();
                self.mission_ack_of(from, MavMissionResult::MAV_MISSION_ACCEPTED, m.mission_type);
            } else {
                self.clear_mission(from);
            }
            return;
        }
        let now = Instant::now();
        self.upload = Some(Upload {
            from,
            mission_type: m.mission_type,
            count: m.count,
            next: 0,
            items: Vec::with_capacity(usize::from(m.count)),
            last_request: now,
            last_activity: now,
        });
        self.send_request(from, 0, m.mission_type);
    }

    pub(super) fn on_mission_item(
        &mut self,
        from: Sender,
        seq: u16,
        item: Item,
        mission_type: MavMissionType,
    ) {
        let Some(u) = self.upload.as_mut() else {
            // ArduPilot ignores items outside an upload (with a warning).
            return;
        };
        if u.from != from || mission_type != u.mission_type {
            return;
        }
        if seq != u.next {
            self.mission_ack_of(
                from,
                MavMissionResult::MAV_MISSION_INVALID_SEQUENCE,
                mission_type,
            );
            return;
        }
        let now = Instant::now();
        u.items.push(item);
        u.next += 1;
        u.last_activity = now;
        if u.next < u.count {
            u.last_request = now;
            let next = u.next;
            self.send_request(from, next, mission_type);
            return;
        }
        let Some(mut done) = self.upload.take() else {
            return;
        };
        if mission_type == MavMissionType::MAV_MISSION_TYPE_FENCE {
            self.fence = done.items;
            self.mission_ack_of(from, MavMissionResult::MAV_MISSION_ACCEPTED, mission_type);
            return;
        }
        // Item 0 is always home on ArduPilot; PX4 keeps it as sent.
        if !self.is_px4() {
            done.items[0] = self.home_item();
        }
        self.install_mission(done.items);
        self.mission_ack(from, MavMissionResult::MAV_MISSION_ACCEPTED);
        self.text(MavSeverity::MAV_SEVERITY_INFO, "Flight plan received");
    }

    pub(super) fn on_item_int(&mut self, from: Sender, m: &MISSION_ITEM_INT_DATA) {
        let bad = absurd_position(
            is_global(m.frame),
            f64::from(m.x) / 1e7,
            f64::from(m.y) / 1e7,
            m.z,
        );
        if let Some(result) = bad {
            return self.refuse_item(from, result);
        }
        self.on_mission_item(from, m.seq, Item::from_int(m), m.mission_type);
    }

    pub(super) fn on_item_float(&mut self, from: Sender, m: &MISSION_ITEM_DATA) {
        let bad = absurd_position(is_global(m.frame), f64::from(m.x), f64::from(m.y), m.z);
        if let Some(result) = bad {
            return self.refuse_item(from, result);
        }
        self.on_mission_item(from, m.seq, Item::from_float(m), m.mission_type);
    }

    /// An item that cannot be a place ends its sender's upload with the error, as ArduPilot does.
    fn refuse_item(&mut self, from: Sender, result: MavMissionResult) {
        if let Some(u) = self.upload.as_ref().filter(|u| u.from == from) {
            let mt = u.mission_type;
            self.upload = None;
            self.mission_ack_of(from, result, mt);
        }
    }

    /// Re-requests and cancels on the wall clock; called by the run loop.
    pub fn check_upload_timers(&mut self, now: Instant) {
        let Some(u) = self.upload.as_mut() else {
            return;
        };
        if now.duration_since(u.last_activity) >= self.mission_timeout {
            let (from, mt) = (u.from, u.mission_type);
            self.upload = None;
            self.mission_ack_of(from, MavMissionResult::MAV_MISSION_OPERATION_CANCELLED, mt);
            self.text(MavSeverity::MAV_SEVERITY_WARNING, "Mission upload timeout");
        } else if now.duration_since(u.last_request) >= self.mission_rerequest {
            u.last_request = now;
            let (from, next, mt) = (u.from, u.next, u.mission_type);
            self.send_request(from, next, mt);
        }
    }

    /// When the run loop must next look at the upload timers.
    pub fn upload_deadline(&self) -> Option<Instant> {
        self.upload.as_ref().map(|u| {
            (u.last_request + self.mission_rerequest).min(u.last_activity + self.mission_timeout)
        })
    }

    fn install_mission(&mut self, items: Vec<Item>) {
        let running = self.mode == Mode::Auto && self.exec.started;
        self.mission = items;
        if self.mission_items() == 0 {
            self.exec = Default::default();
        } else if running && usize::from(self.exec.current) < self.mission.len() {
            // As ArduPilot's mission-change detector: restart the current command.
            let cur = self.exec.current;
            self.exec.restart_at(cur);
        } else {
            self.exec = Default::default();
        }
    }

    pub(super) fn clear_mission(&mut self, from: Sender) {
        if self.mode == Mode::Auto {
            self.mission_ack(from, MavMissionResult::MAV_MISSION_ERROR);
            self.text(
                MavSeverity::MAV_SEVERITY_WARNING,
                "Mission clear refused in AUTO",
            );
            return;
        }
        self.mission = self.empty_mission();
        self.exec = Default::default();
        self.mission_ack(from, MavMissionResult::MAV_MISSION_ACCEPTED);
    }

    pub(super) fn on_clear_all(&mut self, from: Sender, m: &MISSION_CLEAR_ALL_DATA) {
        if m.mission_type == MavMissionType::MAV_MISSION_TYPE_FENCE {
            if self.refused_for_another_upload(from, MavMissionResult::MAV_MISSION_ERROR) {
                return;
            }
            self.upload = None;
            self.fence.clear();
            self.mission_ack_of(from, MavMissionResult::MAV_MISSION_ACCEPTED, m.mission_type);
            return;
        }
        if m.mission_type == MavMissionType::MAV_MISSION_TYPE_ALL {
            self.fence.clear();
        }
        if !matches!(
            m.mission_type,
            MavMissionType::MAV_MISSION_TYPE_MISSION | MavMissionType::MAV_MISSION_TYPE_ALL
        ) {
            self.mission_ack(from, MavMissionResult::MAV_MISSION_UNSUPPORTED);
            return;
        }
        if self.refused_for_another_upload(from, MavMissionResult::MAV_MISSION_ERROR) {
            return;
        }
        self.upload = None;
        self.clear_mission(from);
    }

    /// Answers `from` with `result` when another ground station's upload is under way.
    fn refused_for_another_upload(&mut self, from: Sender, result: MavMissionResult) -> bool {
        match &self.upload {
            Some(u) if u.from != from => {
                self.mission_ack(from, result);
                true
            }
            _ => false,
        }
    }

    pub(super) fn on_request_list(&mut self, from: Sender, m: &MISSION_REQUEST_LIST_DATA) {
        if m.mission_type != MavMissionType::MAV_MISSION_TYPE_MISSION {
            // The fence list; no rally points: an empty list.
            let count = if m.mission_type == MavMissionType::MAV_MISSION_TYPE_FENCE {
                self.fence.len() as u16
            } else {
                0
            };
            self.send_to(
                from.peer,
                MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
                    count,
                    target_system: from.sysid,
                    target_component: from.compid,
                    mission_type: m.mission_type,
                    opaque_id: 0,
                }),
            );
            return;
        }
        let count = self.mission.len() as u16;
        self.send_to(
            from.peer,
            MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
                count,
                target_system: from.sysid,
                target_component: from.compid,
                mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
                opaque_id: 0,
            }),
        );
    }

    /// Download: answer MISSION_REQUEST_INT with MISSION_ITEM_INT, legacy MISSION_REQUEST with MISSION_ITEM.
    pub(super) fn on_request_item(
        &mut self,
        from: Sender,
        seq: u16,
        legacy: bool,
        mt: MavMissionType,
    ) {
        let list = match mt {
            MavMissionType::MAV_MISSION_TYPE_MISSION => &self.mission,
            MavMissionType::MAV_MISSION_TYPE_FENCE => &self.fence,
            _ => {
                self.mission_ack_of(from, MavMissionResult::MAV_MISSION_UNSUPPORTED, mt);
                return;
            }
        };
        let Some(it) = list.get(usize::from(seq)).cloned() else {
            self.mission_ack_of(from, MavMissionResult::MAV_MISSION_INVALID_SEQUENCE, mt);
            return;
        };
        let int = MISSION_ITEM_INT_DATA {
            param1: it.p[0],
            param2: it.p[1],
            param3: it.p[2],
            param4: it.p[3],
            x: it.x,
            y: it.y,
            z: it.z,
            seq,
            command: it.command,
            target_system: from.sysid,
            target_component: from.compid,
            frame: it.frame,
            current: u8::from(
                mt == MavMissionType::MAV_MISSION_TYPE_MISSION && seq == self.exec.current,
            ),
            autocontinue: it.autocontinue,
            mission_type: mt,
        };
        let msg = if legacy {
            MavMessage::MISSION_ITEM(to_float(&int))
        } else {
            MavMessage::MISSION_ITEM_INT(int)
        };
        self.send_to(from.peer, msg);
    }

    pub(super) fn mission_current_msg(&self) -> MavMessage {
        let total = self.mission_items() as u16;
        let state = if total == 0 {
            MissionState::MISSION_STATE_NO_MISSION
        } else if self.exec.complete {
            MissionState::MISSION_STATE_COMPLETE
        } else if !self.exec.started {
            MissionState::MISSION_STATE_NOT_STARTED
        } else if self.mode == Mode::Auto {
            MissionState::MISSION_STATE_ACTIVE
        } else {
            MissionState::MISSION_STATE_PAUSED
        };
        MavMessage::MISSION_CURRENT(MISSION_CURRENT_DATA {
            seq: self.exec.current,
            total,
            mission_state: state,
            mission_mode: u8::from(self.mode == Mode::Auto),
            mission_id: 0,
            fence_id: 0,
            rally_points_id: 0,
        })
    }

    pub(super) fn broadcast_mission_current(&mut self) {
        let m = self.mission_current_msg();
        self.send(Dest::All, m);
    }
}
