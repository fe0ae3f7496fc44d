//! Observed state: what telemetry says the vehicle is (moving or still, armed, in which mode), fed to the
//! plan's state variables that the configuration's `[state]` names. A move that fails (a foreign HOLD, an
//! autopilot error) did not end as the plan expected, so its end effects did not happen: without these
//! values the plan would keep the vehicle "moving" with no task able to make it still again. No domain
//! name is in code: `[state]` says which attribute and which values (checked against the domain at load).

use std::collections::BTreeMap;

use serde::Deserialize;

use super::config::Modes;
use super::telemetry::Telemetry;
use super::types::StateValue;

/// `[state]`.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ObservedState {
    /// Ground speed under which the vehicle is still, m/s.
    #[serde(default = "d_still_below")]
    pub still_below_m_s: f64,
    /// How long (vehicle ms) a failed motion waits for the vehicle to be still before it is reported.
    #[serde(default = "d_settle_ms")]
    pub settle_ms: u64,
    /// Moving or still (VFR_HUD ground speed, else GLOBAL_POSITION_INT's velocity).
    pub moving: Option<Flag>,
    /// A motion whose end a later action holds still (the domain: a `hold` on `moving`'s attribute at its
    /// still value, e.g. a picture) ends once the vehicle is within its radius and still, not as it enters
    /// the radius (src/executive/src/exec/still.rs). Default true.
    #[serde(default = "d_end_still")]
    pub end_still: bool,
    /// Armed or not (HEARTBEAT base_mode).
    pub armed: Option<Flag>,
    /// The flight mode (HEARTBEAT custom_mode, named as in `[modes]`).
    pub mode: Option<ModeValues>,
}

impl Default for ObservedState {
    fn default() -> Self {
        ObservedState {
            still_below_m_s: d_still_below(),
            settle_ms: d_settle_ms(),
            moving: None,
            end_still: d_end_still(),
            armed: None,
            mode: None,
        }
    }
}

fn d_still_below() -> f64 {
    0.2
}
fn d_end_still() -> bool {
    true
}
fn d_settle_ms() -> u64 {
    5_000
}

/// A two-valued observation on an attribute without parameters: its value when true and when false.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Flag {
    pub attribute: String,
    pub yes: String,
    pub no: String,
}

/// The mode on an attribute without parameters: the value of each mode of `[modes]` (by its key: `hold`,
/// `auto`, `guided`, `rtl`, `manual`); a mode not listed is not reported.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ModeValues {
    pub attribute: String,
    pub values: BTreeMap<String, String>,
}

/// The keys of `[modes]` a `[state.mode]` value may name.
pub const MODE_KEYS: [&str; 5] = ["hold", "auto", "guided", "rtl", "manual"];

impl ObservedState {
    /// Every attribute and value the configuration names, with its key (for the check against a domain).
    pub fn named(&self) -> Vec<(String, &str, Vec<&str>)> {
        let mut v = Vec::new();
        for (key, flag) in [("moving", &self.moving), ("armed", &self.armed)] {
            if let Some(f) = flag {
                v.push((
                    format!("state.{key}"),
                    f.attribute.as_str(),
                    vec![f.yes.as_str(), f.no.as_str()],
                ));
            }
        }
        if let Some(m) = &self.mode {
            v.push((
                "state.mode".to_string(),
                m.attribute.as_str(),
                m.values.values().map(String::as_str).collect(),
            ));
        }
        v
    }

    /// Whether the vehicle is moving, when telemetry tells its speed.
    pub fn is_moving(&self, tel: &Telemetry) -> Option<bool> {
        tel.ground_speed.map(|s| s > self.still_below_m_s)
    }

    /// The observed values, as a report's state variables (attribute name → value). `with_moving`: the
    /// moving/still value too (a failed motion, once settled; an interrupted one ended as preempted).
    pub fn values(
        &self,
        tel: &Telemetry,
        modes: &Modes,
        with_moving: bool,
    ) -> Vec<(String, StateValue)> {
        let mut v = Vec::new();
        let flag = |f: &Flag, on: bool| {
            let value = if on { &f.yes } else { &f.no };
            (f.attribute.clone(), StateValue::Symbol(value.clone()))
        };
        if let (true, Some(f), Some(moving)) = (with_moving, &self.moving, self.is_moving(tel)) {
            v.push(flag(f, moving));
        }
        if let Some(f) = &self.armed {
            v.push(flag(f, tel.armed));
        }
        if let (Some(m), Some(custom)) = (&self.mode, tel.custom_mode) {
            let named = modes
                .by_key()
                .into_iter()
                .find(|(_, mode)| mode.custom_mode() == custom)
                .and_then(|(key, _)| m.values.get(key));
            if let Some(value) = named {
                v.push((m.attribute.clone(), StateValue::Symbol(value.clone())));
            }
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::tests::rover_modes as modes;

    fn state() -> ObservedState {
        ObservedState {
            moving: Some(Flag {
                attribute: "STATUS".into(),
                yes: "MOVING".into(),
                no: "STILL".into(),
            }),
            mode: Some(ModeValues {
                attribute: "MODE".into(),
                values: [("hold".to_string(), "HELD".to_string())].into(),
            }),
            ..ObservedState::default()
        }
    }

    #[test]
    fn speed_under_the_threshold_is_still_and_named_modes_are_reported() {
        let mut tel = Telemetry::default();
        tel.ground_speed = Some(0.05);
        tel.custom_mode = Some(4);
        let v = state().values(&tel, &modes(), true);
        assert_eq!(
            v,
            vec![
                ("STATUS".into(), StateValue::Symbol("STILL".into())),
                ("MODE".into(), StateValue::Symbol("HELD".into())),
            ]
        );
        tel.ground_speed = Some(0.4);
        tel.custom_mode = Some(15); // GUIDED: not listed, not reported
        let v = state().values(&tel, &modes(), true);
        assert_eq!(
            v,
            vec![("STATUS".into(), StateValue::Symbol("MOVING".into()))]
        );
        assert!(state().values(&tel, &modes(), false).is_empty());
    }

    #[test]
    fn an_unknown_speed_reports_nothing() {
        let tel = Telemetry::default();
        assert!(state().values(&tel, &modes(), true).is_empty());
    }
}
