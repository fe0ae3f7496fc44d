//! A mission item independent of the wire message (MISSION_ITEM_INT or legacy MISSION_ITEM) and of the file
//! format (.plan, .waypoints): what the mission client uploads and the goal intake receives.

// The legacy MISSION_ITEM / MISSION_REQUEST must still be accepted (ArduPilot sends MISSION_REQUEST).
#![allow(deprecated)]

use mavlink::dialects::ardupilotmega::{
    MavCmd, MavFrame, MavMissionType, MISSION_ITEM_DATA, MISSION_ITEM_INT_DATA,
};
use num_traits::{FromPrimitive, ToPrimitive};

/// Frames whose x/y are latitude/longitude (degrees; ×1e7 on the wire in MISSION_ITEM_INT).
pub fn frame_is_global(frame: u8) -> bool {
    matches!(frame, 0 | 3 | 5 | 6 | 10 | 11)
}

#[derive(Debug, Clone, PartialEq)]
pub struct MissionItem {
    pub command: u16,
    pub frame: u8,
    pub params: [f32; 4],
    /// Latitude (deg) in a global frame, else param5.
    pub x: f64,
    /// Longitude (deg) in a global frame, else param6.
    pub y: f64,
    pub z: f32,
    pub autocontinue: bool,
}

impl MissionItem {
    pub fn new(command: MavCmd, frame: MavFrame) -> Self {
        Self {
            command: command.to_u16().unwrap_or(0),
            frame: frame.to_u8().unwrap_or(0),
            params: [0.0; 4],
            x: 0.0,
            y: 0.0,
            z: 0.0,
            autocontinue: true,
        }
    }

    pub fn waypoint(lat: f64, lon: f64, alt: f32) -> Self {
        let mut it = Self::new(
            MavCmd::MAV_CMD_NAV_WAYPOINT,
            MavFrame::MAV_FRAME_GLOBAL_RELATIVE_ALT,
        );
        it.x = lat;
        it.y = lon;
        it.z = alt;
        it
    }

    pub fn has_position(&self) -> bool {
        frame_is_global(self.frame) && (self.x != 0.0 || self.y != 0.0)
    }

    /// The wire form; `None` when the command or frame is unknown to the dialect.
    pub fn to_int(
        &self,
        seq: u16,
        target: (u8, u8),
        mission_type: MavMissionType,
    ) -> Option<MISSION_ITEM_INT_DATA> {
        let global = frame_is_global(self.frame);
        Some(MISSION_ITEM_INT_DATA {
            param1: self.params[0],
            param2: self.params[1],
            param3: self.params[2],
            param4: self.params[3],
            x: if global {
                (self.x * 1e7).round() as i32
            } else {
                self.x.round() as i32
            },
            y: if global {
                (self.y * 1e7).round() as i32
            } else {
                self.y.round() as i32
            },
            z: self.z,
            seq,
            command: MavCmd::from_u16(self.command)?,
            target_system: target.0,
            target_component: target.1,
            frame: MavFrame::from_u8(self.frame)?,
            current: 0,
            autocontinue: u8::from(self.autocontinue),
            mission_type,
        })
    }

    pub fn from_int(d: &MISSION_ITEM_INT_DATA) -> Self {
        let frame = d.frame.to_u8().unwrap_or(0);
        let global = frame_is_global(frame);
        let scale = if global { 1e-7 } else { 1.0 };
        Self {
            command: d.command.to_u16().unwrap_or(0),
            frame,
            params: [d.param1, d.param2, d.param3, d.param4],
            x: f64::from(d.x) * scale,
            y: f64::from(d.y) * scale,
            z: d.z,
            autocontinue: d.autocontinue != 0,
        }
    }

    pub fn from_float(d: &MISSION_ITEM_DATA) -> Self {
        Self {
            command: d.command.to_u16().unwrap_or(0),
            frame: d.frame.to_u8().unwrap_or(0),
            params: [d.param1, d.param2, d.param3, d.param4],
            x: f64::from(d.x),
            y: f64::from(d.y),
            z: d.z,
            autocontinue: d.autocontinue != 0,
        }
    }
}
