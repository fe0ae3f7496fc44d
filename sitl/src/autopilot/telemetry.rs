//! Telemetry streams (intervals in sim time, so rates scale with the speed-up as on ArduPilot
//! SITL) and the messages they carry.

use std::collections::BTreeMap;

use mavlink::dialects::ardupilotmega::*;

use super::{Autopilot, Dest, Mode};
use crate::config::VehicleKind;
use geodesy::deg_to_e7;

pub const HEARTBEAT: u32 = 0;
pub const SYS_STATUS: u32 = 1;
pub const SYSTEM_TIME: u32 = 2;
pub const GPS_RAW_INT: u32 = 24;
pub const ATTITUDE: u32 = 30;
pub const GLOBAL_POSITION_INT: u32 = 33;
pub const SERVO_OUTPUT_RAW: u32 = 36;
pub const MISSION_CURRENT: u32 = 42;
pub const BATTERY_STATUS: u32 = 147;
pub const AUTOPILOT_VERSION: u32 = 148;
pub const HOME_POSITION: u32 = 242;
pub const EXTENDED_SYS_STATE: u32 = 245;
pub const STORAGE_INFORMATION: u32 = 261;
pub const CAMERA_CAPTURE_STATUS: u32 = 262;
pub const CAMERA_FEEDBACK: u32 = 180;

/// Messages sent at 1 Hz (sim time) by default; others only on request or by interval.
const DEFAULT_STREAMS: [u32; 8] = [
    HEARTBEAT,
    SYS_STATUS,
    SYSTEM_TIME,
    GPS_RAW_INT,
    GLOBAL_POSITION_INT,
    MISSION_CURRENT,
    BATTERY_STATUS,
    ATTITUDE,
];

/// Every message the sim can send on request or at an interval.
pub const SENDABLE: [u32; 14] = [
    HEARTBEAT,
    SYS_STATUS,
    SYSTEM_TIME,
    GPS_RAW_INT,
    ATTITUDE,
    GLOBAL_POSITION_INT,
    SERVO_OUTPUT_RAW,
    MISSION_CURRENT,
    BATTERY_STATUS,
    AUTOPILOT_VERSION,
    HOME_POSITION,
    STORAGE_INFORMATION,
    CAMERA_CAPTURE_STATUS,
    EXTENDED_SYS_STATE,
];

#[derive(Debug, Clone)]
pub struct Streams {
    /// message id -> (interval ms, next due sim ms)
    active: BTreeMap<u32, (u64, u64)>,
}

impl Default for Streams {
    fn default() -> Self {
        Self {
            active: DEFAULT_STREAMS.iter().map(|&id| (id, (1000, 0))).collect(),
        }
    }
}

impl Streams {
    /// Also streams `id` at 1 Hz by default (PX4's ESTIMATOR_STATUS).
    pub fn with_default(mut self, id: u32) -> Self {
        self.active.insert(id, (1000, 0));
        self
    }

    /// SET_MESSAGE_INTERVAL semantics: -1 stops, 0 restores the default, > 0 is the interval in us.
    /// Refused (DENIED): an interval that is not a number, and HEARTBEAT stopped or slower than 1 Hz — it
    /// is every peer's sign that the vehicle is there, and one peer's request would silence it for all.
    pub fn set_interval_us(&mut self, id: u32, interval_us: f32, now_ms: u64) -> MavResult {
        if !SENDABLE.contains(&id) {
            return MavResult::MAV_RESULT_FAILED;
        }
        if !interval_us.is_finite() || (id == HEARTBEAT && !(0.0..=1e6).contains(&interval_us)) {
            return MavResult::MAV_RESULT_DENIED;
        }
        if interval_us < 0.0 {
            self.active.remove(&id);
        } else if interval_us == 0.0 {
            if DEFAULT_STREAMS.contains(&id) {
                self.active.insert(id, (1000, now_ms));
            } else {
                self.active.remove(&id);
            }
        } else {
            let ms = ((interval_us / 1000.0).round() as u64).max(1);
            self.active.insert(id, (ms, now_ms));
        }
        MavResult::MAV_RESULT_ACCEPTED
    }

