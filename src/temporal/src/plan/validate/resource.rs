//! Resources over time at the schedule. Unary: at most one `use` at a time, and only while the
//! availability profile gives it capacity. Reservoirs: the level from the initial level, productions,
//! consumptions and borrowings, taken in the worst case over the quantity intervals — minimum
//! production / maximum consumption and borrowing for the lower bound 0, the reverse for the upper bound
//! (the capacity available then) — and, within one instant, the worst order of the changes there (a
//! borrowing ending at t is returned first, as uses are half-open `[st, et[`).

use crate::model::{NumTerm, ResourceId, ResourceKind, ResourceSetup, Time, UsageKind};

use super::numeric::Iv;
use super::{Ctx, Violation};

pub use crate::model::LEVEL_TOLERANCE;

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
    /// A production; `true`: saturating (clipped at the capacity).
    Produce(Time, bool),
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
                    UsageKind::Produce { at } => Kind::Produce(cx.at(a, at), u.saturating),
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
    /// A saturating production: the levels it raises are clipped at the capacity.
    saturating: bool,
    who: &'a str,
}

fn reservoir(name: &str, setup: &ResourceSetup, usages: &[Usage], out: &mut Vec<Violation>) {
    let mut steps: Vec<Step> = Vec::new();
    for u in usages {
        let (qmin, qmax) = u.q;
        let who = u.who.as_str();
        match u.kind {
            Kind::Produce(t, saturating) => steps.push(Step {
                time: t,
                rank: 2,
                low: qmin,
                high: qmax,
                saturating,
                who,
            }),
            Kind::Consume(t) => steps.push(Step {
                time: t,
                rank: 1,
                low: -qmax,
                high: -qmin,
                saturating: false,
                who,
            }),
            Kind::Use(a, b) => {
                steps.push(Step {
                    time: a,
                    rank: 1,
                    low: -qmax,
                    high: -qmin,
                    saturating: false,
                    who,
                });
                steps.push(Step {
                    time: b.max(a),
                    rank: 0,
                    low: qmax,
                    high: qmin,
                    saturating: false,
                    who,
                });
            }
        }
    }
    steps.sort_by_key(|s| (s.time, s.rank));
    let (mut low, mut high) = (setup.level, setup.level);
    let eps = LEVEL_TOLERANCE;
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
            if s.saturating {
                low = low.min(cap);
            }
        }
        let mut high_mid = high;
        for s in group.iter().filter(|s| s.rank != 1) {
            high_mid += s.high;
            if s.saturating {
                high_mid = high_mid.min(cap);
            }
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
        high = group.iter().fold(high, |h, s| {
            if s.saturating {
                (h + s.high).min(cap)
            } else {
                h + s.high
            }
        });
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

#[cfg(test)]
mod tests {
    use super::*;

    fn u(who: &str, kind: Kind, q: Iv) -> Usage {
        Usage {
            who: who.into(),
            kind,
            q,
        }
    }

    fn setup(level: f64, profile: Vec<(Time, f64)>) -> ResourceSetup {
        ResourceSetup { level, profile }
    }

    fn run(s: &ResourceSetup, usages: &[Usage], unary_kind: bool) -> Vec<Violation> {
        let mut out = Vec::new();
        if unary_kind {
            unary("R", s, usages, &mut out);
        } else {
            reservoir("R", s, usages, &mut out);
        }
        out
    }

    /// The time of the only violation in `v` when it is an over-capacity.
    fn only_over_capacity(v: &[Violation]) -> Option<Time> {
        match v {
            [Violation::ResourceOverCapacity { time, .. }] => Some(*time),
            _ => None,
        }
    }

    #[test]
    fn reservoir_lower_bound_takes_the_maximum_consumption() {
        let s = setup(3.0, vec![(0, 3.0)]);
        let pics: Vec<Usage> = (0..4)
            .map(|i| u(&format!("p{i}"), Kind::Consume(i * 10), (0.8, 1.0)))
            .collect();
        // 3 × [0.8, 1] fits in 3 slots; a fourth may not (4 × 0.8 would, but the worst case is 4).
        assert!(run(&s, &pics[..3], false).is_empty());
        let v = run(&s, &pics, false);
        assert!(
            matches!(v.as_slice(), [Violation::ResourceBelowZero { time: 30, culprit, .. }] if culprit == "p3"),
            "{v:?}"
        );
        // A download producing [1, 2.4] before the fourth: its minimum, 1, is enough, and its maximum
        // cannot overflow (3 − 3 × 0.8 + 2.4 = 3); one producing up to 3 could.
        let mut with = pics;
        with.push(u("dl", Kind::Produce(25, false), (1.0, 2.4)));
        assert!(run(&s, &with, false).is_empty());
        if let Some(dl) = with.last_mut() {
            dl.q = (1.0, 3.0);
        }
        let v = run(&s, &with, false);
        assert!(
            matches!(v.as_slice(), [Violation::ResourceOverCapacity { time: 25, culprit, .. }] if culprit == "dl"),
            "{v:?}"
        );
    }

    #[test]
    fn a_saturating_production_is_clipped_at_the_capacity_and_never_overflows() {
        // Three pictures of [0.9, 1] then a download sending everything (3) and two more pictures: the
        // download cannot overflow, and after it the level is the capacity whatever the sizes were.
        let s = setup(3.0, vec![(0, 3.0)]);
        let mut us: Vec<Usage> = (0..3)
            .map(|i| u(&format!("p{i}"), Kind::Consume(i * 10), (0.9, 1.0)))
            .collect();
        us.push(u("dl", Kind::Produce(25, true), (3.0, 3.0)));
        us.extend((0..3).map(|i| u(&format!("q{i}"), Kind::Consume(30 + i * 10), (0.9, 1.0))));
        assert!(run(&s, &us, false).is_empty());
        // A fourth picture after the download runs out: the download refills to the capacity, no more.
        us.push(u("q3", Kind::Consume(60), (0.9, 1.0)));
        let v = run(&s, &us, false);
        assert!(
            matches!(v.as_slice(), [Violation::ResourceBelowZero { time: 60, culprit, .. }] if culprit == "q3"),
            "{v:?}"
        );
        // The same download, not saturating, may overflow.
        us.pop();
        if let Some(dl) = us.iter_mut().find(|x| x.who == "dl") {
            dl.kind = Kind::Produce(25, false);
        }
        let v = run(&s, &us, false);
        assert_eq!(only_over_capacity(&v), Some(25), "{v:?}");
    }

    #[test]
    fn f32_rounding_is_within_the_planners_tolerance_and_more_is_not() {
        // A card filled with f32 levels off the wire: 3.0000000477 is the planner's 3 (its envelope's
        // tolerance), so the checker agrees; a real overflow by a thousandth is still refused.
        let s = setup(3.0, vec![(0, 3.0)]);
        let near = f64::from(0.8f32) * 4.0 - 0.2;
        assert!(near > 3.0);
        let ok = [u("dl", Kind::Produce(5, false), (0.0, near - 3.0 + 0.0))];
        assert!(run(&s, &ok, false).is_empty(), "{:?}", run(&s, &ok, false));
        let over = setup(near, vec![(0, 3.0)]);
        assert!(run(&over, &[], false).is_empty());
        let bad = setup(3.001, vec![(0, 3.0)]);
        assert!(only_over_capacity(&run(&bad, &[], false)).is_some());
    }

    #[test]
    fn reservoir_upper_bound_takes_the_maximum_production_and_the_profile() {
        let s = setup(2.0, vec![(0, 3.0)]);
        let v = run(&s, &[u("dl", Kind::Produce(5, false), (1.0, 3.0))], false);
        assert!(
            matches!(v.as_slice(), [Violation::ResourceOverCapacity { level, capacity, .. }] if *level == 5.0 && *capacity == 3.0),
            "{v:?}"
        );
        let drop = setup(3.0, vec![(0, 3.0), (1_000, 2.0)]);
        let v = run(&drop, &[], false);
        assert_eq!(only_over_capacity(&v), Some(1_000), "{v:?}");
    }

    #[test]
    fn within_an_instant_decreases_come_before_productions_and_returns_before_borrowings() {
        let s = setup(0.0, vec![(0, 1.0)]);
        let v = run(
            &s,
            &[
                u("c", Kind::Consume(5), (1.0, 1.0)),
                u("p", Kind::Produce(5, false), (1.0, 1.0)),
            ],
            false,
        );
        assert!(
            matches!(v.as_slice(), [Violation::ResourceBelowZero { time: 5, .. }]),
            "{v:?}"
        );
        let full = setup(1.0, vec![(0, 1.0)]);
        let back_to_back = [
            u("a", Kind::Use(0, 10), (1.0, 1.0)),
            u("b", Kind::Use(10, 20), (1.0, 1.0)),
        ];
        assert!(run(&full, &back_to_back, false).is_empty());
        assert!(run(&full, &back_to_back, true).is_empty());
    }

    #[test]
    fn unary_uses_overlap_and_honour_the_availability_profile() {
        let s = setup(1.0, vec![(0, 1.0), (1_000, 0.0), (2_000, 1.0)]);
        let ok = [
            u("a", Kind::Use(0, 999), (1.0, 1.0)),
            u("b", Kind::Use(2_000, 2_500), (1.0, 1.0)),
        ];
        assert!(run(&s, &ok, true).is_empty());
        let v = run(&s, &[u("c", Kind::Use(900, 1_100), (1.0, 1.0))], true);
        assert!(
            matches!(
                v.as_slice(),
                [Violation::ResourceUnavailable { time: 1_000, .. }]
            ),
            "{v:?}"
        );
        let v = run(
            &s,
            &[
                u("a", Kind::Use(0, 500), (1.0, 1.0)),
                u("b", Kind::Use(499, 600), (1.0, 1.0)),
            ],
            true,
        );
        assert!(
            matches!(v.as_slice(), [Violation::UnaryOverlap { time: 499, .. }]),
            "{v:?}"
        );
    }
}
