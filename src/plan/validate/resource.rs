//! Resources over time at the schedule. Unary: at most one `use` at a time, and only while the
//! availability profile gives it capacity. Reservoirs: the level from the initial level, productions,
//! consumptions and borrowings, taken in the worst case over the quantity intervals — minimum
//! production / maximum consumption and borrowing for the lower bound 0, the reverse for the upper bound
//! (the capacity available then) — and, within one instant, the worst order of the changes there (a
//! borrowing ending at t is returned first, as uses are half-open `[st, et[`).

use crate::model::{NumTerm, ResourceId, ResourceKind, ResourceSetup, Time, UsageKind};

use super::numeric::Iv;
use super::{Ctx, Violation};

/// One usage at the schedule.
struct Usage {
    who: String,
    kind: Kind,
    /// Quantity interval.
    q: Iv,
}

enum Kind {
    Use(Time, Time),
    Consume(Time),
    Produce(Time),
}

pub(super) fn check(cx: &Ctx, quantities: &[Vec<Iv>], out: &mut Vec<Violation>) {
    for (r, res) in cx.d.resources.iter().enumerate() {
        let rid = ResourceId::from_index(r);
        let mut usages = Vec::new();
        for (a, doms) in cx.s.actions.iter().zip(quantities) {
            for u in
                cx.d.task(a.task)
                    .usages
                    .iter()
                    .filter(|u| u.resource == rid)
            {
                let q = match u.quantity {
                    NumTerm::Const(c) => (c, c),
                    NumTerm::Var(v) => doms.get(v.index()).copied().unwrap_or((0.0, 0.0)),
                };
                let kind = match u.kind {
                    UsageKind::Use { from, to } => Kind::Use(cx.at(a, from), cx.at(a, to)),
                    UsageKind::Consume { at } => Kind::Consume(cx.at(a, at)),
                    UsageKind::Produce { at } => Kind::Produce(cx.at(a, at)),
                };
                usages.push(Usage {
                    who: cx.label(a),
                    kind,
                    q,
                });
            }
        }
        let fallback = ResourceSetup {
            level: res.capacity,
            profile: vec![(0, res.capacity)],
        };
        let setup = cx.p.resource(rid).unwrap_or(&fallback);
        match res.kind {
            ResourceKind::Unary => unary(&res.name, setup, &usages, out),
            ResourceKind::Reservoir => reservoir(&res.name, setup, &usages, out),
        }
    }
}

fn unary(name: &str, setup: &ResourceSetup, usages: &[Usage], out: &mut Vec<Violation>) {
    let uses: Vec<(Time, Time, &Usage)> = usages
        .iter()
        .filter_map(|u| match u.kind {
            Kind::Use(a, b) => Some((a, b.max(a), u)),
            _ => None,
        })
        .collect();
    for (i, &(a1, b1, u1)) in uses.iter().enumerate() {
        for &(a2, b2, u2) in &uses[i + 1..] {
            // Half-open intervals; an instantaneous use [a, a] occupies the instant a.
            let (s, e) = (a1.max(a2), b1.min(b2));
            let overlap = s < e
                || (a1 == b1 && a2 <= a1 && a1 < b2.max(a2 + 1))
                || (a2 == b2 && a1 <= a2 && a2 < b1.max(a1 + 1));
            if overlap {
                out.push(Violation::UnaryOverlap {
                    resource: name.to_string(),
                    first: u1.who.clone(),
                    second: u2.who.clone(),
                    time: s,
                });
            }
        }
        // Availability: the capacity at the start and at every profile step inside the use.
        let need = u1.q.1;
        let steps = std::iter::once(a1).chain(
            setup
                .profile
                .iter()
                .map(|&(t, _)| t)
                .filter(|&t| t > a1 && t < b1),
        );
        for t in steps {
            let capacity = setup.capacity_at(t);
            if capacity < need {
                out.push(Violation::ResourceUnavailable {
                    resource: name.to_string(),
                    action: u1.who.clone(),
                    time: t,
                    capacity,
                });
                break;
            }
        }
    }
}

