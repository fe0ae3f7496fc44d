//! What a freshly booted ArduPilot is not yet ready for: arming (its arming checks fail while the
//! system and the IMUs settle) and a position (no GPS fix). Both count from each boot, so a
//! `reboot` fault starts them again.

use super::Autopilot;
use crate::scenario::Profile;
use crate::time::secs_to_ms;
use geodesy::deg_to_e7;

/// The failing check ArduPilot reports at a fraction of `ready_after_s`: AP_Arming_Rover's
/// `pre_arm_checks` stops at "System not initialised" until the scheduler is up, then
/// AP_Arming's `ins_checks` stops at the first of the IMU consistency checks (each must pass for
/// 10 s). The fractions only order the texts as they appear on ArduPilot SITL.
const BOOT_CHECKS: [(f64, &str); 3] = [
    (0.5, "System not initialised"),
    (0.9, "Accels inconsistent"),
    (1.0, "Gyros inconsistent"),
];

impl Autopilot {
    /// `secs` have passed since boot (time_boot_ms stays 0 while a reboot is silent).
    fn booted_for(&self, secs: f64) -> bool {
        u64::from(self.time_boot_ms()) >= secs_to_ms(secs)
    }

    /// The arming checks pass (ArduPilot profile: `ready_after_s` after boot).
    pub(super) fn ready(&self) -> bool {
        self.booted_for(self.behaviour.ready_after_s)
    }

    /// The GPS has a fix and home is set (ArduPilot profile: `gps_fix_after_s` after boot).
    pub(crate) fn gps_fixed(&self) -> bool {
        self.booted_for(self.behaviour.gps_fix_after_s)
    }

    /// The position the autopilot reports, lat/lon ×1e7: (0, 0) before the fix, as ArduPilot's
    /// AHRS has no location yet.
    pub(super) fn reported_position_e7(&self) -> (i32, i32) {
        if !self.gps_fixed() {
            return (0, 0);
        }
        let geo = self.frame.to_geo(self.kin.pos);
        (deg_to_e7(geo.lat), deg_to_e7(geo.lon))
    }

    /// Why an unforced arming is refused now, one STATUSTEXT each (empty: it may arm). Forced
    /// arming skips them all, as ArduPilot's `mandatory_checks` pass on a SITL.
    pub(super) fn arm_refusals(&self) -> Vec<String> {
        // A MAVLink arm runs the checks as "arming checks": ArduPilot prefixes "Arm: ".
        let prefix = match self.behaviour.profile {
            Profile::Ardupilot => "Arm: ",
            Profile::Default => "PreArm: ",
            // PX4's checks report "Preflight Fail: ..." (sitl/src/autopilot/px4.rs).
            Profile::Px4 => "Preflight Fail: ",
        };
        let mut out = Vec::new();
        if self.behaviour.profile == Profile::Px4 && !self.ready() {
            out.push(super::px4::HEADING_NOT_STABLE.to_string());
            out.push(super::px4::ARMING_DENIED.to_string());
        }
        if !self.ready() && self.behaviour.profile != Profile::Px4 {
            let ready_ms = secs_to_ms(self.behaviour.ready_after_s) as f64;
            let t = f64::from(self.time_boot_ms());
            let check = BOOT_CHECKS
                .iter()
                .find(|(fraction, _)| t < fraction * ready_ms)
                .map_or(BOOT_CHECKS[2].1, |c| c.1);
            out.push(format!("{prefix}{check}"));
            if check == BOOT_CHECKS[0].1 {
                // ArduPilot returns before any other check while not initialised.
                return out;
            }
        }
        if !self.battery.can_arm() {
            out.push(format!("{prefix}Battery 1 below minimum arming capacity"));
        }
        out
    }
}
