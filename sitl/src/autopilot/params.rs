//! The parameter protocol for the few parameters the simulator has (the fence's, src/fence.rs):
//! PARAM_REQUEST_READ by name or index, PARAM_REQUEST_LIST and PARAM_SET answered with PARAM_VALUE, as
//! ArduPilot does; an unknown name gets no answer (ArduPilot's behaviour: the reader times out).

use mavlink::dialects::ardupilotmega::*;
use nalgebra::Vector2;

use super::mission::Item;
use super::{Autopilot, Sender};
use crate::fence::{FenceParams, PARAMS};
use geodesy::deg_to_e7;

impl Autopilot {
    fn param_value(&mut self, from: Sender, index: usize) {
        let Some(name) = PARAMS.get(index) else {
            return;
        };
        let Some(value) = self.fence_params.param(name) else {
            return;
        };
        self.send_to(
            from.peer,
            MavMessage::PARAM_VALUE(PARAM_VALUE_DATA {
                param_value: value,
                param_count: PARAMS.len() as u16,
                param_index: index as u16,
                param_id: (*name).into(),
                param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
            }),
        );
    }

    pub(super) fn on_param_request_read(&mut self, from: Sender, m: &PARAM_REQUEST_READ_DATA) {
        let index = if m.param_index >= 0 {
            Some(m.param_index as usize)
        } else {
            let name = m.param_id.to_str().unwrap_or("");
            PARAMS.iter().position(|p| *p == name)
        };
        if let Some(i) = index {
            self.param_value(from, i);
        }
    }

    pub(super) fn on_param_request_list(&mut self, from: Sender) {
        for i in 0..PARAMS.len() {
            self.param_value(from, i);
        }
    }

    pub(super) fn on_param_set(&mut self, from: Sender, m: &PARAM_SET_DATA) {
        let name = m.param_id.to_str().unwrap_or("").to_string();
        if self.fence_params.set_param(&name, m.param_value) {
            if let Some(i) = PARAMS.iter().position(|p| *p == name) {
                self.param_value(from, i);
            }
        }
    }

    /// A scenario's fence as the list ArduPilot stores: each polygon as its vertices (param1 = their
    /// count), each circle as one item (param1 = radius).
    pub(super) fn fence_items(&self, f: &FenceParams) -> Vec<Item> {
        let item = |command: MavCmd, p1: f32, ne: [f64; 2]| {
            let g = self.frame.to_geo(Vector2::new(ne[0], ne[1]));
            Item {
                frame: MavFrame::MAV_FRAME_GLOBAL,
                command,
                autocontinue: 0,
                p: [p1, 0.0, 0.0, 0.0],
                x: deg_to_e7(g.lat),
                y: deg_to_e7(g.lon),
                z: 0.0,
                param5: 0.0,
            }
        };
        let mut items = Vec::new();
        for p in &f.polygons {
            let command = if p.inclusion {
                MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_INCLUSION
            } else {
                MavCmd::MAV_CMD_NAV_FENCE_POLYGON_VERTEX_EXCLUSION
            };
            for c in &p.corners_m {
                items.push(item(command, p.corners_m.len() as f32, *c));
            }
        }
        for c in &f.circles {
            let command = if c.inclusion {
                MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_INCLUSION
            } else {
                MavCmd::MAV_CMD_NAV_FENCE_CIRCLE_EXCLUSION
            };
            items.push(item(command, c.radius_m as f32, c.center_m));
        }
        items
    }
}
