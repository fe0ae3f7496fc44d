//! Sim-time arithmetic for durations that come from outside (scenario files, MAVLink params):
//! negative or NaN durations count as 0 and sums saturate instead of overflowing.

/// Seconds to whole milliseconds.
pub fn secs_to_ms(secs: f64) -> u64 {
    // `as` saturates and maps NaN to 0.
    (secs.max(0.0) * 1000.0).round() as u64
}

/// `now_ms` plus `secs`.
pub fn later(now_ms: u64, secs: f64) -> u64 {
    now_ms.saturating_add(secs_to_ms(secs))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hostile_durations_neither_panic_nor_go_back() {
        assert_eq!(later(5, f64::NAN), 5);
        assert_eq!(later(5, -3.0), 5);
        assert_eq!(later(5, 1e300), u64::MAX);
        assert_eq!(later(1000, 1.5), 2500);
    }
}
