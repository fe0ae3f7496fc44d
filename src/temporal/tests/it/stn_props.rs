//! Property tests of the incremental STN against the Floyd–Warshall oracle, on random plan-like networks
//! driven by random sequences of add / tighten / execute / save / restore / remove / relax.

use mavtempo_temporal::stn::floyd_warshall::{solve, solve_constraints, Apsp};
use mavtempo_temporal::stn::{
    Constraint, ConstraintId, EdgeSource, Inconsistent, Level, Stn, Time, Timepoint, INF,
};
use proptest::prelude::*;

#[derive(Clone, Debug)]
enum Op {
    AddTimepoint,
    /// An action: a new start/end pair with a duration interval, after an existing timepoint.
    AddAction {
        after: usize,
        dmin: Time,
        dspan: Time,
    },
    Add {
        from: usize,
        to: usize,
        lb: Time,
        ub: Time,
    },
    Precedence {
        a: usize,
        b: usize,
    },
    Deadline {
        t: usize,
        at: Time,
    },
    Tighten {
        c: usize,
        lb: Time,
        ub: Time,
    },
    /// Executes at `lb + frac·(ub − lb)` (or past the bounds for frac > 100: expect a failure).
    Execute {
        t: usize,
        frac: u16,
    },
    Save,
    Restore {
        back: usize,
    },
    Remove {
        c: usize,
    },
    Relax {
        t: usize,
    },
}

fn lower() -> impl Strategy<Value = Time> {
    prop_oneof![4 => -30i64..60, 1 => Just(-INF)]
}

fn upper() -> impl Strategy<Value = Time> {
    prop_oneof![4 => -30i64..60, 1 => Just(INF)]
}

fn op() -> impl Strategy<Value = Op> {
    let ix = 0usize..64;
    prop_oneof![
        1 => Just(Op::AddTimepoint),
        4 => (ix.clone(), 1i64..20, 0i64..20).prop_map(|(after, dmin, dspan)| Op::AddAction { after, dmin, dspan }),
        4 => (ix.clone(), ix.clone(), lower(), upper()).prop_map(|(from, to, lb, ub)| Op::Add { from, to, lb, ub }),
        3 => (ix.clone(), ix.clone()).prop_map(|(a, b)| Op::Precedence { a, b }),
        2 => (ix.clone(), 0i64..120).prop_map(|(t, at)| Op::Deadline { t, at }),
        2 => (ix.clone(), lower(), upper()).prop_map(|(c, lb, ub)| Op::Tighten { c, lb, ub }),
        3 => (ix.clone(), 0u16..110).prop_map(|(t, frac)| Op::Execute { t, frac }),
        2 => Just(Op::Save),
        2 => (0usize..4).prop_map(|back| Op::Restore { back }),
        2 => ix.clone().prop_map(|c| Op::Remove { c }),
        1 => ix.prop_map(|t| Op::Relax { t }),
    ]
}

/// Everything observable, to check that failures and restores leave the network exactly as it was.
#[derive(Clone, Debug, PartialEq)]
struct Snapshot {
    bounds: Vec<(Time, Time)>,
    constraints: Vec<(ConstraintId, Constraint)>,
    executed: Vec<Option<Time>>,
}

fn snapshot(stn: &Stn) -> Snapshot {
    Snapshot {
        bounds: stn.timepoints().map(|t| (stn.lb(t), stn.ub(t))).collect(),
        constraints: stn.constraints().collect(),
        executed: stn.timepoints().map(|t| stn.executed_at(t)).collect(),
    }
}

fn tp(stn: &Stn, i: usize) -> Timepoint {
    stn.timepoints().nth(i % stn.num_timepoints()).unwrap()
}

