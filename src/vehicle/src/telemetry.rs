//! Telemetry → state: battery level (BATTERY_STATUS, else SYS_STATUS), storage level and capacity
//! (STORAGE_INFORMATION), position (GLOBAL_POSITION_INT → local ENU), mode and arming (HEARTBEAT), and the
//! vehicle's clock (SYSTEM_TIME / time_boot_ms).

use mavlink::dialects::ardupilotmega::{EkfStatusFlags, MavMessage, MavModeFlag, MavType};

use super::api::VehicleEvent;
use super::config::ResourceNames;
use super::geo::Home;
use super::types::{CapacityChange, Enu, ResourceLevel};

#[derive(Debug, Default, Clone)]
pub struct Telemetry {
    pub position: Option<Enu>,
    pub battery_percent: Option<f64>,
    /// Available storage (MiB): the storage resource level.
    pub storage_available: Option<f64>,
    pub storage_used: Option<f64>,
    pub storage_total: Option<f64>,
    pub time_boot_ms: Option<u64>,
    pub custom_mode: Option<u32>,
    /// The vehicle type the autopilot's HEARTBEAT reports (which mode table names its modes).
    pub vehicle_type: Option<MavType>,
    pub armed: bool,
    pub mission_current: Option<(u16, u16)>,
    /// The autopilot has a home (HOME_POSITION received): its position estimate is trusted.
    pub home_known: bool,
    /// The autopilot's home (latitude, longitude, degrees), as HOME_POSITION last gave it.
    pub home_position: Option<(f64, f64)>,
    /// The estimator trusts its horizontal position (EKF_STATUS_REPORT: absolute position, not in
    /// constant-position mode); `None` until an autopilot that has such a report sends it.
    pub navigation_ok: Option<bool>,
    /// PX4's pre-arm verdict (SYS_STATUS's PREARM_CHECK health bit, src/vehicle/src/px4.rs); the readiness
    /// wait only reads it from PX4.
    pub prearm_ok: Option<bool>,
    /// The image index of the camera's last CAMERA_FEEDBACK (ArduPilot's picture confirmation).
    pub camera_feedback_index: Option<u16>,
    /// Ground speed, m/s (VFR_HUD, else GLOBAL_POSITION_INT's velocity).
    pub ground_speed: Option<f64>,
    /// A flying vehicle's state: altitude above home and landed state (src/vehicle/src/flight.rs).
    pub flight: super::flight::FlightTelemetry,
    has_vfr_hud: bool,
    has_battery_status: bool,
    /// The autopilot's own time_boot_ms, last received.
    raw_boot_ms: Option<u64>,
    /// Added to the autopilot's time after a restart, so that `time_boot_ms` runs on.
    boot_offset_ms: u64,
    /// The autopilot restarted (its clock went back) and the driver has not yet dealt with it.
    restarted: bool,
    /// The last SYSTEM_TIME: UTC (us) and our clock then. After a restart, the UTC clock (GPS time, which
    /// a restart does not reset) tells how long the autopilot was silent, and our clock skips it too.
    last_utc: Option<(u64, u64)>,
    /// A restart whose silence is not yet accounted for (until the next SYSTEM_TIME).
    silence_unknown: bool,
}

