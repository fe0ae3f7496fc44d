//! Scenario files (TOML): world (zones, windows), vehicle and payload parameters, and faults.
//! The format is documented in `sitl/README.md`; every table rejects unknown keys by name.

use serde::Deserialize;
use srctext::toml_file::KeyError;

use crate::error::SimError;

/// Every table may be left out: it then takes its default.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Scenario {
    /// Where the vehicle boots; replaces [`crate::SimConfig::home`] (`mavtempo sim --home` replaces it).
    pub home: Option<HomeParams>,
    pub vehicle: VehicleParams,
    pub battery: BatteryParams,
    pub camera: CameraParams,
    pub sampler: SamplerParams,
    /// How closely the autopilot follows ArduPilot where the simple model differs (`[autopilot]`).
    pub autopilot: AutopilotParams,
    /// Terrain zones that slow the vehicle (obstacles, rough ground).
    pub slow_zones: Vec<Zone>,
    /// Zones where a still vehicle recharges. Empty: a 50 m zone around home.
    pub sunlit_zones: Vec<Zone>,
    /// When the downlink can run. Empty: always, at `camera.downlink_mib_per_s`.
    pub visibility_windows: Vec<VisibilityWindow>,
    /// The autopilot's geofence from boot (FENCE_* and the fence list, src/fence.rs).
    pub fence: crate::fence::FenceParams,
    pub faults: Vec<FaultSpec>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VehicleParams {
    /// Default cruise speed (ArduPilot WP_SPEED).
    pub speed_mps: f64,
    pub max_speed_mps: f64,
    pub accel_mps2: f64,
    pub turn_rate_dps: f64,
    /// Acceptance radius (ArduPilot WP_RADIUS).
    pub wp_radius_m: f64,
    /// AUV depth and copter altitude changes (a copter's climb, descent and landing).
    pub vertical_speed_mps: f64,
}

