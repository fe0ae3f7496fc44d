//! `[actions.<task>]` as written: one flat table of every binding key, so that a type error keeps its line
//! (serde's internally tagged enums buffer the table and lose every span), then turned into a [`Binding`]
//! of its `kind`, a key that does not belong to that kind being an error on that key.

use serde::Deserialize;

use super::config::{Binding, ServoStep};
use super::flight::FlightBinding;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BindingKind {
    Move,
    Survey,
    TakePicture,
    Sample,
    ReturnHome,
    Recharge,
    Download,
    Timed,
    Takeoff,
    FlyTo,
    Land,
    ReturnLand,
}

/// Declares the table's keys once: the struct and the list of the keys written come from the same list, so a
/// new key cannot be forgotten in the check of the keys a kind allows.
macro_rules! binding_table {
    ($($key:ident: $ty:ty,)*) => {
        #[derive(Debug, Clone, Default, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct BindingTable {
            kind: Option<BindingKind>,
            $($key: Option<$ty>,)*
        }

        impl BindingTable {
            /// The keys written in the table, `kind` aside.
            fn written(&self) -> Vec<&'static str> {
                let mut keys = Vec::new();
                $(if self.$key.is_some() {
                    keys.push(stringify!($key));
                })*
                keys
            }
        }
    };
}

binding_table! {
    to: String,
    area: String,
    acceptance_radius_m: f64,
    speed_m_s: f64,
    position_variable: String,
    vertical_acceptance_m: f64,
    width_m: f64,
    height_m: f64,
    spacing_m: f64,
    camera_id: u8,
    timeout_ms: u64,
    steps: Vec<ServoStep>,
    until_percent: f64,
    level_arg: String,
    command: u16,
    until_used: f64,
    max_ms: u64,
    poll_ms: u64,
    duration_ms: u64,
    altitude_m: f64,
}

/// What is wrong with a table: the key it is about (relative to the table, empty for the table itself).
pub type TableError = (&'static str, String);

impl BindingTable {
    /// The binding, or the first key that is missing, or set but not of this kind.
    pub fn into_binding(self) -> Result<Binding, TableError> {
        let kind = self.kind.ok_or(("", "missing key `kind`".to_string()))?;
        let keys = self.written();
        let allowed: &[&str] = match kind {
            BindingKind::Move => &[
                "to",
                "acceptance_radius_m",
                "speed_m_s",
                "position_variable",
                "vertical_acceptance_m",
            ],
            BindingKind::Survey => &[
                "area",
                "width_m",
                "height_m",
                "spacing_m",
                "position_variable",
            ],
            BindingKind::TakePicture => &["camera_id", "timeout_ms"],
            BindingKind::Sample => &["steps"],
            BindingKind::ReturnHome => &["acceptance_radius_m", "position_variable"],
            BindingKind::Recharge => &["until_percent", "level_arg"],
            BindingKind::Download => &["command", "until_used", "max_ms", "poll_ms"],
            BindingKind::Timed => &["duration_ms"],
            BindingKind::Takeoff => &["altitude_m", "vertical_acceptance_m"],
            BindingKind::FlyTo => &[
                "to",
                "acceptance_radius_m",
                "vertical_acceptance_m",
                "speed_m_s",
                "position_variable",
            ],
            BindingKind::Land | BindingKind::ReturnLand => {
                &["acceptance_radius_m", "position_variable"]
            }
        };
        if let Some(k) = keys.iter().find(|k| !allowed.contains(k)) {
            return Err((
                k,
                format!(
                    "not a key of kind {kind:?} (its keys: {})",
                    allowed.join(", ")
                ),
            ));
        }
        let position = || {
            self.position_variable
                .clone()
                .unwrap_or_else(|| "position".into())
        };
        let radius = self.acceptance_radius_m.unwrap_or(3.0);
        Ok(match kind {
            BindingKind::Move => Binding::Move {
                to: self.to.clone().unwrap_or_else(|| "to".into()),
                acceptance_radius_m: radius,
                // Negative: the autopilot's own speed.
                speed_m_s: self.speed_m_s.unwrap_or(-1.0),
                position_variable: position(),
                vertical_acceptance_m: self.vertical_acceptance_m,
            },
            BindingKind::Survey => Binding::Survey {
                area: self.area.clone().unwrap_or_else(|| "area".into()),
                width_m: need(self.width_m, "width_m", kind)?,
                height_m: need(self.height_m, "height_m", kind)?,
                spacing_m: need(self.spacing_m, "spacing_m", kind)?,
                position_variable: position(),
            },
            BindingKind::TakePicture => Binding::TakePicture {
                camera_id: self.camera_id.unwrap_or(0),
                timeout_ms: self.timeout_ms.unwrap_or(10_000),
            },
            BindingKind::Sample => Binding::Sample {
                steps: need(self.steps.clone(), "steps", kind)?,
            },
            BindingKind::ReturnHome => Binding::ReturnHome {
                acceptance_radius_m: radius,
                position_variable: position(),
            },
            BindingKind::Recharge => Binding::Recharge {
                until_percent: need(self.until_percent, "until_percent", kind)?,
                level_arg: self.level_arg.clone(),
            },
            BindingKind::Download => Binding::Download {
                command: need(self.command, "command", kind)?,
                until_used: self.until_used.unwrap_or(0.0),
                max_ms: self.max_ms,
                poll_ms: self.poll_ms.unwrap_or(1000),
            },
            BindingKind::Timed => Binding::Timed {
                duration_ms: need(self.duration_ms, "duration_ms", kind)?,
            },
            BindingKind::Takeoff => Binding::Flight(FlightBinding::Takeoff {
                altitude_m: need(self.altitude_m, "altitude_m", kind)?,
                vertical_acceptance_m: self.vertical_acceptance_m.unwrap_or(1.0),
            }),
            BindingKind::FlyTo => Binding::Flight(FlightBinding::FlyTo {
                to: self.to.clone().unwrap_or_else(|| "to".into()),
                acceptance_radius_m: radius,
                vertical_acceptance_m: self.vertical_acceptance_m.unwrap_or(1.0),
                speed_m_s: self.speed_m_s.unwrap_or(-1.0),
                position_variable: position(),
            }),
            BindingKind::Land | BindingKind::ReturnLand => Binding::Flight(FlightBinding::Land {
                home: kind == BindingKind::ReturnLand,
                acceptance_radius_m: radius,
                position_variable: position(),
            }),
        })
    }
}

/// A required key's value, or the error of its absence.
fn need<T>(v: Option<T>, key: &'static str, kind: BindingKind) -> Result<T, TableError> {
    v.ok_or(("", format!("missing key `{key}` (kind {kind:?})")))
}
