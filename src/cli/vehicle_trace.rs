//! The vehicle in `run`'s trace (issue 30): a line when its mode, its arming or its link changes, with the
//! battery, e.g. `[  12.0 s] vehicle: mode HOLD, armed, battery 81 %, link up`.

use crate::model::Time;
use crate::vehicle::status::{StatusProbe, VehicleStatus};

/// The status line: mode, arming, battery, link.
pub fn status_line(s: &VehicleStatus) -> String {
    let battery = s
        .battery_percent
        .map_or("battery unknown".to_string(), |b| {
            format!("battery {b:.0} %")
        });
    format!(
        "mode {}, {}, {battery}, link {}",
        s.mode.as_deref().unwrap_or("unknown"),
        if s.armed { "armed" } else { "disarmed" },
        s.link
    )
}

/// What is compared between cycles: the mode, the arming, the link's state (`up`, `lost`, … without the
/// seconds, which move every second).
type Key = (Option<String>, bool, String);

fn key(s: &VehicleStatus) -> Key {
    let link = s.link.split(':').next().unwrap_or("").to_string();
    (s.mode.clone(), s.armed, link)
}

/// Tells the vehicle's changes, cycle by cycle.
pub struct VehicleTrace {
    probe: StatusProbe,
    last: Option<Key>,
}

impl VehicleTrace {
    pub fn new(probe: StatusProbe) -> Self {
        Self { probe, last: None }
    }

    /// The trace line at mission time `t_ms` when the vehicle changed since the last one.
    pub fn line(&mut self, t_ms: Time) -> Option<String> {
        let s = (self.probe)();
        let k = key(&s);
        if self.last.as_ref() == Some(&k) {
            return None;
        }
        self.last = Some(k);
        Some(format!(
            "[{:>8.1} s] vehicle: {}",
            t_ms as f64 / 1000.0,
            status_line(&s)
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    #[test]
    fn a_line_when_mode_arming_or_link_change_not_for_the_battery_alone() {
        let now = Arc::new(Mutex::new(VehicleStatus {
            mode: Some("GUIDED".into()),
            armed: true,
            battery_percent: Some(81.0),
            link: "up".into(),
        }));
        let shared = now.clone();
        let mut t = VehicleTrace::new(Arc::new(move || {
            shared.lock().map(|s| s.clone()).unwrap_or_default()
        }));
        assert_eq!(
            t.line(12_000).as_deref(),
            Some("[    12.0 s] vehicle: mode GUIDED, armed, battery 81 %, link up")
        );
        let set = |f: &dyn Fn(&mut VehicleStatus)| {
            if let Ok(mut s) = now.lock() {
                f(&mut s);
            }
        };
        set(&|s| s.battery_percent = Some(80.0));
        assert_eq!(t.line(13_000), None);
        set(&|s| s.mode = Some("HOLD".into()));
        assert!(t.line(14_000).is_some_and(|l| l.contains("mode HOLD")));
        set(&|s| s.link = "lost: no heartbeat for 3 s".into());
        assert!(t
            .line(15_000)
            .is_some_and(|l| l.ends_with("link lost: no heartbeat for 3 s")));
        set(&|s| s.link = "lost: no heartbeat for 4 s".into());
        assert_eq!(t.line(16_000), None);
    }
}
