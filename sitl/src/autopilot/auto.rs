//! AUTO: ArduPilot's mission executor. A NAV command runs until verified; the DO commands that
//! follow it run while it runs (and are skipped if it completes first), as AP_Mission does.
//! Also the navigation target of RTL and GUIDED.

use std::collections::VecDeque;

use mavlink::dialects::ardupilotmega::*;
use nalgebra::Vector2;

use super::mission::{is_global, Item};
use super::{Autopilot, Dest, Mode};
use crate::config::VehicleKind;
use crate::faults::SimEvent;
use crate::physics::Target;
use crate::scenario::EventKind;
use crate::time::later;

/// Mission execution state.
#[derive(Debug, Default, Clone)]
pub struct Exec {
    /// Current NAV item (0 before the mission starts).
    pub current: u16,
    pub started: bool,
    pub complete: bool,
    nav_loaded: bool,
    reached: bool,
    hold_until_ms: u64,
    do_queue: VecDeque<u16>,
}

impl Exec {
    pub fn restart_at(&mut self, seq: u16) {
        self.current = seq;
        self.complete = false;
        self.nav_loaded = false;
        self.reached = false;
        self.do_queue.clear();
    }
}

impl Autopilot {
    /// Starts (or resumes) the mission, as entering AUTO armed does.
    pub(super) fn start_mission(&mut self) {
        if self.mission_items() == 0 {
            return;
        }
        let first = self.first_item();
        if self.exec.complete || (first == 1 && self.exec.current == 0) {
            self.exec.restart_at(first);
        } else {
            let cur = self.exec.current;
            self.exec.restart_at(cur);
        }
        if !self.exec.started {
            self.exec.started = true;
        }
        self.emit_event(EventKind::MissionStarted, 0);
    }

    pub(super) fn item_position(&self, it: &Item) -> (Vector2<f64>, f64) {
        if (it.x == 0 && it.y == 0) || !is_global(it.frame) {
            // ArduPilot "sanitizes" a zero location to the current one.
            return (self.kin.pos, self.kin.depth);
        }
        (self.frame.to_local_e7(it.x, it.y), self.depth_of(it.z))
    }

    fn next_nav_after(&self, seq: u16) -> Option<u16> {
        (usize::from(seq) + 1..self.mission.len())
            .find(|&i| self.mission[i].is_nav())
            .map(|i| i as u16)
    }

    /// One AUTO step: load, verify and advance NAV commands; run one pending DO command.
    pub(super) fn step_auto(&mut self) {
        if self.mode != Mode::Auto || !self.armed || !self.exec.started || self.exec.complete {
            return;
        }
        if !self.exec.nav_loaded {
            self.load_nav();
            if self.exec.complete {
                return;
            }
        }
        if let Some(seq) = self.exec.do_queue.pop_front() {
            if let Some(it) = self.mission.get(usize::from(seq)).cloned() {
                self.run_do(seq, &it);
            }
        }
        self.verify_nav();
    }

    /// Finds the NAV command at or after `current` (running DO commands met before it).
    fn load_nav(&mut self) {
        let mut seq = self.exec.current.max(self.first_item());
        while usize::from(seq) < self.mission.len() && !self.mission[usize::from(seq)].is_nav() {
            let it = self.mission[usize::from(seq)].clone();
            self.run_do(seq, &it);
            seq += 1;
        }
        if usize::from(seq) >= self.mission.len() {
            self.complete_mission();
            return;
        }
        self.exec.current = seq;
        self.exec.nav_loaded = true;
        self.exec.reached = false;
        self.exec.hold_until_ms = 0;
        let end = self
            .next_nav_after(seq)
            .unwrap_or(self.mission.len() as u16);
        self.exec.do_queue = (seq + 1..end).collect();
        let it = &self.mission[usize::from(seq)];
        let known = matches!(
            it.command,
            MavCmd::MAV_CMD_NAV_WAYPOINT
                | MavCmd::MAV_CMD_NAV_LOITER_TIME
                | MavCmd::MAV_CMD_NAV_LOITER_UNLIM
                | MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH
                | MavCmd::MAV_CMD_NAV_DELAY
        );
        if !known {
            let id = it.command as u32;
            self.text(
                MavSeverity::MAV_SEVERITY_WARNING,
                &format!("Skipping invalid cmd #{id}"),
            );
        }
        self.broadcast_mission_current();
    }

