//! A request to stop a mission from outside its loop (a signal): set from any thread, seen by
//! [`super::mission::run_mission`] before each cycle and, with a live pacer, while it waits.

use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Arc;

/// Shared by whoever asks (a signal handler) and the mission loop; clones share the request.
#[derive(Clone, Debug, Default)]
pub struct Interrupt(Arc<AtomicI32>);

impl Interrupt {
    /// Asks the mission to stop because of signal number `signal` (> 0). True for the first request; the
    /// first one is kept.
    pub fn request(&self, signal: i32) -> bool {
        self.0
            .compare_exchange(0, signal.max(1), Ordering::AcqRel, Ordering::Acquire)
            .is_ok()
    }

    /// The signal number of the request, if there was one.
    pub fn requested(&self) -> Option<i32> {
        Some(self.0.load(Ordering::Acquire)).filter(|&s| s != 0)
    }

    /// The name of the requested signal (`SIGTERM`), if there was a request.
    pub fn signal_name(&self) -> Option<String> {
        self.requested().map(signal_name)
    }
}

/// `SIGINT`, `SIGTERM`, … for a POSIX signal number (these numbers are the same on every Unix).
pub fn signal_name(signal: i32) -> String {
    match signal {
        1 => "SIGHUP".into(),
        2 => "SIGINT".into(),
        15 => "SIGTERM".into(),
        n => format!("signal {n}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_request_is_kept() {
        let i = Interrupt::default();
        assert_eq!(i.requested(), None);
        let seen = i.clone();
        assert!(i.request(15));
        assert!(!i.request(2));
        assert_eq!(seen.requested(), Some(15));
        assert_eq!(seen.signal_name().as_deref(), Some("SIGTERM"));
    }
}
