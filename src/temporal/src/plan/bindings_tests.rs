//! The per-class index of inequalities ([`super::Bindings`]'s `ne_of`) against the definition it replaces:
//! a scan of every posted inequality, on random sequences of variables, equalities, inequalities, saves
//! and restores.

use proptest::prelude::*;

use super::*;

#[derive(Clone, Debug)]
enum Op {
    Var { objects: u32 },
    Unify { a: usize, b: usize },
    Bind { a: usize, object: u32 },
    Separate { a: usize, b: usize },
    Save,
    Restore { back: usize },
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        2 => (2u32..5).prop_map(|objects| Op::Var { objects }),
        3 => (0usize..64, 0usize..64).prop_map(|(a, b)| Op::Unify { a, b }),
        1 => (0usize..64, 0u32..5).prop_map(|(a, object)| Op::Bind { a, object }),
        3 => (0usize..64, 0usize..64).prop_map(|(a, b)| Op::Separate { a, b }),
        1 => Just(Op::Save),
        1 => (0usize..8).prop_map(|back| Op::Restore { back }),
    ]
}

/// The definition: some posted inequality joins the two classes.
fn has_ne_by_scan(b: &Bindings, x: u32, y: u32) -> bool {
    let (x, y) = (b.root(x), b.root(y));
    b.ne.iter().any(|&(p, q)| {
        let (p, q) = (b.root(p), b.root(q));
        (p == x && q == y) || (p == y && q == x)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn the_class_index_finds_the_inequalities_a_scan_finds(ops in prop::collection::vec(op(), 1..80)) {
        let mut b = Bindings::default();
        let mut levels: Vec<(Level, usize)> = Vec::new();
        let mut vars: Vec<VarId> = Vec::new();
        for op in ops {
            let pick = |i: usize, vars: &[VarId]| (!vars.is_empty()).then(|| vars[i % vars.len()]);
            match op {
                Op::Var { objects } => vars.push(b.new_var((0..objects).map(ObjectId).collect())),
                Op::Unify { a, b: c } => {
                    if let (Some(x), Some(y)) = (pick(a, &vars), pick(c, &vars)) {
                        let level = b.save();
                        if b.unify(STerm::Var(x), STerm::Var(y)).is_err() {
                            b.restore(level);
                        }
                    }
                }
                Op::Bind { a, object } => {
                    if let Some(x) = pick(a, &vars) {
                        let level = b.save();
                        if b.unify(STerm::Var(x), STerm::Obj(ObjectId(object))).is_err() {
                            b.restore(level);
                        }
                    }
                }
                Op::Separate { a, b: c } => {
                    if let (Some(x), Some(y)) = (pick(a, &vars), pick(c, &vars)) {
                        let level = b.save();
                        if b.separate(STerm::Var(x), STerm::Var(y)).is_err() {
                            b.restore(level);
                        }
                    }
                }
                Op::Save => levels.push((b.save(), vars.len())),
                Op::Restore { back } => {
                    if !levels.is_empty() {
                        let keep = levels.len().saturating_sub(back + 1);
                        let (level, n) = levels[keep];
                        levels.truncate(keep + 1);
                        b.restore(level);
                        vars.truncate(n);
                    }
                }
            }
            for x in 0..vars.len() as u32 {
                for y in 0..vars.len() as u32 {
                    prop_assert_eq!(b.has_ne(x, y), has_ne_by_scan(&b, x, y), "classes of {} and {}", x, y);
                }
            }
        }
    }
}