    fn verify_nav(&mut self) {
        let seq = self.exec.current;
        let Some(it) = self.mission.get(usize::from(seq)).cloned() else {
            return;
        };
        let done = match it.command {
            MavCmd::MAV_CMD_NAV_WAYPOINT | MavCmd::MAV_CMD_NAV_LOITER_TIME => {
                self.verify_reach_and_wait(seq, &it, false)
            }
            MavCmd::MAV_CMD_NAV_LOITER_UNLIM => {
                self.verify_reach_and_wait(seq, &it, true);
                false
            }
            MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH => self.at(&Vector2::zeros(), 0.0),
            MavCmd::MAV_CMD_NAV_DELAY => {
                if self.exec.hold_until_ms == 0 {
                    self.exec.hold_until_ms = later(self.now_ms, f64::from(it.p[0]));
                }
                self.now_ms >= self.exec.hold_until_ms
            }
            _ => true,
        };
        if done {
            if it.command == MavCmd::MAV_CMD_NAV_LOITER_TIME {
                self.text(MavSeverity::MAV_SEVERITY_WARNING, "Finished active loiter");
            }
            self.item_reached(seq);
            self.exec.nav_loaded = false;
            self.exec.do_queue.clear();
            // The DO commands of this NAV ran while it ran; those left are skipped, as
            // AP_Mission does.
            match self.next_nav_after(seq) {
                Some(next) => self.exec.current = next,
                None => self.complete_mission(),
            }
        }
    }

    fn verify_reach_and_wait(&mut self, seq: u16, it: &Item, unlimited: bool) -> bool {
        let (pos, depth) = self.item_position(it);
        if !self.exec.reached {
            if !self.at(&pos, depth) {
                return false;
            }
            self.exec.reached = true;
            let wait_s = it.p[0].max(0.0);
            self.exec.hold_until_ms = later(self.now_ms, f64::from(wait_s));
            let text = if unlimited {
                format!("Reached waypoint #{seq}. Loiter unlimited")
            } else if wait_s > 0.0 {
                format!(
                    "Reached waypoint #{seq}. Loiter for {} seconds",
                    wait_s as u32
                )
            } else {
                format!("Reached waypoint #{seq}")
            };
            self.text(MavSeverity::MAV_SEVERITY_INFO, &text);
        }
        self.now_ms >= self.exec.hold_until_ms
    }

    /// The depth a target's altitude `z` means: an AUV's below the surface, a copter's above home
    /// (negative depth), a rover's none.
    pub(super) fn depth_of(&self, z: f32) -> f64 {
        match self.vehicle {
            VehicleKind::Auv if z < 0.0 => f64::from(-z),
            VehicleKind::Copter => -f64::from(z.max(0.0)),
            _ => 0.0,
        }
    }

    fn at(&self, pos: &Vector2<f64>, depth: f64) -> bool {
        (self.kin.pos - pos).norm() <= self.params.wp_radius_m
            && (self.vehicle == VehicleKind::Rover || (self.kin.depth - depth).abs() <= 1.0)
    }

    fn item_reached(&mut self, seq: u16) {
        self.send(
            Dest::All,
            MavMessage::MISSION_ITEM_REACHED(MISSION_ITEM_REACHED_DATA { seq }),
        );
        self.emit_event(EventKind::WaypointReached, i64::from(seq));
    }

