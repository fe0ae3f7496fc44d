//! Payload operations as the autopilot exposes them: camera captures, the downlink
//! (`MAV_CMD_USER_1`, a sim-specific command), and the sampler on a servo.

use mavlink::dialects::ardupilotmega::*;

use super::commands::Cmd;
use super::Autopilot;
use crate::payload::{CaptureOutcome, DownlinkRun, SamplerEvent};
use crate::scenario::EventKind;

impl Autopilot {
    pub(super) fn start_capture(&mut self, count: u32, interval_s: f64) {
        for index in self.camera.start(self.now_ms, count, interval_s) {
            self.emit_event(EventKind::PictureStarted, i64::from(index));
        }
    }

    pub(super) fn set_servo(&mut self, servo: u8, pwm: u16) {
        if (1..=16).contains(&servo) {
            self.servos[usize::from(servo - 1)] = pwm;
        }
        if self.sampler.set_servo(servo, pwm, self.now_ms) {
            let text = if self.sampler.deployed_since_ms.is_some() {
                "Sampler deployed"
            } else {
                "Sampler retracted"
            };
            self.text(MavSeverity::MAV_SEVERITY_INFO, text);
        }
    }

    /// `MAV_CMD_USER_1`: p1 = 1 starts the downlink (p2 = MiB to send, 0 = everything stored),
    /// p1 = 0 stops it. Answered IN_PROGRESS, then progress, then ACCEPTED when all is sent, FAILED
    /// when the visibility window closes, CANCELLED when stopped.
    pub(super) fn downlink_command(&mut self, c: &Cmd) {
        if c.p[0] < 0.5 {
            if let Some(run) = self.downlink.take() {
                let to = run.requester;
                self.ack_to(
                    to,
                    MavCmd::MAV_CMD_USER_1,
                    MavResult::MAV_RESULT_CANCELLED,
                    run.progress_pct(),
                );
                self.text(
                    MavSeverity::MAV_SEVERITY_INFO,
                    &format!("Downlink stopped: {:.2} MiB sent", run.sent_mib),
                );
            }
            self.ack(c, MavResult::MAV_RESULT_ACCEPTED, 0);
            return;
        }
        if self.downlink.is_some() {
            self.ack(c, MavResult::MAV_RESULT_TEMPORARILY_REJECTED, 0);
            return;
        }
        if self.world.visibility(self.now_ms as f64 / 1000.0).is_none() {
            self.text(MavSeverity::MAV_SEVERITY_WARNING, "Downlink: no visibility");
            self.ack(c, MavResult::MAV_RESULT_DENIED, 0);
            return;
        }
        let stored = self.storage.used_mib;
        let to_send = if c.p[1] > 0.0 {
            f64::from(c.p[1]).min(stored)
        } else {
            stored
        };
        if to_send <= 0.0 {
            self.text(MavSeverity::MAV_SEVERITY_INFO, "Downlink: nothing to send");
            self.ack(c, MavResult::MAV_RESULT_ACCEPTED, 100);
            return;
        }
        self.downlink = Some(DownlinkRun {
            to_send_mib: to_send,
            sent_mib: 0.0,
            last_progress_ms: self.now_ms,
            requester: c.from,
        });
        self.emit_event(EventKind::DownlinkStarted, 0);
        self.text(MavSeverity::MAV_SEVERITY_INFO, "Downlink started");
        self.ack(c, MavResult::MAV_RESULT_IN_PROGRESS, 0);
    }

    pub(super) fn step_payload(&mut self) {
        for o in self.camera.step(self.now_ms, &mut self.storage) {
            let (index, failure) = match o {
                CaptureOutcome::Stored { index, .. } => {
                    self.pictures_ok += 1;
                    (index, None)
                }
                CaptureOutcome::Failed { index, reason } => {
                    self.pictures_failed += 1;
                    (index, Some(reason))
                }
            };
            self.report_picture(index, failure);
        }
        if let Some(ev) = self.sampler.step(self.now_ms, self.kin.is_still()) {
            let text = match ev {
                SamplerEvent::Collected(n) => format!("Sampler: sample {n} collected"),
                SamplerEvent::Lost => "Sampler: sample lost (vehicle moving)".to_string(),
            };
            self.text(MavSeverity::MAV_SEVERITY_INFO, &text);
        }
        self.step_downlink();
    }

    fn step_downlink(&mut self) {
        let Some(mut run) = self.downlink.take() else {
            return;
        };
        let to = run.requester;
        let Some(window_rate) = self.world.visibility(self.now_ms as f64 / 1000.0) else {
            self.ack_to(
                to,
                MavCmd::MAV_CMD_USER_1,
                MavResult::MAV_RESULT_FAILED,
                run.progress_pct(),
            );
            self.text(
                MavSeverity::MAV_SEVERITY_WARNING,
                &format!(
                    "Downlink interrupted: visibility lost, {:.2} MiB sent",
                    run.sent_mib
                ),
            );
            return;
        };
        let rate = self.downlink_rate_override.unwrap_or(window_rate);
        let dt = self.tick_ms as f64 / 1000.0;
        let chunk = (rate * dt)
            .min(run.to_send_mib - run.sent_mib)
            .min(self.storage.used_mib)
            .max(0.0);
        run.sent_mib += chunk;
        self.storage.used_mib -= chunk;
        if run.sent_mib >= run.to_send_mib - 1e-9 || self.storage.used_mib <= 1e-9 {
            self.ack_to(
                to,
                MavCmd::MAV_CMD_USER_1,
                MavResult::MAV_RESULT_ACCEPTED,
                100,
            );
            self.text(
                MavSeverity::MAV_SEVERITY_INFO,
                &format!("Downlink complete: {:.2} MiB sent", run.sent_mib),
            );
            return;
        }
        if self.now_ms >= run.last_progress_ms + 1000 {
            run.last_progress_ms = self.now_ms;
            self.ack_to(
                to,
                MavCmd::MAV_CMD_USER_1,
                MavResult::MAV_RESULT_IN_PROGRESS,
                run.progress_pct(),
            );
        }
        self.downlink = Some(run);
    }
}
