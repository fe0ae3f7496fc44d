//! Vehicle configuration (`config/*.toml`): link, identity, timeouts, flight modes and, for each domain task,
//! its action binding — how the task is realised in MAVLink and how its end is recognised — and the
//! `[mapping]` of the domain's names the executive needs (the position attribute, the location type, what an
//! uploaded goal item becomes). Typed serde with unknown keys rejected; errors name the file, the key and the
//! line. Whether the names match a domain is for the executive crate's `config_check` to say.

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;
use srctext::toml_file::KeyError;

use super::binding_table::BindingTable;
use super::geo::Home;
use super::safe_stop::OnShutdown;
use super::types::GoalKind;

/// A configuration that cannot be used: unreadable, or wrong at `file:line:col` (the line shown).
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    #[error("{0}")]
    Read(#[from] srctext::ReadError),
    #[error("{0}")]
    At(Box<srctext::Located>),
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleConfig {
    pub link: LinkConfig,
    pub home: Home,
    #[serde(default)]
    pub autopilot: Autopilot,
    pub modes: Modes,
    #[serde(default)]
    pub resources: ResourceNames,
    #[serde(default)]
    pub mapping: Mapping,
    /// What telemetry says of the vehicle's state, and the domain attributes it sets.
    #[serde(default)]
    pub state: super::observed::ObservedState,
    /// Waiting for the autopilot to be ready before the mission's first start.
    #[serde(default)]
    pub ready: ReadyConfig,
    /// Who commands the vehicle: yielding to the operator, arming, the end of a mission.
    #[serde(default)]
    pub authority: super::authority::AuthorityConfig,
    /// Where the vehicle may go: a range from home, a polygon (src/vehicle/src/limits.rs).
    #[serde(default)]
    pub limits: super::limits::LimitsConfig,
    /// Task name of the domain → binding (from `tables`, once parsed).
    #[serde(skip)]
    pub actions: BTreeMap<String, Binding>,
    /// `[actions.*]` as written (see [`super::binding_table`]).
    #[serde(default, rename = "actions")]
    tables: BTreeMap<String, BindingTable>,
    /// The executive's `[exec]` table, as written: the executive reads it from [`Self::source`] (for its
    /// lines in errors), this layer only knows the key is not unknown.
    pub exec: Option<toml::Table>,
    /// Where the configuration was read from (not a key of the file): for `file:line` in messages.
    #[serde(skip)]
    pub source: Option<ConfigSource>,
}

/// The text a configuration was parsed from and its name.
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigSource {
    /// The file name (or any name given to [`VehicleConfig::parse`]).
    pub origin: String,
    pub text: String,
}

impl ConfigSource {
    /// The 1-based line where the key path `key` (`actions.survey.area`) is written; when it is not written
    /// (a default, a missing binding), the line of the closest written table or key above it, if any.
    pub fn line_of(&self, key: &str) -> Option<usize> {
        let pos = srctext::toml_file::key_offset(&self.text, key)?;
        Some(srctext::locate(&self.origin, &self.text, pos, "").line)
    }
}

#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Autopilot {
    #[default]
    Ardupilot,
    Px4,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinkConfig {
    /// `udpin:`, `udpout:`, `tcpin:`, `tcpout:` or `serial:PORT:BAUD`.
    pub address: String,
    #[serde(default = "d_heartbeat_timeout")]
    pub heartbeat_timeout_ms: u64,
    #[serde(default = "d_ack_timeout")]
    pub command_ack_timeout_ms: u64,
    #[serde(default = "d_retries")]
    pub command_retries: u32,
    #[serde(default = "d_mission_timeout")]
    pub mission_timeout_ms: u64,
    #[serde(default = "d_retries")]
    pub mission_retries: u32,
    /// 64 hex digits; when set, outgoing frames are signed and unsigned incoming frames rejected.
    pub signing_key: Option<String>,
    #[serde(default)]
    pub signing_link_id: u8,
    /// Record every frame in and out to this `.tlog`.
    pub tlog: Option<String>,
    #[serde(default = "d_reconnect")]
    pub reconnect_ms: u64,
    /// The system ids of the ground stations goals are taken from (e.g. `[255]`); others are answered
    /// MISSION_ACK DENIED with the reason. Unset: any system.
    pub goal_sysids: Option<Vec<u8>>,
}

fn d_heartbeat_timeout() -> u64 {
    3000
}
fn d_ack_timeout() -> u64 {
    1000
}
fn d_retries() -> u32 {
    3
}
fn d_mission_timeout() -> u64 {
    1500
}
fn d_reconnect() -> u64 {
    500
}

/// A flight mode: ArduPilot's custom mode number, or PX4's main/sub mode pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(untagged)]
pub enum Mode {
    Number(u32),
    Px4 {
        main: u8,
        #[serde(default)]
        sub: u8,
    },
}

impl Mode {
    /// HEARTBEAT.custom_mode of this mode (PX4: main << 16 | sub << 24).
    pub fn custom_mode(&self) -> u32 {
        match *self {
            Mode::Number(n) => n,
            Mode::Px4 { main, sub } => (u32::from(main) << 16) | (u32::from(sub) << 24),
        }
    }

    /// MAV_CMD_DO_SET_MODE params 2 and 3 (ArduPilot: mode number; PX4: main, sub).
    pub fn set_mode_params(&self) -> (f32, f32) {
        match *self {
            Mode::Number(n) => (n as f32, 0.0),
            Mode::Px4 { main, sub } => (f32::from(main), f32::from(sub)),
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Modes {
    pub hold: Mode,
    pub auto: Mode,
    pub guided: Mode,
    pub rtl: Mode,
    pub manual: Option<Mode>,
    /// A flying vehicle's landing mode (ArduCopter LAND 9, PX4 AUTO.LAND): the `land` binding's.
    pub land: Option<Mode>,
    /// What a SIGINT / SIGTERM leaves the vehicle in: `hold` (default), `rtl` or `none` (as it is).
    #[serde(default)]
    pub on_shutdown: OnShutdown,
}

/// `[ready]`: how long `run` waits for a position fix and arming accepted before the mission starts.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReadyConfig {
    /// Vehicle seconds; 0: do not wait (the first motion arms the vehicle itself).
    #[serde(default = "d_ready_timeout")]
    pub timeout_s: f64,
    /// false: ready with a position (and the estimator trusting it), disarmed — a copter arms at its
    /// takeoff (src/vehicle/src/flight.rs).
    #[serde(default = "d_true")]
    pub arm: bool,
}

fn d_true() -> bool {
    true
}

impl Default for ReadyConfig {
    fn default() -> Self {
        ReadyConfig {
            timeout_s: d_ready_timeout(),
            arm: true,
        }
    }
}

fn d_ready_timeout() -> f64 {
    90.0
}

impl Modes {
    /// The modes by their key in `[modes]`.
    pub fn by_key(&self) -> Vec<(&'static str, Mode)> {
        let mut v = vec![
            ("hold", self.hold),
            ("auto", self.auto),
            ("guided", self.guided),
            ("rtl", self.rtl),
        ];
        if let Some(m) = self.manual {
            v.push(("manual", m));
        }
        if let Some(m) = self.land {
            v.push(("land", m));
        }
        v
    }
}

/// The domain's reservoirs the vehicle's battery (percent) and storage levels are reported as; a level whose
/// resource is not named is not reported.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResourceNames {
    pub battery: Option<String>,
    pub storage: Option<String>,
    /// How finely each level is reported, in the domain reservoir's units (default: the battery in whole
    /// percents, as MAVLink's `battery_remaining`; the storage exactly), and how far beyond that a reading
    /// may stray from the plan and still be noise (default 0), e.g. a move that ends within its acceptance
    /// radius, short of the planned distance.
    pub battery_resolution: Option<f64>,
    pub battery_tolerance: Option<f64>,
    pub storage_resolution: Option<f64>,
    pub storage_tolerance: Option<f64>,
    /// Percent of the battery the plan must never use (a flying vehicle's landing reserve): the battery
    /// reservoir is the level above it, so a plan that keeps the reservoir >= 0 keeps the reserve.
    pub battery_reserve: Option<f64>,
}

/// MAVLink reports the battery in whole percents (`battery_remaining`).
const BATTERY_RESOLUTION: f64 = 1.0;

impl ResourceNames {
    /// The one rule for reported levels, in `demo`, `soak` and `run` alike: a level within `resolution +
    /// tolerance` of the plan's bounds is in them (no repair). `None` when the vehicle reports no level of
    /// the domain's resource `name`.
    pub fn level_tolerance(&self, name: &str) -> Option<f64> {
        if self.battery.as_deref() == Some(name) {
            Some(
                self.battery_resolution.unwrap_or(BATTERY_RESOLUTION)
                    + self.battery_tolerance.unwrap_or(0.0),
            )
        } else if self.storage.as_deref() == Some(name) {
            Some(self.storage_resolution.unwrap_or(0.0) + self.storage_tolerance.unwrap_or(0.0))
        } else {
            None
        }
    }

    /// The first key that is not a number >= 0.
    fn invalid(&self) -> Option<&'static str> {
        [
            ("resources.battery_resolution", self.battery_resolution),
            ("resources.battery_tolerance", self.battery_tolerance),
            ("resources.storage_resolution", self.storage_resolution),
            ("resources.storage_tolerance", self.storage_tolerance),
        ]
        .into_iter()
        .find(|(_, v)| v.is_some_and(|v| !(v.is_finite() && v >= 0.0)))
        .map(|(k, _)| k)
        .or_else(|| {
            self.battery_reserve
                .is_some_and(|r| !(0.0..100.0).contains(&r))
                .then_some("resources.battery_reserve")
        })
    }

    /// The battery reservoir's level for a reported `percent`: what is left above the reserve.
    pub fn battery_level(&self, percent: f64) -> f64 {
        percent - self.battery_reserve.unwrap_or(0.0)
    }
}

/// `[mapping]`: which of the domain's names the executive gives a vehicle meaning to.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Mapping {
    /// The attribute a reported position sets: no parameters, valued in `location_type`.
    pub position: Option<String>,
    /// The type of located objects: a position that names no known object becomes a new object of it.
    pub location_type: Option<String>,
    /// The problem's object a return-home item means.
    pub home_object: Option<String>,
    /// Uploaded item kind (`waypoint`, `picture`, `sample`, `survey`, `return_home`) → its goal.
    #[serde(default)]
    pub goals: BTreeMap<GoalKind, GoalMapping>,
}

