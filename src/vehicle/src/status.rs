//! What an operator sees of the vehicle at a glance (the live page): its mode, whether it is armed, its
//! battery and the state of the link, read from the telemetry the driver keeps.

use std::sync::Arc;
use std::time::Duration;

use serde::{Deserialize, Serialize};

/// The vehicle as last heard.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct VehicleStatus {
    /// The autopilot's mode by name (`GUIDED`, `HOLD`, …); `None` before its first HEARTBEAT.
    pub mode: Option<String>,
    pub armed: bool,
    /// Battery remaining, %.
    pub battery_percent: Option<f64>,
    /// `up`, `waiting for the first heartbeat`, or `lost: no heartbeat for N s`.
    pub link: String,
}

/// Reads the vehicle's status now (never blocks: the last status when the driver is busy).
pub type StatusProbe = Arc<dyn Fn() -> VehicleStatus + Send + Sync>;

/// The link's state from the time since the last HEARTBEAT (`None`: none yet) and the link timeout.
pub fn link_state(silence: Option<Duration>, timeout: Duration) -> String {
    match silence {
        None => "waiting for the first heartbeat".into(),
        Some(s) if s >= timeout => format!("lost: no heartbeat for {} s", s.as_secs()),
        Some(_) => "up".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_link_is_lost_past_its_timeout() {
        let t = Duration::from_secs(3);
        assert_eq!(link_state(None, t), "waiting for the first heartbeat");
        assert_eq!(link_state(Some(Duration::from_millis(900)), t), "up");
        assert_eq!(
            link_state(Some(Duration::from_secs(7)), t),
            "lost: no heartbeat for 7 s"
        );
    }
}
