//! The matrix of paths ([`super::paths`]) against an independent oracle (Floyd–Warshall on the same
//! constraints), on random plan-like networks grown by additions and tightenings, with random saves,
//! restores (backtracking), removals (which drop the matrix) and rebuilds.

use proptest::prelude::*;

use super::floyd_warshall::solve;
use super::*;

#[derive(Clone, Debug)]
enum Op {
    /// An action: start and end with a duration interval, after an existing timepoint.
    Action {
        after: usize,
        dmin: Time,
        dspan: Time,
    },
    /// `a` before `b` (`b − a ≥ gap`).
    Precedence {
        a: usize,
        b: usize,
        gap: Time,
    },
    /// Any constraint between two timepoints (often inconsistent, then refused).
    Add {
        from: usize,
        to: usize,
        lb: Time,
        ub: Time,
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
    Save,
    Restore {
        back: usize,
    },
    Remove {
        c: usize,
    },
    Maintain,
}

fn op() -> impl Strategy<Value = Op> {
    let ix = 0usize..64;
    prop_oneof![
        4 => (ix.clone(), 1i64..20, 0i64..20).prop_map(|(after, dmin, dspan)| Op::Action { after, dmin, dspan }),
        4 => (ix.clone(), ix.clone(), 0i64..3).prop_map(|(a, b, gap)| Op::Precedence { a, b, gap }),
        3 => (ix.clone(), ix.clone(), -30i64..30, -10i64..60).prop_map(|(from, to, lb, ub)| Op::Add { from, to, lb, ub }),
        1 => (ix.clone(), 20i64..200).prop_map(|(t, at)| Op::Deadline { t, at }),
        2 => (ix.clone(), -5i64..10, 0i64..40).prop_map(|(c, lb, ub)| Op::Tighten { c, lb, ub }),
        3 => Just(Op::Save),
        2 => (0usize..3).prop_map(|back| Op::Restore { back }),
        1 => ix.prop_map(|c| Op::Remove { c }),
        1 => Just(Op::Maintain),
    ]
}

fn tp(stn: &Stn, i: usize) -> Timepoint {
    Timepoint((i % stn.num_timepoints()) as u32)
}

/// Every distance and ordering answer equals the oracle's.
fn check(stn: &Stn) -> Result<(), TestCaseError> {
    let apsp = solve(stn).ok_or_else(|| TestCaseError::fail("oracle: inconsistent"))?;
    for a in stn.timepoints() {
        let (from, to) = (stn.distances_from(a), stn.distances_to(a));
        for b in stn.timepoints() {
            let d = apsp.distance(a, b);
            prop_assert_eq!(stn.distance(a, b), d, "distance {:?}->{:?}", a, b);
            prop_assert_eq!(from[b.index()], d, "distances_from {:?}->{:?}", a, b);
            prop_assert_eq!(
                to[b.index()],
                apsp.distance(b, a),
                "distances_to {:?}<-{:?}",
                a,
                b
            );
            for limit in [d.saturating_sub(1), d, d.saturating_add(1), -1, 0, 1] {
                prop_assert_eq!(stn.distance_below(a, b, limit), d < limit);
            }
        }
    }
    Ok(())
}

fn run(ops: Vec<Op>) -> Result<(), TestCaseError> {
    let mut stn = Stn::new();
    stn.add_timepoint();
    stn.maintain_paths();
    prop_assert!(stn.has_paths());
    let mut saved: Vec<Level> = Vec::new();
    let mut kept = true;
    for op in ops {
        match op {
            Op::Action { after, dmin, dspan } => {
                let prev = tp(&stn, after);
                let (st, et) = (stn.add_timepoint(), stn.add_timepoint());
                stn.add_constraint(st, et, dmin, dmin + dspan).ok();
                stn.add_constraint(prev, st, 1, INF).ok();
            }
            Op::Precedence { a, b, gap } => {
                let (a, b) = (tp(&stn, a), tp(&stn, b));
                stn.add_constraint(a, b, gap, INF).ok();
            }
            Op::Add { from, to, lb, ub } => {
                let (from, to) = (tp(&stn, from), tp(&stn, to));
                stn.add_constraint(from, to, lb, ub).ok();
            }
            Op::Deadline { t, at } => {
                let t = tp(&stn, t);
                stn.add_constraint(stn.origin(), t, 0, at).ok();
            }
            Op::Tighten { c, lb, ub } => {
                let all: Vec<ConstraintId> = stn.constraints().map(|(id, _)| id).collect();
                if let Some(&id) = all.get(c % all.len().max(1)) {
                    stn.tighten(id, lb, ub).ok();
                }
            }
            Op::Save => saved.push(stn.save()),
            Op::Restore { back } => {
                if !saved.is_empty() {
                    let keep = saved.len().saturating_sub(1 + back % saved.len());
                    let level = saved[keep];
                    saved.truncate(keep + 1);
                    stn.restore(level);
                }
            }
            Op::Remove { c } => {
                let all: Vec<ConstraintId> = stn.constraints().map(|(id, _)| id).collect();
                if let Some(&id) = all.get(c % all.len().max(1)) {
                    stn.remove_constraint(id);
                    prop_assert!(!stn.has_paths(), "a removal drops the matrix");
                    kept = false;
                }
            }
            Op::Maintain => {
                stn.maintain_paths();
                prop_assert!(stn.has_paths());
                kept = true;
            }
        }
        // Only a removal, or a restore below the level the matrix was built at, drops it.
        if kept && saved.is_empty() {
            prop_assert!(stn.has_paths());
        }
        check(&stn)?;
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 160, ..ProptestConfig::default() })]

    #[test]
    fn matrix_of_paths_equals_floyd_warshall(ops in prop::collection::vec(op(), 1..60)) {
        run(ops)?;
    }
}

/// A network grown past the matrix's first capacities (rows re-indexed with their undo records), then
/// restored step by step back to its root: every intermediate state equals the oracle's.
#[test]
fn a_growing_matrix_restores_through_its_reallocations() {
    let mut stn = Stn::new();
    stn.maintain_paths();
    let mut levels = Vec::new();
    let mut prev = stn.origin();
    for i in 0..40 {
        levels.push(stn.save());
        let (st, et) = (stn.add_timepoint(), stn.add_timepoint());
        stn.add_constraint(st, et, 5 + i % 7, 20).unwrap();
        stn.add_precedence(prev, st).unwrap();
        if i % 3 == 0 {
            // A tightening lowers an existing path's edges: earlier pairs improve.
            let c = stn.constraints().map(|(c, _)| c).nth(i as usize).unwrap();
            stn.tighten(c, 1, 50).unwrap();
        }
        prev = et;
    }
    assert!(stn.has_paths());
    assert!(stn.num_timepoints() > 64);
    check(&stn).unwrap();
    while let Some(level) = levels.pop() {
        stn.restore(level);
        assert!(stn.has_paths());
        check(&stn).unwrap();
    }
    assert_eq!(stn.num_timepoints(), 1);
}
