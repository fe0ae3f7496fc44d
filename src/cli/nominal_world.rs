//! The built-in simulator's nominal world for a mission without a scenario: the simulated vehicle's card,
//! pictures, capture time, speed and battery follow the domain, the problem and the vehicle configuration,
//! so that a fault-free mission runs as planned. Only the downlink's windows stay the simulator's (always open). (The simulator's own defaults — a 12 MiB card, 2–4 MiB
//! pictures taken in 1 s, 5 m/s — are an ArduPilot-like vehicle's, not the domain's: a clean mission would
//! report more storage used than planned and pictures earlier than the domain allows, and be repaired.)

use crate::model::{Bound, Domain, NumConstraint, NumInterval, NumTerm, Problem, Task, UsageKind};
use crate::vehicle::config::{Binding, VehicleConfig};

/// The simulator's scenario for `problem` when none is given: its defaults, with what the domain and the
/// configuration say in place of the payload, motion and battery parameters they determine.
pub fn nominal_scenario(domain: &Domain, problem: &Problem, cfg: &VehicleConfig) -> sitl::Scenario {
    let mut s = sitl::Scenario::default();
    let storage = cfg
        .resources
        .storage
        .as_deref()
        .and_then(|n| domain.resource_id(n));
    let battery = cfg
        .resources
        .battery
        .as_deref()
        .and_then(|n| domain.resource_id(n));
    // The card: the problem's capacity, one domain unit a MiB (what the simulator reports as storage).
    if let Some(r) = storage {
        if let Some(setup) = problem.resources.get(r.index()) {
            s.camera.storage_capacity_mib = setup.capacity_at(0);
        }
    }
    for (name, binding) in &cfg.actions {
        let Some(task) = domain.task_id(name).map(|t| domain.task(t)) else {
            continue;
        };
        match binding {
            Binding::TakePicture { timeout_ms, .. } => {
                // A picture takes the middle of the domain's duration (within the binding's timeout):
                // neither earlier nor later than the plan allows.
                if let Some((lo, hi)) = duration_s(task) {
                    let timeout_s = *timeout_ms as f64 / 1000.0;
                    s.camera.capture_time_s = ((lo + hi) / 2.0).min(timeout_s * 0.9).max(lo);
                }
                if let Some((lo, hi)) = storage.and_then(|r| consumed(task, r)) {
                    s.camera.size_min_mib = lo;
                    s.camera.size_max_mib = hi;
                }
            }
            Binding::Move {
                speed_m_s,
                acceptance_radius_m,
                ..
            } => {
                s.vehicle.speed_mps = *speed_m_s;
                s.vehicle.max_speed_mps = s.vehicle.max_speed_mps.max(*speed_m_s);
                s.vehicle.wp_radius_m = *acceptance_radius_m;
                if let Some(per_m) = battery.and_then(|r| consumed_per_metre(task, r)) {
                    // The domain's units are percent when its capacity is 100; scaled otherwise.
                    let capacity = battery
                        .and_then(|r| problem.resources.get(r.index()))
                        .map_or(100.0, |b| b.capacity_at(0));
                    if capacity > 0.0 {
                        s.battery.drain_pct_per_km = per_m * 1000.0 * 100.0 / capacity;
                    }
                }
            }
            Binding::Download { .. } => {
                // A full card is sent in the middle of the domain's download duration.
                if let Some((lo, hi)) = duration_s(task).filter(|(lo, hi)| lo + hi > 0.0) {
                    s.camera.downlink_mib_per_s = s.camera.storage_capacity_mib / ((lo + hi) / 2.0);
                }
            }
            _ => {}
        }
    }
    if let Some(r) = battery {
        if let Some(b) = problem.resources.get(r.index()) {
            let capacity = b.capacity_at(0);
            if capacity > 0.0 {
                s.battery.initial_pct = (b.level / capacity * 100.0).clamp(0.0, 100.0);
                // The domain's tasks spend battery by what they do, not by the minute.
                s.battery.drain_pct_per_min = 0.0;
                s.battery.arm_min_pct = s.battery.arm_min_pct.min(s.battery.initial_pct / 2.0);
            }
        }
    }
    s
}

