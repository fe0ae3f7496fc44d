//! The camera the autopilot drives (`[autopilot] camera`): a MAVLink camera reporting each picture
//! with CAMERA_IMAGE_CAPTURED, ArduPilot's own AP_Camera reporting with CAMERA_FEEDBACK, or none.
//! Pictures take the same time, fill the same storage and suffer the same faults whichever it is;
//! only what the peers are told differs.

use mavlink::dialects::ardupilotmega::*;

use super::{Autopilot, Dest};
use crate::payload::MAX_PICTURES_PER_REQUEST;
use crate::scenario::CameraBackend;
use geodesy::deg_to_e7;

/// AP_Camera's counters as the autopilot reports them; they start again at each boot.
#[derive(Debug, Clone, Default)]
pub struct ApCamera {
    /// Image index (the sim's, from its start) of this boot's first picture.
    first_index: i32,
    /// Pictures confirmed this boot (CAMERA_FEEDBACK.completed_captures).
    completed: u16,
    /// The last CAMERA_FEEDBACK: AP_Camera sends it again when asked.
    last: Option<CAMERA_FEEDBACK_DATA>,
    /// The interval of the last picture sequence (CAMERA_CAPTURE_STATUS.image_interval).
    interval_s: f32,
}

impl ApCamera {
    /// A (re)boot with `next_index` the index of the next picture.
    pub fn booted(next_index: i32) -> Self {
        Self {
            first_index: next_index,
            ..Self::default()
        }
    }
}

impl Autopilot {
    /// IMAGE_START_CAPTURE (p1 camera id, p2 interval s, p3 count), from a command or a mission item.
    pub(super) fn image_start_capture(
        &mut self,
        id: f32,
        interval_s: f32,
        count: f32,
    ) -> MavResult {
        match self.behaviour.camera {
            CameraBackend::Mavlink => {
                self.start_capture(count.max(1.0) as u32, f64::from(interval_s));
                MavResult::MAV_RESULT_ACCEPTED
            }
            // AP_Camera::handle_command: a negative id is UNSUPPORTED; with no backend for it
            // (none configured, or an id beyond camera 1) take_picture fails: FAILED.
            _ if id < 0.0 => MavResult::MAV_RESULT_UNSUPPORTED,
            CameraBackend::None => MavResult::MAV_RESULT_FAILED,
            CameraBackend::Ardupilot if id >= 2.0 => MavResult::MAV_RESULT_FAILED,
            CameraBackend::Ardupilot => {
                if count == 1.0 || (interval_s == 0.0 && count == 0.0) {
                    self.start_capture(1, 0.0);
                    return MavResult::MAV_RESULT_ACCEPTED;
                }
                // take_multiple_pictures refuses an interval of 0 whole milliseconds.
                if (interval_s * 1000.0) as u32 == 0 {
                    return MavResult::MAV_RESULT_FAILED;
                }
                // Count 0 (or negative) shoots until stopped: here, up to the per-request cap.
                let n = if count >= 1.0 {
                    count as u32
                } else {
                    MAX_PICTURES_PER_REQUEST
                };
                self.ap_camera.interval_s = interval_s;
                self.start_capture(n, f64::from(interval_s));
                MavResult::MAV_RESULT_ACCEPTED
            }
        }
    }

    /// DO_DIGICAM_CONTROL: AP_Camera shoots only when its shooting command (param5) is 1; the simple
    /// MAVLink camera shoots on every one.
    pub(super) fn digicam_control(&mut self, shooting_cmd: f32) {
        match self.behaviour.camera {
            CameraBackend::Mavlink => self.start_capture(1, 0.0),
            CameraBackend::Ardupilot if shooting_cmd == 1.0 => self.start_capture(1, 0.0),
            CameraBackend::Ardupilot | CameraBackend::None => {}
        }
    }

    /// Tells the peers about picture `index`, stored or failed for `failure`.
    pub(super) fn report_picture(&mut self, index: i32, failure: Option<&'static str>) {
        match self.behaviour.camera {
            CameraBackend::Mavlink => {
                if let Some(reason) = failure {
                    self.text(MavSeverity::MAV_SEVERITY_ERROR, reason);
                }
                let msg = self.image_captured(index, failure.is_none());
                self.send(Dest::All, msg);
            }
            // AP_Camera hears of a picture only through its feedback pin: a failed one is silence.
            CameraBackend::Ardupilot => match failure {
                Some(reason) => tracing::debug!(index, reason, "sitl: no camera feedback"),
                None => {
                    self.ap_camera.completed = self.ap_camera.completed.saturating_add(1);
                    let fb = self.feedback(index);
                    self.ap_camera.last = Some(fb.clone());
                    self.send(Dest::All, MavMessage::CAMERA_FEEDBACK(fb));
                }
            },
            CameraBackend::None => {}
        }
    }