/// The goal an uploaded item kind becomes, on `attribute`: `attribute() = L` when it has no parameters and
/// is valued in the location type (be at L), `attribute(L) = true` when its one parameter is a location and
/// it is boolean (a picture of L, L sampled).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GoalMapping {
    pub attribute: String,
}

/// One servo step of a sampler sequence.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ServoStep {
    pub servo: u8,
    pub pwm: u16,
    pub hold_ms: u64,
}

/// How a task is realised and how its end is recognised (read through [`BindingTable`]).
#[derive(Debug, Clone)]
pub enum Binding {
    /// GUIDED `DO_REPOSITION` to the location argument `to`; done within `acceptance_radius_m`;
    /// interrupted by HOLD (the report gives the reached position as state variable `position`).
    Move {
        to: String,
        acceptance_radius_m: f64,
        speed_m_s: f64,
        position_variable: String,
        /// When set, the move is also done only within this vertical distance (an AUV reaching a depth);
        /// unset, only the horizontal distance counts (a ground vehicle does not control its altitude).
        vertical_acceptance_m: Option<f64>,
    },
    /// A lawnmower mission over a rectangle centred on the location argument `area`, run in AUTO;
    /// done on the last MISSION_ITEM_REACHED.
    Survey {
        area: String,
        width_m: f64,
        height_m: f64,
        spacing_m: f64,
        position_variable: String,
    },
    /// IMAGE_START_CAPTURE; done on CAMERA_IMAGE_CAPTURED, failed on capture_result 0 or timeout.
    TakePicture { camera_id: u8, timeout_ms: u64 },
    /// A DO_SET_SERVO sequence; done when the last step's hold time has elapsed.
    Sample { steps: Vec<ServoStep> },
    /// RTL; done within `acceptance_radius_m` of home.
    ReturnHome {
        acceptance_radius_m: f64,
        position_variable: String,
    },
    /// HOLD until the battery reaches `until_percent`, or the number argument `level_arg` when one is named.
    Recharge {
        until_percent: f64,
        level_arg: Option<String>,
    },
    /// The vehicle's downlink command (COMMAND_LONG `command`); done when used storage falls to
    /// `until_used` (STORAGE_INFORMATION polled every `poll_ms`), or after `max_ms` (the slot on the link is
    /// over: the downlink is stopped and what was sent is freed, maybe less than planned).
    Download {
        command: u16,
        until_used: f64,
        max_ms: Option<u64>,
        poll_ms: u64,
    },
    /// A task the autopilot has no counterpart for (e.g. turning a pan-and-tilt unit it does not drive, a
    /// software initialisation): nothing is sent, the action ends `duration_ms` after its start.
    Timed { duration_ms: u64 },
    /// A multicopter's flight actions (takeoff, fly to a place at its altitude, land or return and land):
    /// run by [`super::flight`].
    Flight(super::flight::FlightBinding),
}