/// A change of the worst-case levels at an instant: `rank` orders changes within the instant.
struct Step<'a> {
    time: Time,
    /// 0: a borrowing returned, 1: a decrease (consumption, borrowing starts), 2: a production.
    rank: u8,
    /// Change of the lowest possible level.
    low: f64,
    /// Change of the highest possible level.
    high: f64,
    who: &'a str,
}

fn reservoir(name: &str, setup: &ResourceSetup, usages: &[Usage], out: &mut Vec<Violation>) {
    let mut steps: Vec<Step> = Vec::new();
    for u in usages {
        let (qmin, qmax) = u.q;
        let who = u.who.as_str();
        match u.kind {
            Kind::Produce(t) => steps.push(Step {
                time: t,
                rank: 2,
                low: qmin,
                high: qmax,
                who,
            }),
            Kind::Consume(t) => steps.push(Step {
                time: t,
                rank: 1,
                low: -qmax,
                high: -qmin,
                who,
            }),
            Kind::Use(a, b) => {
                steps.push(Step {
                    time: a,
                    rank: 1,
                    low: -qmax,
                    high: -qmin,
                    who,
                });
                steps.push(Step {
                    time: b.max(a),
                    rank: 0,
                    low: qmax,
                    high: qmin,
                    who,
                });
            }
        }
    }
    steps.sort_by_key(|s| (s.time, s.rank));
    let (mut low, mut high) = (setup.level, setup.level);
    let eps = 1e-9;
    let mut below_reported = false;
    let mut above_reported = false;
    let initial_cap = setup.capacity_at(0);
    if high > initial_cap + eps {
        above_reported = true;
        out.push(Violation::ResourceOverCapacity {
            resource: name.to_string(),
            time: 0,
            level: high,
            capacity: initial_cap,
            culprit: "the initial level".into(),
        });
    }
    // Productions are applied after the decreases of the same instant for the lower level, and all
    // increases before the decreases for the upper level.
    let mut i = 0;
    while i < steps.len() {
        let t = steps[i].time;
        let group: Vec<&Step> = steps[i..].iter().take_while(|s| s.time == t).collect();
        i += group.len();
        let cap = setup.capacity_at(t);
        for s in group.iter().filter(|s| s.rank <= 1) {
            low += s.low;
            if low < -eps && !below_reported {
                below_reported = true;
                out.push(Violation::ResourceBelowZero {
                    resource: name.to_string(),
                    time: t,
                    level: low,
                    culprit: s.who.to_string(),
                });
            }
        }
        for s in group.iter().filter(|s| s.rank == 2) {
            low += s.low;
        }
        let mut high_mid = high;
        for s in group.iter().filter(|s| s.rank != 1) {
            high_mid += s.high;
            if high_mid > cap + eps && !above_reported {
                above_reported = true;
                out.push(Violation::ResourceOverCapacity {
                    resource: name.to_string(),
                    time: t,
                    level: high_mid,
                    capacity: cap,
                    culprit: s.who.to_string(),
                });
            }
        }
        high = group.iter().fold(high, |h, s| h + s.high);
    }
    // Capacity drops of the profile below a level reached earlier.
    if !above_reported {
        for &(t, cap) in &setup.profile {
            let level = level_high_at(setup.level, &steps, t);
            if level > cap + eps {
                out.push(Violation::ResourceOverCapacity {
                    resource: name.to_string(),
                    time: t,
                    level,
                    capacity: cap,
                    culprit: "a drop of the availability profile".into(),
                });
                break;
            }
        }
    }
}

/// The upper level after every change at or before `t`.
fn level_high_at(initial: f64, steps: &[Step], t: Time) -> f64 {
    steps
        .iter()
        .filter(|s| s.time <= t)
        .fold(initial, |h, s| h + s.high)
}
