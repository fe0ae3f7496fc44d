//! The autopilot's own fence, read at readiness: the fence list over the mission protocol
//! (`mission_type` = FENCE: polygon vertices 5001/5002 with param1 = their count, circles 5003/5004 with
//! param1 = the radius, the return point 5000 — ArduPilot's AC_PolyFence_loader and PX4's geofence alike)
//! and ArduPilot's FENCE_ENABLE / FENCE_TYPE / FENCE_RADIUS (bit 2 of FENCE_TYPE: a circle of FENCE_RADIUS
//! around home; bit 4: the fence list), read with PARAM_REQUEST_READ. An autopilot without the
//! parameters (PX4) does not answer: after the retries they are absent and the list alone counts. Pure:
//! the driver feeds it.

use mavlink::dialects::ardupilotmega::{MavMessage, PARAM_REQUEST_READ_DATA};
use serde::Serialize;

use super::items::MissionItem;
use super::limits::{Limits, AUTOPILOT_FENCE};

/// The parameters read, in order.
pub const PARAMS: [&str; 3] = ["FENCE_ENABLE", "FENCE_TYPE", "FENCE_RADIUS"];
/// Vehicle ms between two requests of an unanswered parameter, and the requests made.
const RETRY_MS: u64 = 1_000;
const TRIES: u32 = 3;
/// FENCE_TYPE bits (AC_Fence): the circle around home, the polygons and circles of the list.
const TYPE_CIRCLE: u32 = 2;
const TYPE_POLYGON: u32 = 4;

/// What the autopilot says of its fence.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct AutopilotFence {
    /// FENCE_ENABLE, FENCE_TYPE, FENCE_RADIUS; `None`: the autopilot has no such parameter.
    pub enable: Option<f32>,
    pub fence_type: Option<f32>,
    pub radius_m: Option<f32>,
    /// The fence list.
    #[serde(skip)]
    pub items: Vec<MissionItem>,
    /// Why the list could not be read, if it could not.
    pub download_error: Option<String>,
    /// The autopilot's home (HOME_POSITION), the centre of its FENCE_RADIUS circle; else the
    /// configuration's.
    pub home: Option<(f64, f64)>,
}

impl AutopilotFence {
    /// Adds what the autopilot enforces to `limits`; a line saying what was taken, for the log.
    pub fn apply(&self, limits: &mut Limits) -> String {
        if self.enable == Some(0.0) {
            return "the autopilot's fence is disabled (FENCE_ENABLE = 0): not used".into();
        }
        let bits = self.fence_type.map(|t| t as u32);
        let mut taken = Vec::new();
        if let (Some(b), Some(r)) = (bits, self.radius_m) {
            if b & TYPE_CIRCLE != 0 && r > 0.0 {
                let h = limits.home();
                let (lat, lon) = self.home.unwrap_or((h.lat, h.lon));
                limits.add_disc(AUTOPILOT_FENCE, true, lat, lon, f64::from(r));
                taken.push(format!("a {r:.0} m circle around home"));
            }
        }
        if bits.is_none_or(|b| b & TYPE_POLYGON != 0) {
            let (polygons, circles, skipped) = self.zones(limits);
            if polygons > 0 {
                taken.push(format!("{polygons} polygon(s)"));
            }
            if circles > 0 {
                taken.push(format!("{circles} circle(s)"));
            }
            if skipped > 0 {
                taken.push(format!("{skipped} malformed item(s) skipped"));
            }
        }
        if taken.is_empty() {
            "the autopilot has no fence".into()
        } else {
            format!("the autopilot's fence: {}", taken.join(", "))
        }
    }