/// Incremental bounds and on-demand distances equal the oracle's.
fn check_against_oracle(stn: &Stn) -> Result<(), TestCaseError> {
    let apsp: Apsp =
        solve(stn).ok_or_else(|| TestCaseError::fail("oracle: network inconsistent"))?;
    for t in stn.timepoints() {
        prop_assert_eq!(
            (stn.lb(t), stn.ub(t)),
            (apsp.lb(t), apsp.ub(t)),
            "bounds of {:?}",
            t
        );
    }
    for a in stn.timepoints() {
        // The one-search forms: every distance from a, and to a.
        let (from, to) = (stn.distances_from(a), stn.distances_to(a));
        for b in stn.timepoints() {
            prop_assert_eq!(
                from[b.index()],
                apsp.distance(a, b),
                "distances_from {:?}->{:?}",
                a,
                b
            );
            prop_assert_eq!(
                to[b.index()],
                apsp.distance(b, a),
                "distances_to {:?}->{:?}",
                b,
                a
            );
        }
        for b in stn.timepoints() {
            prop_assert_eq!(
                stn.distance(a, b),
                apsp.distance(a, b),
                "distance {:?}->{:?}",
                a,
                b
            );
            // The threshold form, around the true value and at the ordering thresholds.
            let d = apsp.distance(a, b);
            for limit in [d.saturating_sub(1), d, d.saturating_add(1), -1, 0, 1] {
                prop_assert_eq!(
                    stn.distance_below(a, b, limit),
                    d < limit,
                    "distance_below {:?}->{:?} limit {}",
                    a,
                    b,
                    limit
                );
            }
        }
    }
    Ok(())
}

/// A rejected addition: the oracle agrees it is inconsistent, the network is unchanged, and the reported
/// cycle is a closed chain of real edges (of `candidate` for `New`) with a negative total.
fn check_rejection(
    stn: &Stn,
    before: &Snapshot,
    candidate: Constraint,
    err: &Inconsistent,
) -> Result<(), TestCaseError> {
    prop_assert_eq!(&snapshot(stn), before, "failed call changed the network");
    let with = stn.constraints().map(|(_, k)| k).chain([candidate]);
    prop_assert!(
        solve_constraints(stn.num_timepoints(), with).is_none(),
        "oracle finds it consistent"
    );
    let cycle = &err.cycle;
    prop_assert!(!cycle.is_empty());
    prop_assert!(err.total() < 0, "cycle total {}", err.total());
    for (i, e) in cycle.iter().enumerate() {
        let next = &cycle[(i + 1) % cycle.len()];
        prop_assert_eq!(e.to, next.from, "cycle not closed at {}", i);
        let implied_by = |k: Constraint| {
            (k.from == e.from && k.to == e.to && k.ub < INF && k.ub <= e.weight)
                || (k.to == e.from && k.from == e.to && k.lb > -INF && -k.lb <= e.weight)
        };
        match e.source {
            EdgeSource::Constraint(c) => {
                prop_assert!(stn.is_active(c));
                prop_assert!(
                    implied_by(stn.constraint(c)),
                    "edge {:?} not from {:?}",
                    e,
                    c
                );
            }
            EdgeSource::New => {
                prop_assert!(implied_by(candidate), "edge {:?} not from the candidate", e)
            }
            EdgeSource::AfterOrigin => {
                prop_assert!(
                    e.to == stn.origin() && e.weight == 0,
                    "bad implicit edge {:?}",
                    e
                )
            }
        }
    }
    Ok(())
}

/// Adds `candidate`; on success the oracle agrees it is consistent, on failure see `check_rejection`.
fn add(stn: &mut Stn, k: Constraint) -> Result<Option<ConstraintId>, TestCaseError> {
    let before = snapshot(stn);
    match stn.add_constraint(k.from, k.to, k.lb, k.ub) {
        Ok(c) => Ok(Some(c)),
        Err(e) => check_rejection(stn, &before, k, &e).map(|_| None),
    }
}

