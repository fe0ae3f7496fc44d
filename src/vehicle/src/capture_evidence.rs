//! A picture's end from the camera's own account (CAMERA_CAPTURE_STATUS, polled), beside its
//! CAMERA_IMAGE_CAPTURED: over a lossy radio that one message may never arrive, while the camera's image
//! count says the picture was taken. Only statuses sent after the picture began count (a late or reordered
//! one may predate it); the first of them is the count before the picture.

/// What CAMERA_CAPTURE_STATUS said.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CaptureStatus {
    /// The vehicle's clock when sent (time_boot_ms).
    pub time_ms: u64,
    /// image_status: a capture in progress (1 or 3).
    pub capturing: bool,
    /// image_count: images captured so far.
    pub count: i32,
}

/// What the statuses show about the picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The image count went up: the picture was taken.
    Captured,
    /// The camera was capturing, is idle again, and its count did not move: no image.
    NoImage,
}

/// How often (vehicle ms) the status is asked for while the picture runs.
pub const POLL_MS: u64 = 1_000;

#[derive(Debug, Clone)]
pub struct CaptureEvidence {
    began_ms: u64,
    before: Option<i32>,
    seen_capturing: bool,
    last_poll_ms: u64,
}

impl CaptureEvidence {
    /// A picture began at `began_ms` (vehicle clock).
    pub fn new(began_ms: u64) -> Self {
        Self {
            began_ms,
            before: None,
            seen_capturing: false,
            last_poll_ms: began_ms,
        }
    }

    /// True when the status should be asked for again (and notes that it is).
    pub fn poll_due(&mut self, vnow: u64) -> bool {
        if vnow.saturating_sub(self.last_poll_ms) >= POLL_MS {
            self.last_poll_ms = vnow;
            return true;
        }
        false
    }

    /// A status received; a verdict once the statuses show one.
    pub fn observe(&mut self, s: CaptureStatus) -> Option<Verdict> {
        if s.time_ms < self.began_ms {
            return None;
        }
        let Some(before) = self.before else {
            self.before = Some(s.count);
            self.seen_capturing |= s.capturing;
            return None;
        };
        if s.count > before {
            return Some(Verdict::Captured);
        }
        if s.capturing {
            self.seen_capturing = true;
            return None;
        }
        self.seen_capturing.then_some(Verdict::NoImage)
    }

    /// A CAMERA_IMAGE_CAPTURED sent at `time_ms` is this picture's (not an earlier one's, late or doubled).
    pub fn is_current(&self, time_ms: u64) -> bool {
        time_ms >= self.began_ms
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn st(time_ms: u64, capturing: bool, count: i32) -> CaptureStatus {
        CaptureStatus {
            time_ms,
            capturing,
            count,
        }
    }

    #[test]
    fn the_count_going_up_is_a_picture_taken() {
        let mut e = CaptureEvidence::new(10_000);
        assert_eq!(
            e.observe(st(9_000, false, 1)),
            None,
            "sent before the picture began"
        );
        assert_eq!(e.observe(st(10_500, true, 2)), None, "the count before");
        assert_eq!(e.observe(st(12_000, true, 2)), None);
        assert_eq!(e.observe(st(18_500, false, 3)), Some(Verdict::Captured));
    }

    #[test]
    fn idle_again_without_an_image_is_no_image_but_idle_before_capturing_is_nothing() {
        let mut e = CaptureEvidence::new(0);
        assert_eq!(e.observe(st(100, false, 4)), None);
        assert_eq!(
            e.observe(st(1_100, false, 4)),
            None,
            "the command may still be on its way"
        );
        assert_eq!(e.observe(st(2_100, true, 4)), None);
        assert_eq!(e.observe(st(9_100, false, 4)), Some(Verdict::NoImage));
    }

    #[test]
    fn polls_once_a_second_of_vehicle_time() {
        let mut e = CaptureEvidence::new(5_000);
        assert!(!e.poll_due(5_999));
        assert!(e.poll_due(6_000));
        assert!(!e.poll_due(6_500));
        assert!(e.poll_due(7_000));
        assert!(!e.is_current(4_999));
        assert!(e.is_current(5_000));
    }
}
