//! Payload: camera (picture sizes drawn within bounds, seeded) against a storage capacity, a
//! downlink that frees storage inside visibility windows, and a sampler on a servo.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::scenario::{CameraParams, SamplerParams};
use crate::time::secs_to_ms;

/// Most pictures one IMAGE_START_CAPTURE schedules (its count comes from outside).
pub const MAX_PICTURES_PER_REQUEST: u32 = 1000;

#[derive(Debug, Clone)]
pub struct Storage {
    pub capacity_mib: f64,
    pub used_mib: f64,
}

impl Storage {
    /// The camera's storage, empty.
    pub fn empty(camera: &CameraParams) -> Self {
        Self {
            capacity_mib: camera.storage_capacity_mib,
            used_mib: 0.0,
        }
    }

    pub fn available(&self) -> f64 {
        (self.capacity_mib - self.used_mib).max(0.0)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum CaptureOutcome {
    Stored { index: i32, size_mib: f64 },
    Failed { index: i32, reason: &'static str },
}

#[derive(Debug)]
pub struct Camera {
    params: CameraParams,
    rng: ChaCha8Rng,
    /// (due sim ms, image index, the size an injected fault imposes)
    pending: Vec<(u64, i32, Option<f64>)>,
    next_index: i32,
    /// Injected failures still to apply.
    pub fail_next: u32,
    /// Injected hangs still to apply: the capture is dropped without an outcome.
    pub hang_next: u32,
    /// Injected capture times (and image sizes) still to apply, in order.
    pub duration_next: Vec<(f64, Option<f64>)>,
    /// A capture hung: the camera says it is capturing until it is asked again.
    hung: bool,
}

impl Camera {
    pub fn new(params: &CameraParams, rng: ChaCha8Rng) -> Self {
        Self {
            params: params.clone(),
            rng,
            pending: Vec::new(),
            next_index: 0,
            fail_next: 0,
            hang_next: 0,
            duration_next: Vec::new(),
            hung: false,
        }
    }

    /// A restart: the captures under way are lost.
    pub fn cancel(&mut self) {
        self.pending.clear();
        self.hung = false;
    }

    /// A capture is under way (or hung).
    pub fn capturing(&self) -> bool {
        self.hung || !self.pending.is_empty()
    }

    /// Captures scheduled and not yet completed.
    pub fn pending(&self) -> usize {
        self.pending.len()
    }

    /// The index the next picture gets (= pictures triggered so far).
    pub fn next_index(&self) -> i32 {
        self.next_index
    }

    /// Schedules `count` pictures `interval_s` apart; returns their image indices.
    pub fn start(&mut self, now_ms: u64, count: u32, interval_s: f64) -> Vec<i32> {
        self.hung = false;
        let (capture_s, size) = if self.duration_next.is_empty() {
            (self.params.capture_time_s, None)
        } else {
            self.duration_next.remove(0)
        };
        let capture_ms = secs_to_ms(capture_s);
        let step_ms = secs_to_ms(interval_s);
        (0..count.clamp(1, MAX_PICTURES_PER_REQUEST))
            .map(|i| {
                let index = self.next_index;
                self.next_index += 1;
                self.pending.push((
                    now_ms
                        .saturating_add(capture_ms)
                        .saturating_add(u64::from(i).saturating_mul(step_ms)),
                    index,
                    size,
                ));
                index
            })
            .collect()
    }

    /// Completes the captures due at `now_ms`.
    pub fn step(&mut self, now_ms: u64, storage: &mut Storage) -> Vec<CaptureOutcome> {
        let mut out = Vec::new();
        let mut i = 0;
        while i < self.pending.len() {
            if self.pending[i].0 > now_ms {
                i += 1;
                continue;
            }
            let (_, index, imposed) = self.pending.remove(i);
            // Draw the size even on failure or when imposed, so that neither shifts later sizes.
            let drawn = self
                .rng
                .gen_range(self.params.size_min_mib..=self.params.size_max_mib);
            let size = imposed.unwrap_or(drawn);
            if self.hang_next > 0 {
                self.hang_next -= 1;
                self.hung = true;
                tracing::debug!(index, "camera: capture hangs");
            } else if self.fail_next > 0 {
                self.fail_next -= 1;
                out.push(CaptureOutcome::Failed {
                    index,
                    reason: "Camera: capture failed",
                });
            } else if storage.available() < size {
                out.push(CaptureOutcome::Failed {
                    index,
                    reason: "Camera: storage full",
                });
            } else {
                storage.used_mib += size;
                out.push(CaptureOutcome::Stored {
                    index,
                    size_mib: size,
                });
            }
        }
        out
    }
}

/// A running downlink.
#[derive(Debug, Clone)]
pub struct DownlinkRun {
    pub to_send_mib: f64,
    pub sent_mib: f64,
    pub last_progress_ms: u64,
    /// Who asked, for the COMMAND_ACKs that follow.
    pub requester: crate::autopilot::Sender,
}

impl DownlinkRun {
    pub fn progress_pct(&self) -> u8 {
        if self.to_send_mib <= 0.0 {
            100
        } else {
            ((self.sent_mib / self.to_send_mib) * 100.0).clamp(0.0, 100.0) as u8
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub enum SamplerEvent {
    Collected(u32),
    Lost,
}

#[derive(Debug, Clone)]
pub struct Sampler {
    pub params: SamplerParams,
    pub deployed_since_ms: Option<u64>,
    pub samples: u32,
    pub pwm: u16,
}

impl Sampler {
    pub fn new(params: &SamplerParams) -> Self {
        Self {
            params: params.clone(),
            deployed_since_ms: None,
            samples: 0,
            pwm: 1000,
        }
    }

    /// A servo output changed; returns true when it drives the sampler.
    pub fn set_servo(&mut self, servo: u8, pwm: u16, now_ms: u64) -> bool {
        if servo != self.params.servo {
            return false;
        }
        self.pwm = pwm;
        if pwm >= self.params.deploy_pwm {
            self.deployed_since_ms.get_or_insert(now_ms);
        } else {
            self.deployed_since_ms = None;
        }
        true
    }

    /// A sample is collected after `duration_s` deployed while still; moving loses it.
    pub fn step(&mut self, now_ms: u64, still: bool) -> Option<SamplerEvent> {
        let since = self.deployed_since_ms?;
        if !still {
            self.deployed_since_ms = Some(now_ms);
            return if now_ms > since {
                Some(SamplerEvent::Lost)
            } else {
                None
            };
        }
        if now_ms.saturating_sub(since) as f64 >= self.params.duration_s * 1000.0 {
            self.samples += 1;
            // Stay deployed: the next sample starts now.
            self.deployed_since_ms = Some(now_ms);
            return Some(SamplerEvent::Collected(self.samples));
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn picture_sizes_stay_within_bounds_and_fill_storage() {
        let p = CameraParams::default();
        let mut cam = Camera::new(&p, ChaCha8Rng::seed_from_u64(7));
        let mut st = Storage::empty(&p);
        cam.start(0, 10, 1.0);
        let out = cam.step(100_000, &mut st);
        assert_eq!(out.len(), 10);
        let mut stored = 0.0;
        for o in &out {
            if let CaptureOutcome::Stored { size_mib, .. } = o {
                assert!((p.size_min_mib..=p.size_max_mib).contains(size_mib));
                stored += size_mib;
            }
        }
        assert!((st.used_mib - stored).abs() < 1e-9);
        assert!(st.used_mib <= st.capacity_mib);
        assert!(out.iter().any(|o| matches!(
            o,
            CaptureOutcome::Failed {
                reason: "Camera: storage full",
                ..
            }
        )));
    }

    #[test]
    fn a_hung_capture_stores_nothing_and_answers_nothing() {
        let p = CameraParams::default();
        let mut cam = Camera::new(&p, ChaCha8Rng::seed_from_u64(3));
        let mut st = Storage::empty(&p);
        cam.hang_next = 1;
        cam.start(0, 2, 1.0);
        let out = cam.step(100_000, &mut st);
        // The first capture vanished; the second one is stored as usual.
        assert_eq!(out.len(), 1, "{out:?}");
        assert!(matches!(out[0], CaptureOutcome::Stored { index: 1, .. }));
        assert_eq!(cam.hang_next, 0);
    }

    #[test]
    fn an_injected_capture_time_and_size_apply_to_the_next_picture_only() {
        let p = CameraParams::default();
        let mut cam = Camera::new(&p, ChaCha8Rng::seed_from_u64(5));
        let mut st = Storage::empty(&p);
        cam.duration_next.push((3.0, Some(0.25)));
        cam.start(0, 1, 1.0);
        // Not yet due at 2.9 s, done at 3 s with the imposed size.
        assert!(cam.step(2_900, &mut st).is_empty());
        let out = cam.step(3_000, &mut st);
        assert_eq!(
            out,
            vec![CaptureOutcome::Stored {
                index: 0,
                size_mib: 0.25
            }]
        );
        // The next one is the camera's own again: its capture time, a size within bounds.
        cam.start(3_000, 1, 1.0);
        let due = 3_000 + secs_to_ms(p.capture_time_s);
        assert!(cam.step(due - 1, &mut st).is_empty());
        match cam.step(due, &mut st).as_slice() {
            [CaptureOutcome::Stored { size_mib, .. }] => {
                assert!((p.size_min_mib..=p.size_max_mib).contains(size_mib))
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_hostile_picture_count_is_capped() {
        let mut cam = Camera::new(&CameraParams::default(), ChaCha8Rng::seed_from_u64(1));
        let n = cam.start(u64::MAX - 5, u32::MAX, f64::MAX).len();
        assert_eq!(n, MAX_PICTURES_PER_REQUEST as usize);
    }

    #[test]
    fn sampler_collects_only_when_still() {
        let mut s = Sampler::new(&SamplerParams::default());
        assert!(s.set_servo(9, 1900, 0));
        assert_eq!(s.step(1000, false), Some(SamplerEvent::Lost));
        assert_eq!(s.step(5000, true), None);
        assert_eq!(s.step(6000, true), Some(SamplerEvent::Collected(1)));
        assert!(!s.set_servo(3, 1900, 0));
    }
}
