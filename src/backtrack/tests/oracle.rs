//! Random changes, saves and restores on a small trailed store, checked against clones taken at each save.

use backtrack::{Backtrack, Level, Trail};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

/// A growable array of values, every change trailed.
#[derive(Clone, Debug, Default)]
struct Store {
    values: Vec<i32>,
    trail: Trail<Undo>,
}

#[derive(Clone, Debug)]
enum Undo {
    Pushed,
    Popped(i32),
    Set(usize, i32),
}

impl Store {
    fn push(&mut self, v: i32) {
        self.values.push(v);
        self.trail.push(Undo::Pushed);
    }

    fn pop(&mut self) {
        if let Some(v) = self.values.pop() {
            self.trail.push(Undo::Popped(v));
        }
    }

    fn set(&mut self, i: usize, v: i32) {
        if let Some(x) = self.values.get_mut(i) {
            self.trail.push(Undo::Set(i, *x));
            *x = v;
        }
    }

    fn save(&self) -> Level {
        self.trail.level()
    }

    fn restore(&mut self, level: Level) {
        let values = &mut self.values;
        self.trail.restore(level, |e| match e {
            Undo::Pushed => {
                values.pop();
            }
            Undo::Popped(v) => values.push(v),
            Undo::Set(i, old) => values[i] = old,
        });
    }
}

backtrack::impl_backtrack!(Store, Level);

#[derive(Clone, Debug)]
enum Op {
    Push(i32),
    Pop,
    Set(usize, i32),
    Save,
    /// Restore the saved level at this index (modulo the number held).
    Restore(usize),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        3 => any::<i32>().prop_map(Op::Push),
        1 => Just(Op::Pop),
        3 => (0usize..8, any::<i32>()).prop_map(|(i, v)| Op::Set(i, v)),
        2 => Just(Op::Save),
        2 => any::<usize>().prop_map(Op::Restore),
    ]
}

proptest! {
    // Seeded: the same sequences on every run.
    #![proptest_config(ProptestConfig { cases: 256, rng_seed: RngSeed::Fixed(19), ..ProptestConfig::default() })]

    #[test]
    fn restore_gives_back_the_state_saved(ops in prop::collection::vec(op(), 0..200)) {
        let mut store = Store::default();
        // The oracle: a clone of the values at each level still valid, oldest first.
        let mut saved: Vec<(Level, Vec<i32>)> = Vec::new();
        for op in ops {
            match op {
                Op::Push(v) => store.push(v),
                Op::Pop => store.pop(),
                Op::Set(i, v) => store.set(i, v),
                Op::Save => {
                    let level = Backtrack::save(&mut store);
                    saved.push((level, store.values.clone()));
                }
                Op::Restore(k) => {
                    if saved.is_empty() {
                        continue;
                    }
                    let k = k % saved.len();
                    Backtrack::restore(&mut store, saved[k].0);
                    prop_assert_eq!(&store.values, &saved[k].1);
                    prop_assert_eq!(store.save(), saved[k].0);
                    // The levels saved after the one restored are invalid now; it stays valid.
                    saved.truncate(k + 1);
                }
            }
        }
        store.restore(Level::ROOT);
        prop_assert!(store.values.is_empty());
        prop_assert!(store.trail.is_empty());
    }
}