    /// REQUEST_DATA_STREAM: HEARTBEAT is no data stream (ArduPilot sends it whatever the rates).
    pub fn set_rate_hz(&mut self, ids: &[u32], hz: u16, now_ms: u64) {
        for &id in ids.iter().filter(|&&id| id != HEARTBEAT) {
            if hz == 0 {
                self.active.remove(&id);
            } else {
                self.active
                    .insert(id, ((1000 / u64::from(hz)).max(1), now_ms));
            }
        }
    }

    /// Ids due at `now_ms`, rescheduled.
    pub fn due(&mut self, now_ms: u64) -> Vec<u32> {
        let mut out = Vec::new();
        for (id, (interval, next)) in self.active.iter_mut() {
            if *next <= now_ms {
                out.push(*id);
                *next = (*next + *interval).max(now_ms + 1).min(now_ms + *interval);
            }
        }
        out
    }
}

/// REQUEST_DATA_STREAM groups as ArduPilot maps them.
pub fn data_stream_ids(stream: MavDataStream) -> Vec<u32> {
    match stream {
        MavDataStream::MAV_DATA_STREAM_ALL => SENDABLE
            .iter()
            .copied()
            .filter(|id| DEFAULT_STREAMS.contains(id))
            .collect(),
        MavDataStream::MAV_DATA_STREAM_EXTENDED_STATUS => {
            vec![SYS_STATUS, MISSION_CURRENT, GPS_RAW_INT]
        }
        MavDataStream::MAV_DATA_STREAM_POSITION => vec![GLOBAL_POSITION_INT],
        MavDataStream::MAV_DATA_STREAM_EXTRA1 => vec![ATTITUDE],
        MavDataStream::MAV_DATA_STREAM_RAW_CONTROLLER => vec![SERVO_OUTPUT_RAW],
        MavDataStream::MAV_DATA_STREAM_EXTRA3 => vec![SYSTEM_TIME, BATTERY_STATUS],
        _ => Vec::new(),
    }
}

impl Autopilot {
    /// The streams at boot: PX4 also streams ESTIMATOR_STATUS (mavlink_main.cpp, onboard mode).
    pub(super) fn default_streams(&self) -> Streams {
        let s = Streams::default();
        if self.is_px4() {
            s.with_default(super::px4::ESTIMATOR_STATUS)
        } else {
            s
        }
    }

    pub(super) fn time_boot_ms(&self) -> u32 {
        self.now_ms.saturating_sub(self.booted_ms) as u32
    }

    /// Sends the streams due now.
    pub(super) fn step_telemetry(&mut self) {
        for id in self.streams.due(self.now_ms) {
            if let Some(m) = self.build(id) {
                self.send(Dest::All, m);
            }
        }
    }