    fn complete_mission(&mut self) {
        self.exec.complete = true;
        self.exec.nav_loaded = false;
        self.exec.current = (self.mission.len() as u16).saturating_sub(1);
        self.text(MavSeverity::MAV_SEVERITY_NOTICE, "Mission Complete");
        self.broadcast_mission_current();
    }

    fn run_do(&mut self, seq: u16, it: &Item) {
        match it.command {
            MavCmd::MAV_CMD_DO_CHANGE_SPEED => {
                if self.change_speed(f64::from(it.p[1])) {
                    self.text(
                        MavSeverity::MAV_SEVERITY_INFO,
                        &format!("speed: {:.1} m/s", it.p[1]),
                    );
                }
                self.item_reached(seq);
            }
            MavCmd::MAV_CMD_DO_SET_SERVO => {
                self.set_servo(it.p[0] as u8, it.p[1] as u16);
            }
            MavCmd::MAV_CMD_IMAGE_START_CAPTURE => {
                // A mission has no one to answer.
                let _ = self.image_start_capture(it.p[0], it.p[1], it.p[2]);
            }
            MavCmd::MAV_CMD_DO_DIGICAM_CONTROL => self.digicam_control(it.param5),
            other => {
                let id = other as u32;
                self.text(
                    MavSeverity::MAV_SEVERITY_WARNING,
                    &format!("Skipping invalid cmd #{id}"),
                );
            }
        }
    }

    /// Where the current mode wants the vehicle, if anywhere.
    pub(super) fn nav_target(&self) -> Option<Target> {
        if !self.armed || self.nav_blocked() || self.battery.pct <= 0.0 {
            return None;
        }
        let speed = self.speed_override.unwrap_or(self.params.speed_mps);
        if self.is_copter() {
            if let Some(decided) = self.copter_target(speed) {
                return decided;
            }
        }
        match self.mode {
            Mode::Auto if self.exec.started && !self.exec.complete && self.exec.nav_loaded => {
                let it = self.mission.get(usize::from(self.exec.current))?;
                let (pos, depth) = match it.command {
                    MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH => (Vector2::zeros(), 0.0),
                    MavCmd::MAV_CMD_NAV_DELAY => return None,
                    MavCmd::MAV_CMD_NAV_WAYPOINT
                    | MavCmd::MAV_CMD_NAV_LOITER_TIME
                    | MavCmd::MAV_CMD_NAV_LOITER_UNLIM => self.item_position(it),
                    _ => return None,
                };
                let pass_through = it.command == MavCmd::MAV_CMD_NAV_WAYPOINT
                    && it.p[0] <= 0.0
                    && self
                        .next_nav_after(self.exec.current)
                        .and_then(|n| self.mission.get(usize::from(n)))
                        .is_some_and(|n| n.command == MavCmd::MAV_CMD_NAV_WAYPOINT);
                Some(Target {
                    pos,
                    depth,
                    speed,
                    stop: !pass_through,
                })
            }
            Mode::Rtl => Some(Target {
                pos: Vector2::zeros(),
                depth: 0.0,
                speed,
                stop: true,
            }),
            Mode::Guided => self.guided_target.map(|mut t| {
                t.speed = if t.speed > 0.0 { t.speed } else { speed };
                t
            }),
            _ => None,
        }
    }

    /// RTL's arrival notice (once per RTL).
    pub(super) fn step_rtl(&mut self) {
        if self.mode == Mode::Rtl
            && self.armed
            && !self.rtl_reported
            && self.at(&Vector2::zeros(), 0.0)
        {
            self.rtl_reported = true;
            self.text(MavSeverity::MAV_SEVERITY_INFO, "Reached destination");
        }
    }

    pub(super) fn emit_event(&mut self, kind: EventKind, value: i64) {
        let at_m = [self.kin.pos.y, self.kin.pos.x];
        self.events.push(SimEvent { kind, value, at_m });
    }
}
