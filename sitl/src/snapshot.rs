//! A read-only picture of the simulated vehicle, for test assertions and the demo. Peers over
//! MAVLink never see it: it is the ground truth to compare their view against.

#[derive(Debug, Clone, Default, PartialEq)]
pub struct Snapshot {
    /// Sim time since the simulation started (`time_boot_ms` until a `reboot` fault restarts that).
    pub time_ms: u64,
    pub lat: f64,
    pub lon: f64,
    pub north_m: f64,
    pub east_m: f64,
    pub depth_m: f64,
    /// Copter: EXTENDED_SYS_STATE's landed state (1 on the ground, 2 in the air, 3 taking off, 4 landing);
    /// 0 for other vehicles.
    pub landed_state: u8,
    pub speed_mps: f64,
    pub heading_deg: f64,
    /// Odometer.
    pub distance_m: f64,
    pub mode: &'static str,
    pub custom_mode: u32,
    pub armed: bool,
    pub battery_pct: f64,
    pub storage_capacity_mib: f64,
    pub storage_used_mib: f64,
    pub pictures_ok: u32,
    pub pictures_failed: u32,
    pub samples: u32,
    pub downlink_active: bool,
    /// Mission items excluding home (MISSION_CURRENT.total).
    pub mission_total: u16,
    pub mission_current: u16,
    pub mission_complete: bool,
    pub link_blackout: bool,
    pub frames_dropped: u64,
    /// The last STATUSTEXTs sent, oldest first.
    pub statustexts: Vec<String>,
    /// COMMAND_LONG/INT received that command the vehicle (all but message requests), copies included.
    pub control_commands: u32,
    /// ARM requests received (MAV_CMD_COMPONENT_ARM_DISARM with p1 = 1).
    pub arm_commands: u32,
}