/// The task's duration bounds (`et - st`), seconds, when both are finite: the intersection of its
/// constraints between start and end (the loader adds `st <= et`, the domain writes the bounds).
fn duration_s(task: &Task) -> Option<(f64, f64)> {
    let whole = task
        .temporal
        .iter()
        .filter(|c| c.from == task.start && c.to == task.end);
    let lo = whole.clone().filter_map(|c| c.interval.min_ms()).max()?;
    let hi = whole.filter_map(|c| c.interval.max_ms()).min()?;
    (lo <= hi).then(|| (lo as f64 / 1000.0, hi as f64 / 1000.0))
}

/// What the task consumes of `r`, as bounds.
fn consumed(task: &Task, r: crate::model::ResourceId) -> Option<(f64, f64)> {
    let u = task
        .usages
        .iter()
        .find(|u| u.resource == r && matches!(u.kind, UsageKind::Consume { .. }))?;
    match u.quantity {
        NumTerm::Const(c) => Some((c, c)),
        NumTerm::Var(v) => bounds(&task.num_vars.get(v.index())?.domain),
    }
}

/// A consumption of `r` written `?q = ?dist * k` (or `k * ?dist`) with `?dist = distance(..)`: k per metre.
fn consumed_per_metre(task: &Task, r: crate::model::ResourceId) -> Option<f64> {
    let u = task
        .usages
        .iter()
        .find(|u| u.resource == r && matches!(u.kind, UsageKind::Consume { .. }))?;
    let NumTerm::Var(q) = u.quantity else {
        return None;
    };
    let is_distance = |v| {
        task.numeric
            .iter()
            .any(|c| matches!(c, NumConstraint::Distance { var, .. } if *var == v))
    };
    task.numeric.iter().find_map(|c| match c {
        NumConstraint::Product { var, a, b } if *var == q => match (a, b) {
            (NumTerm::Var(d), NumTerm::Const(k)) | (NumTerm::Const(k), NumTerm::Var(d))
                if is_distance(*d) =>
            {
                Some(*k)
            }
            _ => None,
        },
        _ => None,
    })
}

fn bounds(i: &NumInterval) -> Option<(f64, f64)> {
    let value = |b: Bound<f64>| match b {
        Bound::Closed(v) | Bound::Open(v) => Some(v),
        Bound::Inf => None,
    };
    Some((value(i.lb)?, value(i.ub)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rover domain with its demo configuration: the card is the problem's 3 slots, a picture 0.9 to 1
    /// slot taken in the middle of [5, 20] s, the speed the configuration's, 0.5 % per metre.
    #[test]
    fn the_rover_world_follows_its_domain_and_configuration() {
        let domain =
            crate::lang::parse_domain("rover.ixt", include_str!("../../domains/rover/rover.ixt"))
                .expect("rover domain");
        let problem = crate::lang::parse_problem(
            "fig2.ixt",
            include_str!("../../domains/rover/problems/fig2.ixt"),
            &domain,
        )
        .expect("fig2");
        let cfg = VehicleConfig::parse(
            include_str!("../../config/demo-rover.toml"),
            "demo-rover.toml",
        )
        .expect("config");
        let s = nominal_scenario(&domain, &problem, &cfg);
        assert_eq!(s.camera.storage_capacity_mib, 3.0);
        assert_eq!((s.camera.size_min_mib, s.camera.size_max_mib), (0.9, 1.0));
        assert_eq!(s.camera.capture_time_s, 12.5);
        assert_eq!(s.vehicle.speed_mps, 0.45);
        assert_eq!(s.battery.drain_pct_per_km, 500.0);
        assert_eq!(s.battery.initial_pct, 90.0);
        assert_eq!(s.battery.drain_pct_per_min, 0.0);
        // A full card (3 slots) in the middle of the download's [10, 40] s.
        assert_eq!(s.camera.downlink_mib_per_s, 3.0 / 25.0);
    }
}