impl Default for VehicleParams {
    fn default() -> Self {
        Self {
            speed_mps: 5.0,
            max_speed_mps: 8.0,
            accel_mps2: 1.5,
            turn_rate_dps: 90.0,
            wp_radius_m: 3.0,
            vertical_speed_mps: 0.5,
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BatteryParams {
    pub initial_pct: f64,
    pub capacity_mah: f64,
    /// Drain per kilometre driven.
    pub drain_pct_per_km: f64,
    /// Drain per minute, moving or not (electronics).
    pub drain_pct_per_min: f64,
    /// Recharge per minute while still in a sunlit zone.
    pub recharge_pct_per_min: f64,
    /// Arming is refused below this level ("PreArm: Battery 1 below minimum arming capacity").
    pub arm_min_pct: f64,
    /// Copter: drain per minute off the ground (hover power), on top of the others.
    pub hover_pct_per_min: f64,
}

impl Default for BatteryParams {
    fn default() -> Self {
        Self {
            initial_pct: 98.0,
            capacity_mah: 5000.0,
            drain_pct_per_km: 4.0,
            drain_pct_per_min: 0.2,
            recharge_pct_per_min: 3.0,
            arm_min_pct: 20.0,
            hover_pct_per_min: 0.0,
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CameraParams {
    /// Picture sizes are drawn uniformly in [min, max] (the paper's uncertain compression rate).
    pub size_min_mib: f64,
    pub size_max_mib: f64,
    pub capture_time_s: f64,
    pub storage_capacity_mib: f64,
    /// Downlink rate when no visibility window sets one.
    pub downlink_mib_per_s: f64,
}

impl Default for CameraParams {
    fn default() -> Self {
        Self {
            size_min_mib: 2.0,
            size_max_mib: 4.0,
            capture_time_s: 1.0,
            storage_capacity_mib: 12.0,
            downlink_mib_per_s: 0.5,
        }
    }
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SamplerParams {
    /// Servo output driving the sampler (DO_SET_SERVO instance).
    pub servo: u8,
    /// PWM at or above which the sampler is deployed.
    pub deploy_pwm: u16,
    /// Still time needed to collect one sample.
    pub duration_s: f64,
}

impl Default for SamplerParams {
    fn default() -> Self {
        Self {
            servo: 9,
            deploy_pwm: 1500,
            duration_s: 5.0,
        }
    }
}

/// `[home]`: the vehicle's boot position, in degrees.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct HomeParams {
    pub lat: f64,
    pub lon: f64,
}

/// A set of autopilot behaviours chosen at once.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum Profile {
    /// The simple model every scenario had so far: ready and with a GPS fix at boot, the camera
    /// answers CAMERA_IMAGE_CAPTURED, speeds are accepted in any state.
    #[default]
    Default,
    /// What a real ArduPilot Rover (4.7-dev) SITL does: arming refused for 20 s after boot, no
    /// position for 10 s, AP_Camera (CAMERA_FEEDBACK), GUIDED submodes and their speed rules.
    Ardupilot,
    /// What a real PX4 (main, SIH rover) does: its custom modes, COMMAND_INT in GLOBAL_INT only, arming
    /// rejected while its checks fail after boot, no EKF_STATUS_REPORT, no camera (sitl/src/autopilot/px4.rs).
    Px4,
}

impl std::str::FromStr for Profile {
    type Err = SimError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "default" => Ok(Self::Default),
            "ardupilot" => Ok(Self::Ardupilot),
            "px4" => Ok(Self::Px4),
            other => Err(SimError::UnknownProfile(other.to_string())),
        }
    }
}

/// Which camera the autopilot drives.
#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum CameraBackend {
    /// A MAVLink camera (camera protocol v2): CAMERA_IMAGE_CAPTURED per picture.
    Mavlink,
    /// ArduPilot's AP_Camera (CAM1_TYPE set, feedback on): CAMERA_FEEDBACK per picture stored,
    /// no CAMERA_IMAGE_CAPTURED.
    Ardupilot,
    /// No camera configured: IMAGE_START_CAPTURE is FAILED.
    None,
}

/// Declares the `[autopilot]` keys once: the table as written (each key optional, absent: the profile's
/// value), the behaviour it comes to (each key resolved), and the resolution key by key; so a new key
/// cannot be declared in one and forgotten in the other.
macro_rules! autopilot_keys {
    ($($(#[$doc:meta])* $key:ident: $ty:ty,)*) => {
        /// `[autopilot]`: a profile, and keys that override what it sets.
        #[derive(Debug, Clone, Default, Deserialize, PartialEq)]
        #[serde(deny_unknown_fields, default)]
        pub struct AutopilotParams {
            pub profile: Profile,
            $($(#[$doc])* pub $key: Option<$ty>,)*
        }

        /// The behaviours an [`AutopilotParams`] comes to: its profile's, overridden key by key.
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct Behaviour {
            /// The profile the keys started from (it also sets the wording of arming refusals).
            pub profile: Profile,
            $($(#[$doc])* pub $key: $ty,)*
        }

        impl AutopilotParams {
            /// Its profile's behaviour, with each key written taking the place of the profile's value.
            pub fn behaviour(&self) -> Behaviour {
                let p = self.profile.behaviour();
                Behaviour {
                    profile: self.profile,
                    $($key: self.$key.unwrap_or(p.$key),)*
                }
            }
        }
    };
}

autopilot_keys! {
    /// Arming is refused (FAILED + "Arm: ..." texts) for this long after each boot.
    ready_after_s: f64,
    /// GLOBAL_POSITION_INT / GPS_RAW_INT read lat = lon = 0 for this long after each boot.
    gps_fix_after_s: f64,
    /// Which camera the autopilot drives.
    camera: CameraBackend,
    /// GUIDED starts in its Stop submode; speeds follow ArduPilot's submode rules (see the README).
    guided_submodes: bool,
    /// STORAGE_INFORMATION is answered (ArduPilot itself has none: REQUEST_MESSAGE(261) is FAILED).
    storage_information: bool,
}

impl Profile {
    pub fn behaviour(self) -> Behaviour {
        match self {
            Profile::Default => Behaviour {
                profile: self,
                ready_after_s: 0.0,
                gps_fix_after_s: 0.0,
                camera: CameraBackend::Mavlink,
                guided_submodes: false,
                storage_information: true,
            },
            // 20 s and 10 s as observed on ArduPilot Rover SITL; the storage stays answered so that
            // a companion tracking it keeps working (see the README).
            Profile::Ardupilot => Behaviour {
                profile: self,
                ready_after_s: 20.0,
                gps_fix_after_s: 10.0,
                camera: CameraBackend::Ardupilot,
                guided_submodes: true,
                storage_information: true,
            },
            // PX4 SIH rover: the GPS (SENS_EN_GPSSIM) gives a position within seconds; arming is refused
            // until the heading estimate is stable; no camera component; it has a STORAGE_INFORMATION
            // stream (its SD card).
            Profile::Px4 => Behaviour {
                profile: self,
                ready_after_s: PX4_READY_AFTER_S,
                gps_fix_after_s: PX4_GPS_FIX_AFTER_S,
                camera: CameraBackend::None,
                guided_submodes: false,
                storage_information: true,
            },
        }
    }
}

impl AutopilotParams {
    /// A profile with no key overridden.
    pub fn profile(profile: Profile) -> Self {
        Self {
            profile,
            ..Self::default()
        }
    }
}

/// Seconds after boot a PX4 SIH rover refuses arming ("heading estimate not stable") and has no position;
/// measured on PX4 main's `sihsim_rover_ackermann` (docs/real-autopilots.md).
/// First GLOBAL_POSITION_INT at 2.0 s of its clock, SYS_STATUS's PREARM_CHECK bit at 4.7 s, ARM accepted
/// at 5.5 s (2026-11-27, on 2 loaded cores).
const PX4_READY_AFTER_S: f64 = 5.0;
const PX4_GPS_FIX_AFTER_S: f64 = 2.0;

/// Longest boot delay accepted (a day): beyond it a delay is a typo, and ms stay far from overflow.
const MAX_BOOT_DELAY_S: f64 = 86_400.0;

/// A disc in the local frame (metres north/east of home) or around a lat/lon.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Zone {
    /// [north, east] metres from home.
    pub center_m: Option<[f64; 2]>,
    /// [lat, lon] degrees.
    pub center: Option<[f64; 2]>,
    pub radius_m: f64,
    /// Speed multiplier inside the zone (slow zones only; default 0.25).
    #[serde(default = "default_speed_factor")]
    pub speed_factor: f64,
}

fn default_speed_factor() -> f64 {
    0.25
}

#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct VisibilityWindow {
    pub start_s: f64,
    pub end_s: f64,
    pub rate_mib_per_s: f64,
}

/// One fault: what happens and when.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FaultSpec {
    pub when: Trigger,
    pub fault: Fault,
}

/// When a fault fires: at a sim time, or on the `occurrence`-th event of a kind (optionally with a
/// value: waypoint seq, picture index, command id, mode number), `delay_s` after it.
#[derive(Debug, Clone, Deserialize, PartialEq, Default)]
#[serde(deny_unknown_fields)]
pub struct Trigger {
    pub at_s: Option<f64>,
    pub on: Option<EventKind>,
    pub value: Option<i64>,
    #[serde(default = "one")]
    pub occurrence: u32,
    #[serde(default)]
    pub delay_s: f64,
    /// Only events within `within_m` (default [`NEAR_M`]) of this place (east, north metres from home):
    /// "the picture of p2", whichever capture that is in the plan's order.
    pub near_m: Option<[f64; 2]>,
    pub within_m: Option<f64>,
    /// Only events at or after this simulated time (seconds since the start) count: "a move late in the
    /// mission", whichever move that is in the plan's order.
    pub after_s: Option<f64>,
}

/// How close an event must be to a trigger's `near_m` when `within_m` is not given.
pub const NEAR_M: f64 = 3.0;

impl Trigger {
    /// Whether an event at `at_m` is near enough (always, without `near_m`).
    pub fn is_near(&self, at_m: [f64; 2]) -> bool {
        self.near_m.is_none_or(|p| {
            (p[0] - at_m[0]).hypot(p[1] - at_m[1]) <= self.within_m.unwrap_or(NEAR_M)
        })
    }
}

fn one() -> u32 {
    1
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    /// A mission item was reached (value: its seq).
    WaypointReached,
    /// A picture capture started (value: image index, from 0).
    PictureStarted,
    /// A COMMAND_LONG/COMMAND_INT arrived (value: command id).
    Command,
    /// The mode changed (value: custom mode number).
    ModeChanged,
    Armed,
    Disarmed,
    /// The vehicle started moving.
    Moving,
    DownlinkStarted,
    MissionStarted,
}

/// What a fault does.
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Fault {
    /// The next `count` COMMAND_LONG/INT with this id are answered with `result`.
    CommandFails {
        command: u16,
        #[serde(default)]
        result: FailResult,
        #[serde(default = "one")]
        count: u32,
    },
    /// The next `count` pictures fail (CAMERA_IMAGE_CAPTURED with capture_result 0).
    PictureFails {
        #[serde(default = "one")]
        count: u32,
    },
    /// The next `count` captures hang: the camera accepts the trigger but never stores an image nor
    /// answers (no CAMERA_IMAGE_CAPTURED), so the companion sees a timeout.
    PictureHangs {
        #[serde(default = "one")]
        count: u32,
    },
    /// The next `count` captures take `capture_time_s` instead of the camera's capture time (a picture
    /// that ends earlier, or later, than the plan expects), each storing `size_mib` if given (a capture cut
    /// short stores a smaller image: seed 1 §5's too-short picture).
    PictureDuration {
        capture_time_s: f64,
        #[serde(default)]
        size_mib: Option<f64>,
        #[serde(default = "one")]
        count: u32,
    },
    /// A slow zone appears.
    SlowZone { zone: Zone },
    /// The battery level drops by `percent` points.
    BatteryDrop { percent: f64 },
    /// The storage capacity shrinks by `mib`.
    StorageShrink { mib: f64 },
    /// Navigation fails: STATUSTEXT "Navigation failed: no map available", vehicle stops (HOLD);
    /// navigating modes are refused for `duration_s` (0: only this stop).
    NavFails {
        #[serde(default)]
        duration_s: f64,
    },
    /// Someone else changes the mode (an RC mode switch, another ground station): the autopilot enters
    /// custom mode `mode` (e.g. 4, HOLD on a rover) as if commanded, and the companion is not told why.
    ModeChange { mode: u32 },
    /// Someone else arms the vehicle (an RC stick, a ground station): refused as an ARM command would be
    /// while the autopilot is not ready.
    Arm,
    /// Nothing in or out for `duration_s`.
    LinkBlackout { duration_s: f64 },
    /// Per-frame probabilities on the link for `duration_s` (absent: for ever).
    LinkQuality {
        #[serde(default)]
        loss: f64,
        #[serde(default)]
        duplicate: f64,
        #[serde(default)]
        reorder: f64,
        duration_s: Option<f64>,
    },
    /// The downlink rate becomes `mib_per_s` (sub-production of a download).
    DownlinkRate { mib_per_s: f64 },
    /// The autopilot restarts, as ArduPilot does after a brown-out or a watchdog: nothing in or out for
    /// `silent_s`, then it boots with its clock (time_boot_ms) from 0, disarmed, in its initial mode
    /// (MANUAL), the running command (guided target, capture, downlink) forgotten; the vehicle stays where
    /// it stopped and the mission stored on it is kept.
    Reboot {
        #[serde(default = "default_reboot_silence")]
        silent_s: f64,
    },
}

fn default_reboot_silence() -> f64 {
    3.0
}

#[derive(Debug, Clone, Copy, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum FailResult {
    #[default]
    Denied,
    Failed,
    TemporarilyRejected,
}

impl Scenario {
    /// Reads and checks a scenario file.
    pub fn load(path: &std::path::Path) -> Result<Self, SimError> {
        let text = srctext::read(path)?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses and checks scenario text; `origin` names it in errors, each at its `line:col`.
    pub fn parse(text: &str, origin: &str) -> Result<Self, SimError> {
        let at = |e| SimError::ScenarioAt(Box::new(e));
        let scenario: Scenario = srctext::toml_file::parse(origin, text).map_err(at)?;
        scenario.check().map_err(|e| at(e.locate(origin, text)))?;
        Ok(scenario)
    }

    /// The first problem: the key path it is about (`slow_zones.1`) and why.
    pub(crate) fn check(&self) -> Result<(), KeyError> {
        let bad = |key: &str, reason: &str| Err(KeyError::new(key, reason));
        let c = &self.camera;
        if !(c.size_min_mib > 0.0 && c.size_min_mib <= c.size_max_mib) {
            return bad(
                "camera.size_min_mib",
                "need 0 < size_min_mib <= size_max_mib",
            );
        }
        if c.storage_capacity_mib <= 0.0 {
            return bad("camera.storage_capacity_mib", "must be > 0");
        }
        let v = &self.vehicle;
        if !(v.speed_mps > 0.0 && v.max_speed_mps >= v.speed_mps && v.accel_mps2 > 0.0) {
            return bad(
                "vehicle.speed_mps",
                "need 0 < speed_mps <= max_speed_mps and accel_mps2 > 0",
            );
        }
        if v.turn_rate_dps <= 0.0 || v.wp_radius_m <= 0.0 {
            return bad(
                "vehicle.turn_rate_dps",
                "turn_rate_dps and wp_radius_m must be > 0",
            );
        }
        if let Some(h) = self.home {
            if !(-90.0..=90.0).contains(&h.lat) {
                return bad("home.lat", "must be in [-90, 90]");
            }
            if !(-180.0..=180.0).contains(&h.lon) {
                return bad("home.lon", "must be in [-180, 180]");
            }
        }
        for (key, delay) in [
            ("autopilot.ready_after_s", self.autopilot.ready_after_s),
            ("autopilot.gps_fix_after_s", self.autopilot.gps_fix_after_s),
        ] {
            if delay.is_some_and(|d| !(0.0..=MAX_BOOT_DELAY_S).contains(&d)) {
                return bad(key, "must be in [0, 86400] seconds");
            }
        }
        if !(0.0..=100.0).contains(&self.battery.initial_pct) {
            return bad("battery.initial_pct", "must be in [0, 100]");
        }
        for (name, zones) in [
            ("slow_zones", &self.slow_zones),
            ("sunlit_zones", &self.sunlit_zones),
        ] {
            for (i, z) in zones.iter().enumerate() {
                check_zone(z).map_err(|(key, e)| {
                    let path = format!("{name}.{i}.{key}");
                    KeyError::new(path.trim_end_matches('.'), e)
                })?;
            }
        }
        for (i, w) in self.visibility_windows.iter().enumerate() {
            if !(w.start_s < w.end_s && w.rate_mib_per_s >= 0.0) {
                return Err(KeyError::new(
                    format!("visibility_windows.{i}"),
                    format!(
                        "[{}, {}]: need start_s < end_s and rate_mib_per_s >= 0",
                        w.start_s, w.end_s
                    ),
                ));
            }
        }
        if let Err((key, e)) = self.fence.check() {
            return Err(KeyError::new(key, e));
        }
        for (i, f) in self.faults.iter().enumerate() {
            check_fault(f).map_err(|e| KeyError::new(format!("faults.{i}"), e))?;
        }
        Ok(())
    }
}

/// A zone's first problem: the key it is about and why.
fn check_zone(z: &Zone) -> Result<(), (&'static str, &'static str)> {
    if z.center_m.is_some() == z.center.is_some() {
        return Err((
            "",
            "give exactly one of center_m = [north, east] or center = [lat, lon]",
        ));
    }
    if z.center.is_some_and(|[lat, lon]| {
        !((-90.0..=90.0).contains(&lat) && (-180.0..=180.0).contains(&lon))
    }) {
        return Err((
            "center",
            "[lat, lon]: lat must be in [-90, 90] and lon in [-180, 180]",
        ));
    }
    if z.radius_m <= 0.0 || !(0.0..=1.0).contains(&z.speed_factor) {
        return Err(("", "need radius_m > 0 and speed_factor in [0, 1]"));
    }
    Ok(())
}

/// A fault's first problem, as its reason (the caller names the key).
fn check_fault(f: &FaultSpec) -> Result<(), std::borrow::Cow<'static, str>> {
    let t = &f.when;
    if t.at_s.is_some() == t.on.is_some() {
        return Err("`when` needs exactly one of at_s or on".into());
    }
    if t.occurrence == 0 || t.delay_s < 0.0 {
        return Err("`when`: occurrence must be >= 1 and delay_s >= 0".into());
    }
    if t.near_m.is_some_and(|p| !p.iter().all(|c| c.is_finite()))
        || t.within_m.is_some_and(|r| !(r.is_finite() && r >= 0.0))
    {
        return Err("`when`: near_m must be finite and within_m finite and >= 0".into());
    }
    if t.after_s.is_some_and(|a| !(a.is_finite() && a >= 0.0)) {
        return Err("`when`: after_s must be finite and >= 0".into());
    }
    let prob = |p: f64| (0.0..=1.0).contains(&p);
    match &f.fault {
        Fault::SlowZone { zone } => {
            check_zone(zone).map_err(|(key, e)| format!("{key} {e}").into())
        }
        Fault::PictureDuration { capture_time_s, .. }
            if !(capture_time_s.is_finite()
                && *capture_time_s >= 0.0
                && *capture_time_s < 86_400.0) =>
        {
            Err("picture_duration: capture_time_s must be in [0, 86400[".into())
        }
        Fault::PictureDuration {
            size_mib: Some(m), ..
        } if !(m.is_finite() && *m >= 0.0) => {
            Err("picture_duration: size_mib must be finite and >= 0".into())
        }
        Fault::BatteryDrop { percent } if !(0.0..=100.0).contains(percent) => {
            Err("battery_drop: percent must be in [0, 100]".into())
        }
        Fault::StorageShrink { mib } if *mib < 0.0 => {
            Err("storage_shrink: mib must be >= 0".into())
        }
        Fault::LinkBlackout { duration_s } if *duration_s <= 0.0 => {
            Err("link_blackout: duration_s must be > 0".into())
        }
        Fault::LinkQuality {
            loss,
            duplicate,
            reorder,
            ..
        } if !(prob(*loss) && prob(*duplicate) && prob(*reorder)) => {
            Err("link_quality: loss, duplicate and reorder must be in [0, 1]".into())
        }
        Fault::Reboot { silent_s } if *silent_s < 0.0 => {
            Err("reboot: silent_s must be >= 0".into())
        }
        Fault::DownlinkRate { mib_per_s } if *mib_per_s < 0.0 => {
            Err("downlink_rate: mib_per_s must be >= 0".into())
        }
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_fault_kind() {
        let text = r#"
[camera]
storage_capacity_mib = 9.0
[[slow_zones]]
center_m = [10.0, 0.0]
radius_m = 5.0
[[faults]]
when = { at_s = 1.0 }
fault = { kind = "command_fails", command = 400, result = "failed" }
[[faults]]
when = { on = "picture_started", value = 0 }
fault = { kind = "picture_fails" }
[[faults]]
when = { on = "waypoint_reached", value = 2, delay_s = 1.5 }
fault = { kind = "slow_zone", zone = { center = [43.0, 1.0], radius_m = 20.0, speed_factor = 0.1 } }
[[faults]]
when = { on = "moving", occurrence = 2 }
fault = { kind = "battery_drop", percent = 30.0 }
[[faults]]
when = { at_s = 2.0 }
fault = { kind = "storage_shrink", mib = 3.0 }
[[faults]]
when = { at_s = 3.0 }
fault = { kind = "nav_fails" }
[[faults]]
when = { at_s = 4.0 }
fault = { kind = "link_blackout", duration_s = 2.0 }
[[faults]]
when = { at_s = 5.0 }
fault = { kind = "link_quality", loss = 0.1, duplicate = 0.05, reorder = 0.05 }
[[faults]]
when = { on = "downlink_started" }
fault = { kind = "downlink_rate", mib_per_s = 0.1 }

[[faults]]
when = { on = "moving", occurrence = 2 }
fault = { kind = "reboot", silent_s = 4.0 }
"#;
        let s = Scenario::parse(text, "inline").expect("valid scenario");
        assert_eq!(s.faults.len(), 10);
        assert_eq!(s.faults[9].fault, Fault::Reboot { silent_s: 4.0 });
        assert_eq!(s.camera.storage_capacity_mib, 9.0);
        assert_eq!(s.faults[3].when.occurrence, 2);
    }

    #[test]
    fn rejects_unknown_keys_and_bad_triggers() {
        let unknown = "[camera]\nsize_min = 1.0\n";
        let err = Scenario::parse(unknown, "x.toml").expect_err("unknown key");
        assert!(err.to_string().contains("size_min"), "{err}");
        let both = "[[faults]]\nwhen = { at_s = 1.0, on = \"armed\" }\nfault = { kind = \"picture_fails\" }\n";
        let err = Scenario::parse(both, "x.toml").expect_err("two triggers");
        assert!(err.to_string().contains("exactly one"), "{err}");
        let bad_kind = "[[faults]]\nwhen = { at_s = 1.0 }\nfault = { kind = \"meteor\" }\n";
        assert!(Scenario::parse(bad_kind, "x.toml").is_err());
    }
}