    fn image_captured(&self, index: i32, ok: bool) -> MavMessage {
        let geo = self.frame.to_geo(self.kin.pos);
        MavMessage::CAMERA_IMAGE_CAPTURED(CAMERA_IMAGE_CAPTURED_DATA {
            time_utc: self.epoch_unix_us + self.now_ms * 1000,
            time_boot_ms: self.time_boot_ms(),
            lat: deg_to_e7(geo.lat),
            lon: deg_to_e7(geo.lon),
            alt: -(self.kin.depth * 1000.0) as i32,
            relative_alt: 0,
            q: [1.0, 0.0, 0.0, 0.0],
            image_index: index,
            camera_id: 1,
            capture_result: if ok {
                MavBool::MAV_BOOL_TRUE
            } else {
                MavBool::MAV_BOOL_FALSE
            },
            file_url: if ok {
                format!("sitl://img/{index:04}.jpg").as_str().into()
            } else {
                "".into()
            },
        })
    }

    /// AP_Camera_Backend::send_camera_feedback for picture `index`, confirmed now.
    fn feedback(&self, index: i32) -> CAMERA_FEEDBACK_DATA {
        let (lat, lng) = self.reported_position_e7();
        let alt_m = -self.kin.depth as f32;
        CAMERA_FEEDBACK_DATA {
            // Stamped with the GPS time: 0 before the fix.
            time_usec: if self.gps_fixed() {
                self.epoch_unix_us + self.now_ms * 1000
            } else {
                0
            },
            lat,
            lng,
            alt_msl: alt_m,
            alt_rel: alt_m,
            yaw: self.kin.heading.to_degrees() as f32,
            // AP_Camera counts images from 1 at each boot.
            img_idx: u16::try_from(index - self.ap_camera.first_index + 1).unwrap_or(u16::MAX),
            target_system: 0,
            cam_idx: 0,
            flags: CameraFeedbackFlags::CAMERA_FEEDBACK_PHOTO,
            completed_captures: self.ap_camera.completed,
            ..Default::default()
        }
    }

    /// CAMERA_FEEDBACK on request: the last one (AP_Camera sends its zeroed record before any).
    pub(super) fn last_feedback(&self) -> Option<MavMessage> {
        (self.behaviour.camera == CameraBackend::Ardupilot)
            .then(|| MavMessage::CAMERA_FEEDBACK(self.ap_camera.last.clone().unwrap_or_default()))
    }

    /// CAMERA_CAPTURE_STATUS as the configured camera reports it (none: nothing to report).
    pub(super) fn capture_status(&self) -> Option<MavMessage> {
        let status = match self.behaviour.camera {
            // The camera's own account: a capture under way, and the images captured so far, for a
            // companion that missed a CAMERA_IMAGE_CAPTURED.
            CameraBackend::Mavlink => CAMERA_CAPTURE_STATUS_DATA {
                time_boot_ms: self.time_boot_ms(),
                available_capacity: self.storage.available() as f32,
                image_status: u8::from(self.camera.capturing()),
                image_count: i32::try_from(self.pictures_ok).unwrap_or(i32::MAX),
                camera_device_id: 1,
                ..Default::default()
            },
            // AP_Camera_Backend::send_camera_capture_status: never "capturing", 2 while a sequence
            // has pictures left, the pictures triggered this boot, no capacity.
            CameraBackend::Ardupilot => CAMERA_CAPTURE_STATUS_DATA {
                time_boot_ms: self.time_boot_ms(),
                image_status: if self.camera.pending() > 1 { 2 } else { 0 },
                image_interval: self.ap_camera.interval_s,
                available_capacity: f32::NAN,
                image_count: self.camera.next_index() - self.ap_camera.first_index,
                ..Default::default()
            },
            CameraBackend::None => return None,
        };
        Some(MavMessage::CAMERA_CAPTURE_STATUS(status))
    }
}