fn run(ops: Vec<Op>) -> Result<(), TestCaseError> {
    let mut stn = Stn::new();
    let mut saved: Vec<(Level, Snapshot)> = Vec::new();
    for _ in 0..3 {
        stn.add_timepoint();
    }
    for op in ops {
        let o = stn.origin();
        match op {
            Op::AddTimepoint => {
                stn.add_timepoint();
            }
            Op::AddAction { after, dmin, dspan } => {
                let prev = tp(&stn, after);
                let (st, et) = (stn.add_timepoint(), stn.add_timepoint());
                add(
                    &mut stn,
                    Constraint {
                        from: st,
                        to: et,
                        lb: dmin,
                        ub: dmin + dspan,
                    },
                )?;
                add(
                    &mut stn,
                    Constraint {
                        from: prev,
                        to: st,
                        lb: 1,
                        ub: INF,
                    },
                )?;
            }
            Op::Add { from, to, lb, ub } => {
                let (from, to) = (tp(&stn, from), tp(&stn, to));
                add(&mut stn, Constraint { from, to, lb, ub })?;
            }
            Op::Precedence { a, b } => {
                let (a, b) = (tp(&stn, a), tp(&stn, b));
                add(
                    &mut stn,
                    Constraint {
                        from: a,
                        to: b,
                        lb: 1,
                        ub: INF,
                    },
                )?;
            }
            Op::Deadline { t, at } => {
                let t = tp(&stn, t);
                add(
                    &mut stn,
                    Constraint {
                        from: o,
                        to: t,
                        lb: 0,
                        ub: at,
                    },
                )?;
            }
            Op::Tighten { c, lb, ub } => {
                let all: Vec<_> = stn.constraints().collect();
                if all.is_empty() {
                    continue;
                }
                let (id, k) = all[c % all.len()];
                let before = snapshot(&stn);
                if let Err(e) = stn.tighten(id, lb, ub) {
                    let tightened = Constraint {
                        lb: k.lb.max(lb),
                        ub: k.ub.min(ub),
                        ..k
                    };
                    // The oracle sees the tightened constraint replace the old one.
                    let mut rest = stn.clone();
                    rest.remove_constraint(id);
                    check_rejection(&rest, &snapshot(&rest), tightened, &e)?;
                    prop_assert_eq!(&snapshot(&stn), &before);
                } else {
                    let k2 = stn.constraint(id);
                    prop_assert_eq!(
                        (k2.lb, k2.ub),
                        (k.lb.max(lb.max(-INF)), k.ub.min(ub.min(INF)))
                    );
                }
            }
            Op::Execute { t, frac } => {
                let t = tp(&stn, t);
                let (lb, ub) = (stn.lb(t), stn.ub(t));
                let at = lb + (ub.min(lb + 200) - lb) * frac as Time / 100;
                let before = snapshot(&stn);
                // The network is minimal: every value inside the bounds, and only those, can be executed.
                match stn.execute(t, at) {
                    Ok(_) => {
                        prop_assert!(lb <= at && at <= ub, "executed outside its bounds");
                        prop_assert!(stn.is_executed(t));
                        prop_assert_eq!(stn.executed_at(t), Some(at));
                        prop_assert_eq!((stn.lb(t), stn.ub(t)), (at, at));
                    }
                    Err(e) => {
                        prop_assert!(at > ub || at < lb, "rejected inside its bounds");
                        check_rejection(
                            &stn,
                            &before,
                            Constraint {
                                from: o,
                                to: t,
                                lb: at,
                                ub: at,
                            },
                            &e,
                        )?;
                    }
                }
            }
            Op::Save => {
                let level = stn.save();
                saved.push((level, snapshot(&stn)));
            }
            Op::Restore { back } => {
                if saved.is_empty() {
                    continue;
                }
                let keep = saved.len().saturating_sub(1 + back % saved.len());
                let (level, snap) = saved[keep].clone();
                saved.truncate(keep);
                stn.restore(level);
                prop_assert_eq!(
                    &snapshot(&stn),
                    &snap,
                    "restore did not give back the saved network"
                );
            }
            Op::Remove { c } => {
                let all: Vec<_> = stn.constraints().collect();
                if all.is_empty() {
                    continue;
                }
                let (id, _) = all[c % all.len()];
                stn.remove_constraint(id);
                prop_assert!(!stn.is_active(id));
            }
            Op::Relax { t } => {
                let t = tp(&stn, t);
                stn.relax_timepoint(t);
                prop_assert_eq!(stn.constraints_of(t).count(), 0);
                prop_assert!(!stn.is_executed(t) || t == o);
            }
        }
        check_against_oracle(&stn)?;
        let now = 40;
        let due: Vec<_> = stn.due(now).collect();
        let expected: Vec<_> = stn
            .timepoints()
            .filter(|&t| !stn.is_executed(t) && stn.lb(t) <= now)
            .collect();
        prop_assert_eq!(due, expected);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 192, ..ProptestConfig::default() })]

    #[test]
    fn incremental_network_equals_floyd_warshall(ops in prop::collection::vec(op(), 1..40)) {
        run(ops)?;
    }
}