    /// Adds the list's polygons and circles; (polygons, circles, items skipped).
    fn zones(&self, limits: &mut Limits) -> (usize, usize, usize) {
        let (mut polygons, mut circles, mut skipped) = (0, 0, 0);
        let mut i = 0;
        while i < self.items.len() {
            let it = &self.items[i];
            match it.command {
                5001 | 5002 => {
                    let n = it.params[0] as usize;
                    let run: Vec<[f64; 2]> = self.items[i..]
                        .iter()
                        .take(n)
                        .take_while(|v| v.command == it.command)
                        .map(|v| [v.x, v.y])
                        .collect();
                    if n >= 3 && run.len() == n {
                        limits.add_area(AUTOPILOT_FENCE, it.command == 5001, &run);
                        polygons += 1;
                        i += n;
                    } else {
                        skipped += run.len().max(1);
                        i += run.len().max(1);
                    }
                }
                5003 | 5004 if it.params[0] > 0.0 => {
                    let r = f64::from(it.params[0]);
                    limits.add_disc(AUTOPILOT_FENCE, it.command == 5003, it.x, it.y, r);
                    circles += 1;
                    i += 1;
                }
                // The return point (5000) is where the autopilot goes on a breach, no limit.
                5000 => i += 1,
                _ => {
                    skipped += 1;
                    i += 1;
                }
            }
        }
        (polygons, circles, skipped)
    }
}

/// The vehicle's limits: the configuration's `[limits]` and what the autopilot's fence adds; with the line
/// saying what the fence added (for the log and the operator), when it was read.
pub fn limits_for(
    cfg: &super::limits::LimitsConfig,
    home: super::geo::Home,
    fence: Option<&AutopilotFence>,
) -> (Option<Limits>, Option<String>) {
    let mut limits = Limits::from_config(cfg, home).unwrap_or_else(|| Limits::none(home));
    let said = fence.map(|f| f.apply(&mut limits));
    ((!limits.is_empty()).then_some(limits), said)
}

/// The reading under way.
#[derive(Debug, Clone)]
pub struct FenceRead {
    fence: AutopilotFence,
    /// Per parameter: answered (or given up on: no answer a retry period after the last request), the
    /// requests made and when the last went out (vehicle ms).
    asked: [(bool, u32, u64); 3],
    list_done: bool,
}

impl Default for FenceRead {
    fn default() -> Self {
        Self::new()
    }
}

impl FenceRead {
    pub fn new() -> Self {
        FenceRead {
            fence: AutopilotFence::default(),
            asked: [(false, 0, 0); 3],
            list_done: false,
        }
    }

    /// Every parameter answered or given up on, and the list read (or failed).
    pub fn done(&self) -> bool {
        self.list_done && self.asked.iter().all(|&(settled, _, _)| settled)
    }

    pub fn fence(&self) -> &AutopilotFence {
        &self.fence
    }

    /// The parameter requests due at `vnow`.
    pub fn tick(&mut self, vnow: u64, target: (u8, u8), out: &mut Vec<MavMessage>) {
        for (i, a) in self.asked.iter_mut().enumerate() {
            let (settled, tries, last) = *a;
            if settled || (tries > 0 && vnow.saturating_sub(last) < RETRY_MS) {
                continue;
            }
            if tries >= TRIES {
                // The autopilot has no such parameter (PX4): absent.
                a.0 = true;
                continue;
            }
            *a = (false, tries + 1, vnow);
            out.push(MavMessage::PARAM_REQUEST_READ(PARAM_REQUEST_READ_DATA {
                param_index: -1,
                target_system: target.0,
                target_component: target.1,
                param_id: PARAMS[i].into(),
            }));
        }
    }

    /// A message from the autopilot: a PARAM_VALUE of one of ours.
    pub fn on_message(&mut self, msg: &MavMessage) {
        let MavMessage::PARAM_VALUE(v) = msg else {
            return;
        };
        let name = v.param_id.to_str().unwrap_or("").trim_end_matches('\0');
        let Some(i) = PARAMS.iter().position(|p| *p == name) else {
            return;
        };
        self.asked[i].0 = true;
        // (A late answer after giving up still counts.)
        let slot = match i {
            0 => &mut self.fence.enable,
            1 => &mut self.fence.fence_type,
            _ => &mut self.fence.radius_m,
        };
        *slot = Some(v.param_value);
    }