    /// Builds message `id` from the current state (None if the sim cannot send it).
    pub(super) fn build(&self, id: u32) -> Option<MavMessage> {
        let geo = self.frame.to_geo(self.kin.pos);
        let alt_mm = -(self.kin.depth * 1000.0).round() as i32;
        let reported = self.reported_position_e7();
        Some(match id {
            HEARTBEAT => self.heartbeat(),
            // ArduPilot sends it on request only; vtol_state is a VTOL's (MAV_VTOL_STATE_UNDEFINED).
            EXTENDED_SYS_STATE => MavMessage::EXTENDED_SYS_STATE(EXTENDED_SYS_STATE_DATA {
                vtol_state: MavVtolState::MAV_VTOL_STATE_UNDEFINED,
                landed_state: self.landed_state(),
            }),
            SYS_STATUS => MavMessage::SYS_STATUS(SYS_STATUS_DATA {
                onboard_control_sensors_present: sensors(),
                onboard_control_sensors_enabled: sensors(),
                onboard_control_sensors_health: self.health_sensors(sensors()),
                load: 100,
                voltage_battery: self.battery.voltage_mv(),
                current_battery: self.battery.current_ca(self.kin.speed),
                battery_remaining: self.battery.pct.round() as i8,
                ..Default::default()
            }),
            SYSTEM_TIME => MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
                time_unix_usec: self.epoch_unix_us + self.now_ms * 1000,
                time_boot_ms: self.time_boot_ms(),
            }),
            GPS_RAW_INT if !self.gps_fixed() => MavMessage::GPS_RAW_INT(GPS_RAW_INT_DATA {
                time_usec: self.now_ms * 1000,
                eph: u16::MAX,
                epv: u16::MAX,
                vel: u16::MAX,
                cog: u16::MAX,
                fix_type: GpsFixType::GPS_FIX_TYPE_NO_FIX,
                ..Default::default()
            }),
            GPS_RAW_INT => MavMessage::GPS_RAW_INT(GPS_RAW_INT_DATA {
                time_usec: self.now_ms * 1000,
                lat: deg_to_e7(geo.lat),
                lon: deg_to_e7(geo.lon),
                alt: alt_mm,
                eph: 80,
                epv: 120,
                vel: (self.kin.speed * 100.0).round() as u16,
                cog: cdeg(self.kin.heading),
                fix_type: GpsFixType::GPS_FIX_TYPE_3D_FIX,
                satellites_visible: 12,
                ..Default::default()
            }),
            ATTITUDE => MavMessage::ATTITUDE(ATTITUDE_DATA {
                time_boot_ms: self.time_boot_ms(),
                yaw: self.kin.heading as f32,
                ..Default::default()
            }),
            GLOBAL_POSITION_INT => MavMessage::GLOBAL_POSITION_INT(GLOBAL_POSITION_INT_DATA {
                time_boot_ms: self.time_boot_ms(),
                lat: reported.0,
                lon: reported.1,
                alt: alt_mm,
                relative_alt: alt_mm,
                vx: (self.kin.speed * self.kin.heading.cos() * 100.0).round() as i16,
                vy: (self.kin.speed * self.kin.heading.sin() * 100.0).round() as i16,
                vz: (self.kin.vz * 100.0).round() as i16,
                hdg: cdeg(self.kin.heading),
            }),
            SERVO_OUTPUT_RAW => MavMessage::SERVO_OUTPUT_RAW(SERVO_OUTPUT_RAW_DATA {
                time_usec: (self.now_ms * 1000) as u32,
                servo1_raw: self.servos[0],
                servo2_raw: self.servos[1],
                servo3_raw: self.servos[2],
                servo4_raw: self.servos[3],
                servo5_raw: self.servos[4],
                servo6_raw: self.servos[5],
                servo7_raw: self.servos[6],
                servo8_raw: self.servos[7],
                servo9_raw: self.servos[8],
                servo10_raw: self.servos[9],
                servo11_raw: self.servos[10],
                servo12_raw: self.servos[11],
                servo13_raw: self.servos[12],
                servo14_raw: self.servos[13],
                servo15_raw: self.servos[14],
                servo16_raw: self.servos[15],
                port: 0,
            }),
            MISSION_CURRENT => self.mission_current_msg(),
            BATTERY_STATUS => {
                let mut voltages = [u16::MAX; 10];
                voltages[0] = self.battery.voltage_mv();
                MavMessage::BATTERY_STATUS(BATTERY_STATUS_DATA {
                    current_consumed: self.battery.consumed_mah.round() as i32,
                    energy_consumed: (self.battery.consumed_mah * 14.4 * 3.6 / 100.0).round()
                        as i32,
                    temperature: i16::MAX,
                    voltages,
                    current_battery: self.battery.current_ca(self.kin.speed),
                    id: 0,
                    battery_function: MavBatteryFunction::MAV_BATTERY_FUNCTION_ALL,
                    mavtype: MavBatteryType::MAV_BATTERY_TYPE_LIPO,
                    battery_remaining: self.battery.pct.round() as i8,
                    time_remaining: 0,
                    charge_state: if self.battery.charging {
                        MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_CHARGING
                    } else if self.battery.pct < 15.0 {
                        MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_CRITICAL
                    } else {
                        MavBatteryChargeState::MAV_BATTERY_CHARGE_STATE_OK
                    },
                    ..Default::default()
                })
            }
            AUTOPILOT_VERSION => MavMessage::AUTOPILOT_VERSION(AUTOPILOT_VERSION_DATA {
                capabilities: MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MISSION_FLOAT
                    | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_PARAM_FLOAT
                    | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MISSION_INT
                    | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_COMMAND_INT
                    | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_GLOBAL_INT
                    | MavProtocolCapability::MAV_PROTOCOL_CAPABILITY_MAVLINK2,
                flight_sw_version: 0x0406_00ff,
                uid: 0x5349_544c,
                ..Default::default()
            }),
            // Home is set at the first fix; before it ArduPilot sends no HOME_POSITION.
            HOME_POSITION if !self.gps_fixed() => return None,
            STORAGE_INFORMATION if !self.behaviour.storage_information => return None,
            HOME_POSITION => {
                let home = self.frame.origin();
                MavMessage::HOME_POSITION(HOME_POSITION_DATA {
                    latitude: deg_to_e7(home.lat),
                    longitude: deg_to_e7(home.lon),
                    q: [1.0, 0.0, 0.0, 0.0],
                    time_usec: self.now_ms * 1000,
                    ..Default::default()
                })
            }
            STORAGE_INFORMATION => MavMessage::STORAGE_INFORMATION(STORAGE_INFORMATION_DATA {
                time_boot_ms: self.time_boot_ms(),
                total_capacity: self.storage.capacity_mib as f32,
                used_capacity: self.storage.used_mib as f32,
                available_capacity: self.storage.available() as f32,
                read_speed: 20.0,
                write_speed: 10.0,
                storage_id: 1,
                storage_count: 1,
                status: StorageStatus::STORAGE_STATUS_READY,
                mavtype: StorageType::STORAGE_TYPE_SD,
                name: "sitl-sd".into(),
                storage_usage: StorageUsageFlag::STORAGE_USAGE_FLAG_SET
                    | StorageUsageFlag::STORAGE_USAGE_FLAG_PHOTO,
            }),
            CAMERA_CAPTURE_STATUS => return self.capture_status(),
            CAMERA_FEEDBACK => return self.last_feedback(),
            super::px4::ESTIMATOR_STATUS => return self.estimator_status(),
            _ => return None,
        })
    }

    pub(super) fn heartbeat(&self) -> MavMessage {
        let mut base = MavModeFlag::MAV_MODE_FLAG_CUSTOM_MODE_ENABLED;
        match self.mode {
            Mode::Manual => base |= MavModeFlag::MAV_MODE_FLAG_MANUAL_INPUT_ENABLED,
            Mode::Auto | Mode::Rtl | Mode::Guided => {
                base |= MavModeFlag::MAV_MODE_FLAG_GUIDED_ENABLED
            }
            Mode::Hold | Mode::Land => {}
        }
        if self.armed {
            base |= MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED;
        }
        MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: self.reported_mode(),
            mavtype: match self.vehicle {
                VehicleKind::Rover => MavType::MAV_TYPE_GROUND_ROVER,
                VehicleKind::Auv => MavType::MAV_TYPE_SUBMARINE,
                VehicleKind::Copter => MavType::MAV_TYPE_QUADROTOR,
            },
            autopilot: if self.is_px4() {
                MavAutopilot::MAV_AUTOPILOT_PX4
            } else {
                MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA
            },
            base_mode: base,
            system_status: if self.battery.pct < 10.0 {
                MavState::MAV_STATE_CRITICAL
            } else {
                MavState::MAV_STATE_ACTIVE
            },
            mavlink_version: 3,
        })
    }
}

fn sensors() -> MavSysStatusSensor {
    MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_GYRO
        | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_ACCEL
        | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_3D_MAG
        | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_GPS
        | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_MOTOR_OUTPUTS
        | MavSysStatusSensor::MAV_SYS_STATUS_SENSOR_BATTERY
}

fn cdeg(rad: f64) -> u16 {
    (rad.to_degrees().rem_euclid(360.0) * 100.0).round() as u16 % 36000
}
