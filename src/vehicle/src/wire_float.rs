//! MAVLink carries levels and goal parameters as f32; the planner and its checker compute in f64. Widening
//! an f32 bit for bit turns 0.9 into 0.8999999761581421 and a full 3-slot card into 3.0000000477 — a level
//! the checker finds over the capacity. An f32 from the wire is read as the decimal it was written from (its
//! shortest representation), the same value on both sides.

/// The f64 of the shortest decimal that reads back as `x` (non-finite values unchanged).
pub fn widen(x: f32) -> f64 {
    if !x.is_finite() {
        return f64::from(x);
    }
    // Display gives the shortest round-trip decimal; it always parses.
    x.to_string().parse().unwrap_or(f64::from(x))
}

#[cfg(test)]
mod tests {
    use super::widen;

    #[test]
    fn decimals_survive_the_f32_wire() {
        assert_eq!(widen(0.9), 0.9);
        // Bit for bit, four pictures of 0.8 would fill 3.2000000477 slots.
        assert_eq!(widen(0.8) * 4.0, 3.2);
        assert_ne!(f64::from(0.8f32) * 4.0, 3.2);
        assert_eq!(widen(1e-3), 1e-3);
        assert!(widen(f32::NAN).is_nan());
        assert_eq!(widen(f32::INFINITY), f64::INFINITY);
        assert_eq!(widen(f32::MAX), 3.4028235e38);
    }
}