    /// The fence list downloaded, or why not.
    pub fn on_list(&mut self, list: Result<Vec<MissionItem>, String>) {
        match list {
            Ok(items) => self.fence.items = items,
            Err(e) => self.fence.download_error = Some(e),
        }
        self.list_done = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::limits::tests::HOME;
    use crate::types::Enu;
    use mavlink::dialects::ardupilotmega::{MavParamType, PARAM_VALUE_DATA};

    fn vertex(command: u16, n: f32, e: f64, north: f64) -> MissionItem {
        let (lat, lon, _) = HOME.to_global(Enu::new(e, north, 0.0));
        let mut it = MissionItem::waypoint(lat, lon, 0.0);
        it.command = command;
        it.params[0] = n;
        it
    }

    fn value(name: &str, v: f32) -> MavMessage {
        MavMessage::PARAM_VALUE(PARAM_VALUE_DATA {
            param_value: v,
            param_count: 3,
            param_index: 0,
            param_id: name.into(),
            param_type: MavParamType::MAV_PARAM_TYPE_REAL32,
        })
    }

    #[test]
    fn parameters_unanswered_are_given_up_after_their_retries() {
        let mut r = FenceRead::new();
        let mut out = Vec::new();
        r.tick(0, (1, 1), &mut out);
        assert_eq!(out.len(), 3);
        r.on_message(&value("FENCE_ENABLE", 1.0));
        r.on_list(Ok(Vec::new()));
        r.tick(500, (1, 1), &mut out);
        assert_eq!(out.len(), 3, "not yet due");
        r.tick(1_000, (1, 1), &mut out);
        r.tick(2_000, (1, 1), &mut out);
        assert!(!r.done());
        assert_eq!(out.len(), 7);
        r.tick(3_000, (1, 1), &mut out);
        assert!(r.done(), "FENCE_TYPE and FENCE_RADIUS absent (a PX4)");
        assert_eq!(r.fence().enable, Some(1.0));
        assert_eq!(r.fence().radius_m, None);
    }

    #[test]
    fn an_enabled_fence_adds_its_circle_polygons_and_exclusions() {
        let mut r = FenceRead::new();
        for (n, v) in [
            ("FENCE_ENABLE", 1.0),
            ("FENCE_TYPE", 6.0),
            ("FENCE_RADIUS", 100.0),
        ] {
            r.on_message(&value(n, v));
        }
        r.on_list(Ok(vec![
            vertex(5000, 0.0, 0.0, 0.0),
            vertex(5002, 3.0, 10.0, 10.0),
            vertex(5002, 3.0, 20.0, 10.0),
            vertex(5002, 3.0, 10.0, 20.0),
            vertex(5004, 4.0, -20.0, 0.0),
        ]));
        let mut l = Limits::none(HOME);
        let said = r.fence().apply(&mut l);
        assert_eq!(
            said,
            "the autopilot's fence: a 100 m circle around home, 1 polygon(s), 1 circle(s)"
        );
        assert!(l.check_local(Enu::new(120.0, 0.0, 0.0)).is_err());
        assert!(l.check_local(Enu::new(13.0, 13.0, 0.0)).is_err());
        assert!(l.check_local(Enu::new(-21.0, 0.0, 0.0)).is_err());
        assert_eq!(l.check_local(Enu::new(40.0, 40.0, 0.0)), Ok(()));
        // The circle is around the autopilot's own home when it told it (HOME_POSITION).
        let (lat, lon, _) = HOME.to_global(Enu::new(0.0, 150.0, 0.0));
        let moved = AutopilotFence {
            home: Some((lat, lon)),
            items: Vec::new(),
            ..r.fence().clone()
        };
        let mut l = Limits::none(HOME);
        moved.apply(&mut l);
        assert_eq!(l.check_local(Enu::new(0.0, 200.0, 0.0)), Ok(()));
        assert!(l.check_local(Enu::new(0.0, 0.0, 0.0)).is_err());
        // Disabled: nothing is taken.
        r.on_message(&value("FENCE_ENABLE", 0.0));
        let mut l = Limits::none(HOME);
        assert!(r.fence().apply(&mut l).contains("disabled"));
        assert!(l.is_empty());
    }
}
