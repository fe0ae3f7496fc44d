//! Battery: drains with distance and time, recharges when still in a sunlit zone.

use crate::scenario::BatteryParams;

#[derive(Debug, Clone)]
pub struct Battery {
    pub pct: f64,
    /// mAh drawn since boot (BATTERY_STATUS.current_consumed).
    pub consumed_mah: f64,
    pub charging: bool,
    params: BatteryParams,
}

impl Battery {
    pub fn new(params: &BatteryParams) -> Self {
        Self {
            pct: params.initial_pct,
            consumed_mah: 0.0,
            charging: false,
            params: params.clone(),
        }
    }

    /// One step: `dist_m` driven during `dt` seconds; `recharge` when still in a sunlit zone.
    pub fn step(&mut self, dt: f64, dist_m: f64, recharge: bool) {
        let drain = self.params.drain_pct_per_km * dist_m / 1000.0
            + self.params.drain_pct_per_min * dt / 60.0;
        let gain = if recharge {
            self.params.recharge_pct_per_min * dt / 60.0
        } else {
            0.0
        };
        self.charging = recharge && self.pct < 100.0;
        self.consumed_mah += drain / 100.0 * self.params.capacity_mah;
        self.pct = (self.pct - drain + gain).clamp(0.0, 100.0);
    }

    /// A copter off the ground for `dt` seconds: hover power.
    pub fn hover(&mut self, dt: f64) {
        self.drop_by(self.params.hover_pct_per_min * dt / 60.0);
    }

    pub fn drop_by(&mut self, pct: f64) {
        self.consumed_mah += pct.max(0.0) / 100.0 * self.params.capacity_mah;
        self.pct = (self.pct - pct).clamp(0.0, 100.0);
    }

    /// 4S LiPo-like curve: 12.0 V empty .. 16.8 V full, in mV.
    pub fn voltage_mv(&self) -> u16 {
        (12_000.0 + 48.0 * self.pct).round() as u16
    }

    /// cA: higher while moving.
    pub fn current_ca(&self, speed: f64) -> i16 {
        (150.0 + 250.0 * speed).round().min(i16::MAX as f64) as i16
    }

    pub fn can_arm(&self) -> bool {
        self.pct >= self.params.arm_min_pct
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drains_with_distance_and_time_and_recharges() {
        let p = BatteryParams::default();
        let mut b = Battery::new(&p);
        b.step(60.0, 1000.0, false);
        let expect = p.initial_pct - p.drain_pct_per_km - p.drain_pct_per_min;
        assert!((b.pct - expect).abs() < 1e-9);
        let before = b.pct;
        b.step(60.0, 0.0, true);
        assert!(b.pct > before && b.charging);
        b.drop_by(500.0);
        assert_eq!(b.pct, 0.0);
        assert!(!b.can_arm());
    }
}