impl Telemetry {
    /// Updates the state from an autopilot message; resource changes become events.
    pub fn update(
        &mut self,
        msg: &MavMessage,
        home: &Home,
        names: &ResourceNames,
        events: &mut Vec<VehicleEvent>,
    ) {
        if let Some(p) = super::px4::prearm_from(msg) {
            self.prearm_ok = Some(p);
        }
        self.flight.update(msg);
        match msg {
            MavMessage::HEARTBEAT(h) => {
                self.custom_mode = Some(h.custom_mode);
                self.vehicle_type = Some(h.mavtype);
                self.armed = h
                    .base_mode
                    .contains(MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED);
            }
            MavMessage::GLOBAL_POSITION_INT(p) => {
                self.clock(u64::from(p.time_boot_ms));
                if !self.has_vfr_hud {
                    let (vx, vy) = (f64::from(p.vx) / 100.0, f64::from(p.vy) / 100.0);
                    self.ground_speed = Some(vx.hypot(vy));
                }
                // (0, 0) until the GPS has a fix: never a position to plan from.
                if p.lat != 0 || p.lon != 0 {
                    self.position = Some(home.to_local(
                        f64::from(p.lat) * 1e-7,
                        f64::from(p.lon) * 1e-7,
                        f64::from(p.alt) * 1e-3,
                    ));
                }
            }
            MavMessage::SYSTEM_TIME(t) => {
                self.clock(u64::from(t.time_boot_ms));
                self.utc(t.time_unix_usec);
            }
            MavMessage::BATTERY_STATUS(b) if b.battery_remaining >= 0 => {
                self.has_battery_status = true;
                self.battery(f64::from(b.battery_remaining), names, events);
            }
            MavMessage::SYS_STATUS(s) if !self.has_battery_status && s.battery_remaining >= 0 => {
                self.battery(f64::from(s.battery_remaining), names, events);
            }
            MavMessage::STORAGE_INFORMATION(s) => {
                self.clock(u64::from(s.time_boot_ms));
                let total = super::wire_float::widen(s.total_capacity);
                if let (Some(old), Some(name)) = (self.storage_total, &names.storage) {
                    if (old - total).abs() > 1e-6 {
                        events.push(VehicleEvent::Capacity(CapacityChange {
                            resource: name.clone(),
                            capacity: total,
                            delta: total - old,
                        }));
                    }
                }
                self.storage_total = Some(total);
                self.storage_used = Some(super::wire_float::widen(s.used_capacity));
                let avail = super::wire_float::widen(s.available_capacity);
                if self.storage_available != Some(avail) {
                    self.storage_available = Some(avail);
                    if let Some(name) = &names.storage {
                        events.push(VehicleEvent::Resource(ResourceLevel {
                            resource: name.clone(),
                            level: avail,
                        }));
                    }
                }
            }
            MavMessage::MISSION_CURRENT(m) => self.mission_current = Some((m.seq, m.total)),
            MavMessage::EKF_STATUS_REPORT(e) => {
                let f = e.flags;
                self.navigation_ok = Some(
                    f.contains(EkfStatusFlags::EKF_POS_HORIZ_ABS)
                        && !f.contains(EkfStatusFlags::EKF_CONST_POS_MODE),
                );
            }
            // PX4's estimator report (it has no EKF_STATUS_REPORT): the same flags.
            MavMessage::ESTIMATOR_STATUS(_) => {
                self.navigation_ok = super::px4::navigation_from(msg)
            }
            MavMessage::HOME_POSITION(h) if h.latitude != 0 || h.longitude != 0 => {
                self.home_known = true;
                self.home_position = Some((
                    geodesy::e7_to_deg(h.latitude),
                    geodesy::e7_to_deg(h.longitude),
                ));
            }
            MavMessage::CAMERA_FEEDBACK(f) => self.camera_feedback_index = Some(f.img_idx),
            MavMessage::VFR_HUD(v) if v.groundspeed.is_finite() => {
                self.has_vfr_hud = true;
                self.ground_speed = Some(f64::from(v.groundspeed.abs()));
            }
            _ => {}
        }
    }

    fn clock(&mut self, ms: u64) {
        if self
            .raw_boot_ms
            .is_some_and(|raw| ms.saturating_add(super::commands::REBOOT_CLOCK_JUMP_MS) < raw)
        {
            // The autopilot restarted: its clock counts from 0 again; ours runs on from where it was.
            self.boot_offset_ms = self.time_boot_ms.unwrap_or(0).saturating_sub(ms);
            self.restarted = true;
            self.silence_unknown = true;
            tracing::warn!(
                time_boot_ms = ms,
                "the autopilot's clock went back: it restarted"
            );
        }
        if self.raw_boot_ms.is_none_or(|raw| ms > raw) || self.restarted {
            self.raw_boot_ms = Some(ms);
        }
        let ms = ms.saturating_add(self.boot_offset_ms);
        // Monotonic: a late message must not move the executive's clock back.
        if ms > 0 && self.time_boot_ms.is_none_or(|t| ms > t) {
            self.time_boot_ms = Some(ms);
        }
    }

    /// After a restart, moves our clock on by the silence the UTC clock shows (bounded by it: never back).
    fn utc(&mut self, utc_us: u64) {
        if utc_us == 0 {
            return;
        }
        if self.silence_unknown {
            if let (Some((u0, e0)), Some(now)) = (self.last_utc, self.time_boot_ms) {
                let est = e0.saturating_add(utc_us.saturating_sub(u0) / 1000);
                if est > now {
                    self.boot_offset_ms = self.boot_offset_ms.saturating_add(est - now);
                    self.time_boot_ms = Some(est);
                }
            }
            self.silence_unknown = false;
        }
        if let Some(now) = self.time_boot_ms {
            self.last_utc = Some((utc_us, now));
        }
    }

    /// A time_boot_ms the autopilot sent, on our clock (which runs on across its restarts).
    pub fn vehicle_time(&self, time_boot_ms: u32) -> u64 {
        u64::from(time_boot_ms).saturating_add(self.boot_offset_ms)
    }

    /// True once after the autopilot restarted (its clock went back).
    pub fn take_restart(&mut self) -> bool {
        std::mem::take(&mut self.restarted)
    }

    fn battery(&mut self, level: f64, names: &ResourceNames, events: &mut Vec<VehicleEvent>) {
        if self.battery_percent != Some(level) {
            self.battery_percent = Some(level);
            if let Some(name) = &names.battery {
                events.push(VehicleEvent::Resource(ResourceLevel {
                    resource: name.clone(),
                    level: names.battery_level(level),
                }));
            }
        }
    }

    /// The current levels of the known resources (the final levels a report carries).
    pub fn levels(&self, names: &ResourceNames) -> Vec<ResourceLevel> {
        let mut v = Vec::new();
        if let (Some(b), Some(name)) = (self.battery_percent, &names.battery) {
            v.push(ResourceLevel {
                resource: name.clone(),
                level: names.battery_level(b),
            });
        }
        if let (Some(s), Some(name)) = (self.storage_available, &names.storage) {
            v.push(ResourceLevel {
                resource: name.clone(),
                level: s,
            });
        }
        v
    }
}
