//! Kinematic vehicle: bounded speed, acceleration and turn rate; AUV depth at a vertical speed.

use nalgebra::Vector2;

use crate::scenario::VehicleParams;

/// Where the autopilot wants to go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// [north, east] metres from home.
    pub pos: Vector2<f64>,
    /// Metres below the surface (AUV; 0 for a rover).
    pub depth: f64,
    pub speed: f64,
    /// Brake to arrive at rest (last waypoint, loiter, guided) rather than pass through.
    pub stop: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Kinematics {
    pub pos: Vector2<f64>,
    pub depth: f64,
    /// Radians, 0 = north, clockwise.
    pub heading: f64,
    pub speed: f64,
    pub vz: f64,
    /// A copter: depth is minus its altitude, never below the ground (else never above the surface).
    pub flies: bool,
}

impl Kinematics {
    /// Advances by `dt` seconds towards `target` (or brakes without one); `speed_factor` is the
    /// terrain's multiplier at the current position. Returns the distance travelled.
    pub fn step(
        &mut self,
        dt: f64,
        target: Option<&Target>,
        p: &VehicleParams,
        speed_factor: f64,
    ) -> f64 {
        let mut desired_speed = 0.0;
        let mut desired_vz = 0.0;
        if let Some(t) = target {
            let delta = t.pos - self.pos;
            let dist = delta.norm();
            if dist > 1e-3 {
                let want = delta.y.atan2(delta.x);
                let err = wrap_pi(want - self.heading);
                let max_turn = p.turn_rate_dps.to_radians() * dt;
                self.heading = wrap_pi(self.heading + err.clamp(-max_turn, max_turn));
                desired_speed = t.speed.min(p.max_speed_mps) * speed_factor;
                if t.stop {
                    desired_speed = desired_speed.min((2.0 * p.accel_mps2 * dist).sqrt());
                }
                // Slow down while pointing away from the target (skid-steer turn).
                desired_speed *= err.cos().max(0.0);
            }
            let dz = t.depth - self.depth;
            desired_vz = (dz / dt.max(1e-6)).clamp(-p.vertical_speed_mps, p.vertical_speed_mps);
        }
        let dv = p.accel_mps2 * dt;
        self.speed += (desired_speed - self.speed).clamp(-dv, dv);
        self.speed = self.speed.max(0.0);
        self.vz = desired_vz;
        let depth = self.depth + self.vz * dt;
        self.depth = if self.flies {
            depth.min(0.0)
        } else {
            depth.max(0.0)
        };
        let step = self.speed * dt;
        self.pos += Vector2::new(self.heading.cos(), self.heading.sin()) * step;
        step
    }

    pub fn is_still(&self) -> bool {
        self.speed < 0.05 && self.vz.abs() < 0.05
    }
}

pub fn wrap_pi(a: f64) -> f64 {
    let mut a = a % std::f64::consts::TAU;
    if a > std::f64::consts::PI {
        a -= std::f64::consts::TAU;
    } else if a < -std::f64::consts::PI {
        a += std::f64::consts::TAU;
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A surface target at [north, east] `pos`, to be reached at 5 m/s.
    fn target(north: f64, east: f64, stop: bool) -> Target {
        Target {
            pos: Vector2::new(north, east),
            depth: 0.0,
            speed: 5.0,
            stop,
        }
    }

    #[test]
    fn reaches_a_target_and_stops_within_bounds() {
        let p = VehicleParams::default();
        let mut k = Kinematics::default();
        let t = target(0.0, 50.0, true);
        let mut max_speed: f64 = 0.0;
        for _ in 0..(60 * 50) {
            k.step(0.02, Some(&t), &p, 1.0);
            max_speed = max_speed.max(k.speed);
        }
        assert!((k.pos - t.pos).norm() < p.wp_radius_m, "{:?}", k.pos);
        assert!(max_speed <= 5.0 + 1e-9);
        assert!(k.is_still());
    }

    #[test]
    fn slow_terrain_caps_speed() {
        let p = VehicleParams::default();
        let mut k = Kinematics::default();
        let t = target(1000.0, 0.0, false);
        for _ in 0..500 {
            k.step(0.02, Some(&t), &p, 0.2);
        }
        assert!((k.speed - 1.0).abs() < 1e-6, "{}", k.speed);
    }
}