/// The longest duration a configuration may give, ms: a week (longer ones overflow clock arithmetic).
const MAX_MS: u64 = 7 * 24 * 3_600_000;
const TOO_LONG: &str = "at most a week (604800000 ms)";

/// A binding's durations in ms, with their keys.
fn binding_ms(b: &Binding) -> Vec<(&'static str, u64)> {
    match b {
        Binding::TakePicture { timeout_ms, .. } => vec![("timeout_ms", *timeout_ms)],
        Binding::Sample { steps } => steps.iter().map(|s| ("steps", s.hold_ms)).collect(),
        Binding::Download {
            max_ms, poll_ms, ..
        } => {
            vec![("max_ms", max_ms.unwrap_or(0)), ("poll_ms", *poll_ms)]
        }
        Binding::Timed { duration_ms } => vec![("duration_ms", *duration_ms)],
        _ => Vec::new(),
    }
}

impl VehicleConfig {
    pub fn load(path: &Path) -> Result<Self, ConfigError> {
        let text = srctext::read(path)?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses and validates all but the executive's `[exec]` table; `origin` names the source in errors.
    pub fn parse(text: &str, origin: &str) -> Result<Self, ConfigError> {
        let mut cfg: VehicleConfig =
            srctext::toml_file::parse(origin, text).map_err(|e| ConfigError::At(Box::new(e)))?;
        let tables = std::mem::take(&mut cfg.tables);
        for (task, table) in tables {
            let binding = table.into_binding().map_err(|(key, reason)| {
                let path = format!("actions.{task}.{key}");
                let path = path.trim_end_matches('.');
                let message = format!("{path}: {reason}");
                ConfigError::At(Box::new(srctext::toml_file::at_key(
                    origin, text, path, message,
                )))
            })?;
            cfg.actions.insert(task, binding);
        }
        cfg.validate()
            .map_err(|e| ConfigError::At(Box::new(e.locate(origin, text))))?;
        cfg.source = Some(ConfigSource {
            origin: origin.to_string(),
            text: text.to_string(),
        });
        Ok(cfg)
    }

    /// The first semantic error: the key path it is about and why.
    fn validate(&self) -> Result<(), KeyError> {
        let invalid = |key: String, reason: &str| KeyError::new(key, reason);
        super::endpoint::Address::parse(&self.link.address)
            .map_err(|r| invalid("link.address".into(), &r.to_string()))?;
        if let Some(k) = &self.link.signing_key {
            super::frame::parse_key(k).map_err(|r| invalid("link.signing_key".into(), &r))?;
        }
        if let Some((key, reason)) = self.limits.invalid() {
            return Err(invalid(key.into(), &reason));
        }
        if let Some(key) = self.resources.invalid() {
            let why = if key == "resources.battery_reserve" {
                "a percent in [0, 100["
            } else {
                "must be a level >= 0"
            };
            return Err(invalid(key.into(), why));
        }
        if let Some(ids) = &self.link.goal_sysids {
            if ids.is_empty() || ids.contains(&0) {
                return Err(invalid(
                    "link.goal_sysids".into(),
                    "system ids 1 to 255, at least one (leave the key out to take goals from any system)",
                ));
            }
        }
        if !(-90.0..=90.0).contains(&self.home.lat) {
            return Err(invalid("home.lat".into(), "must be in [-90, 90]"));
        }
        if !(-180.0..=180.0).contains(&self.home.lon) {
            return Err(invalid("home.lon".into(), "must be in [-180, 180]"));
        }
        let l = &self.link;
        let link_ms = [
            ("heartbeat_timeout_ms", l.heartbeat_timeout_ms),
            ("command_ack_timeout_ms", l.command_ack_timeout_ms),
            ("mission_timeout_ms", l.mission_timeout_ms),
            ("reconnect_ms", l.reconnect_ms),
        ];
        for (k, ms) in link_ms {
            if ms > MAX_MS {
                return Err(invalid(format!("link.{k}"), TOO_LONG));
            }
        }
        let st = &self.state;
        if !(st.still_below_m_s.is_finite() && st.still_below_m_s >= 0.0) {
            return Err(invalid(
                "state.still_below_m_s".into(),
                "must be a speed >= 0",
            ));
        }
        if st.settle_ms > MAX_MS {
            return Err(invalid("state.settle_ms".into(), TOO_LONG));
        }
        if let Some(m) = &st.mode {
            let known: Vec<&str> = self.modes.by_key().iter().map(|(k, _)| *k).collect();
            if let Some(k) = m.values.keys().find(|k| !known.contains(&k.as_str())) {
                return Err(KeyError::new(
                    format!("state.mode.values.{k}"),
                    format!("not a mode of [modes] (they are: {})", known.join(", ")),
                ));
            }
        }
        let ready = self.ready.timeout_s;
        if !(ready.is_finite() && (0.0..=(MAX_MS / 1000) as f64).contains(&ready)) {
            return Err(invalid(
                "ready.timeout_s".into(),
                "seconds, from 0 (do not wait) to a week",
            ));
        }
        for (task, b) in &self.actions {
            let key = |k: &str| format!("actions.{task}.{k}");
            if let Some((k, _)) = binding_ms(b).into_iter().find(|(_, ms)| *ms > MAX_MS) {
                return Err(invalid(key(k), TOO_LONG));
            }
            match b {
                Binding::Move {
                    acceptance_radius_m,
                    ..
                }
                | Binding::ReturnHome {
                    acceptance_radius_m,
                    ..
                } if acceptance_radius_m.is_nan() || *acceptance_radius_m <= 0.0 => {
                    return Err(invalid(key("acceptance_radius_m"), "must be > 0"));
                }
                Binding::Move {
                    vertical_acceptance_m: Some(v),
                    ..
                } if !(v.is_finite() && *v > 0.0) => {
                    return Err(invalid(key("vertical_acceptance_m"), "must be > 0"));
                }
                Binding::Survey {
                    spacing_m,
                    width_m,
                    height_m,
                    ..
                } => {
                    if spacing_m.is_nan() || *spacing_m <= 0.0 {
                        return Err(invalid(key("spacing_m"), "must be > 0"));
                    }
                    if width_m.is_nan() || height_m.is_nan() || *width_m <= 0.0 || *height_m <= 0.0
                    {
                        return Err(invalid(key("width_m"), "width_m and height_m must be > 0"));
                    }
                    if width_m / spacing_m > 500.0 {
                        return Err(invalid(
                            key("spacing_m"),
                            "more than 500 legs: spacing too small",
                        ));
                    }
                }
                Binding::Flight(f) => {
                    if let Some((k, why)) = f.invalid(&self.modes) {
                        return Err(invalid(key(k), why));
                    }
                }
                Binding::Sample { steps } if steps.is_empty() => {
                    return Err(invalid(key("steps"), "needs at least one servo step"));
                }
                Binding::Recharge { until_percent, .. }
                    if !(0.0..=100.0).contains(until_percent) =>
                {
                    return Err(invalid(key("until_percent"), "must be in [0, 100]"));
                }
                _ => {}
            }
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::{Mode, Modes};

    /// ArduPilot Rover's modes (MANUAL 0, HOLD 4, AUTO 10, RTL 11, GUIDED 15).
    pub(crate) fn rover_modes() -> Modes {
        Modes {
            hold: Mode::Number(4),
            auto: Mode::Number(10),
            guided: Mode::Number(15),
            rtl: Mode::Number(11),
            manual: Some(Mode::Number(0)),
            land: None,
            on_shutdown: Default::default(),
        }
    }
}
