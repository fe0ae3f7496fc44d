//! The ground station's goals: a seeded Poisson process of uploads over the mission, each goal with a random
//! target among the scenario's and a random start window after its arrival.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::model::Time;
use crate::vehicle::{Enu, GoalKind, GoalLocation, GoalRequest};

/// A goal the ground station may ask for: its kind and the place it is about.
#[derive(Clone, Debug)]
pub struct Target {
    pub kind: GoalKind,
    pub place: String,
    pub at: Enu,
}

/// How goals arrive.
#[derive(Clone, Debug)]
pub struct ArrivalModel {
    /// Mean number of goals per hour (the Poisson rate).
    pub per_hour: f64,
    /// Arrivals in `[0, until_ms[` (ms after the origin).
    pub until_ms: Time,
    /// The start window opens between 0 and this long after the arrival…
    pub max_delay_ms: Time,
    /// …and stays open between these two durations.
    pub width_ms: (Time, Time),
    /// d_achiev announced with the goal.
    pub achieve_ms: Time,
    /// Every window closes by then (the mission's horizon).
    pub horizon_ms: Time,
}

/// One upload: the time it arrives and its goal.
#[derive(Clone, Debug)]
pub struct Arrival {
    pub at_ms: Time,
    pub goal: GoalRequest,
}

/// The arrivals of one seeded run, in time order, named `g1`, `g2`, ...
pub fn arrivals(model: &ArrivalModel, targets: &[Target], rng: &mut ChaCha8Rng) -> Vec<Arrival> {
    let mut out = Vec::new();
    if targets.is_empty() || model.per_hour <= 0.0 {
        return out;
    }
    let mean_gap_ms = 3_600_000.0 / model.per_hour;
    let mut t = 0.0;
    loop {
        // Exponential inter-arrival times: a Poisson process.
        let u: f64 = rng.gen_range(f64::EPSILON..1.0);
        t += -u.ln() * mean_gap_ms;
        if t >= model.until_ms as f64 {
            return out;
        }
        let at_ms = t as Time;
        let target = &targets[rng.gen_range(0..targets.len())];
        let open = at_ms + rng.gen_range(0..=model.max_delay_ms.max(0));
        let close =
            (open + rng.gen_range(model.width_ms.0..=model.width_ms.1)).min(model.horizon_ms);
        let s = |ms: Time| ms as f64 / 1000.0;
        out.push(Arrival {
            at_ms,
            goal: GoalRequest {
                name: format!("g{}", out.len() + 1),
                kind: target.kind,
                proposition: format!("{}({})", target.kind.predicate(), target.place),
                location: Some(GoalLocation {
                    name: target.place.clone(),
                    new: false,
                    at: target.at,
                    lat: 0.0,
                    lon: 0.0,
                }),
                priority: rng.gen_range(1..=3),
                start_window_s: (s(open), s(close.max(open))),
                duration_s: (0.0, 0.0),
                d_achiev_s: s(model.achieve_ms),
            },
        });
    }
}
