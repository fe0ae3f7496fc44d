//! The novelty of a state (Lipovetzky & Geffner, "Best-First Width Search", AAAI 2017): 1 when it makes
//! true an atom that no state before it in its partition had, 2 when it only makes true a new *pair* of
//! atoms, 3 otherwise. Partitioned by a heuristic value, it tells apart the states of a plateau that
//! h_FF cannot: a search that tries the novel ones first explores the plateau broadly instead of deep
//! along one branch, which is how width-based search escapes the plateaus of stacking domains.

use std::collections::HashMap;

use super::{AtomId, State};

/// Above this many atoms only single atoms are tracked (the pair table of a partition has n² bits).
const MAX_PAIR_ATOMS: usize = 1024;

/// The atoms and pairs of atoms seen so far, per partition.
#[derive(Clone, Debug)]
pub struct Novelty {
    n_atoms: usize,
    /// Per partition: one bit per atom, then (when tracked) one per ordered pair `a < b` at `a·n + b`.
    seen: HashMap<u32, Vec<u64>>,
    atoms: Vec<usize>,
}

impl Novelty {
    pub fn new(n_atoms: usize) -> Self {
        Novelty {
            n_atoms,
            seen: HashMap::new(),
            atoms: Vec::new(),
        }
    }

    /// The novelty (1, 2 or 3) of `state` in `partition`, recording its atoms and pairs there. Only the
    /// pairs with one of `added` (what the action reaching it made true) are looked at: the others were
    /// true together before it, and looking at every pair of a state costs more than evaluating it.
    pub fn measure(&mut self, partition: u32, state: &State, added: &[AtomId]) -> u32 {
        let n = self.n_atoms;
        let pairs = n <= MAX_PAIR_ATOMS;
        let bits = if pairs { n + n * n } else { n };
        let table = self
            .seen
            .entry(partition)
            .or_insert_with(|| vec![0; bits.div_ceil(64)]);
        self.atoms.clear();
        self.atoms.extend((0..n).filter(|&a| state.has(a as u32)));
        let mut mark = |i: usize| -> bool {
            let (w, b) = (i / 64, 1u64 << (i % 64));
            match table.get_mut(w) {
                Some(x) if *x & b == 0 => {
                    *x |= b;
                    true
                }
                _ => false,
            }
        };
        let mut new_atom = false;
        for &a in &self.atoms {
            new_atom |= mark(a);
        }
        let mut new_pair = false;
        if pairs {
            for a in added.iter().map(|&a| a as usize).filter(|&a| a < n) {
                if !state.has(a as AtomId) {
                    continue;
                }
                for &b in self.atoms.iter().filter(|&&b| b != a) {
                    new_pair |= mark(n + a.min(b) * n + a.max(b));
                }
            }
        }
        if new_atom {
            1
        } else if new_pair {
            2
        } else {
            3
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The novelty of the state of `atoms`, all of them made true by the last action.
    fn measure(nov: &mut Novelty, partition: u32, n: usize, atoms: &[u32]) -> u32 {
        nov.measure(partition, &state(n, atoms), atoms)
    }

    fn state(n: usize, atoms: &[u32]) -> State {
        let mut s = State::empty(n);
        for &a in atoms {
            s.set(a, true);
        }
        s
    }

    #[test]
    fn new_atoms_then_new_pairs_then_nothing_new_per_partition() {
        let mut nov = Novelty::new(4);
        assert_eq!(measure(&mut nov, 5, 4, &[0, 1]), 1);
        assert_eq!(measure(&mut nov, 5, 4, &[2, 3]), 1);
        // Atoms 0 and 2 are known, but never together.
        assert_eq!(measure(&mut nov, 5, 4, &[0, 2]), 2);
        assert_eq!(measure(&mut nov, 5, 4, &[0, 2]), 3);
        assert_eq!(measure(&mut nov, 5, 4, &[1]), 3);
        // Another partition has seen nothing.
        assert_eq!(measure(&mut nov, 4, 4, &[0, 2]), 1);
    }

    #[test]
    fn only_the_pairs_with_an_atom_just_made_true_count() {
        let mut nov = Novelty::new(3);
        assert_eq!(measure(&mut nov, 0, 3, &[0]), 1);
        assert_eq!(measure(&mut nov, 0, 3, &[1]), 1);
        // 0 and 1 never were true together, but the action made neither true.
        assert_eq!(nov.measure(0, &state(3, &[0, 1]), &[]), 3);
        assert_eq!(nov.measure(0, &state(3, &[0, 1]), &[1]), 2);
        // Added but not true in the state (deleted again by the end): no pair.
        assert_eq!(nov.measure(0, &state(3, &[0, 1]), &[2]), 3);
    }

    #[test]
    fn without_the_pair_table_only_new_atoms_count() {
        let n = MAX_PAIR_ATOMS + 1;
        let mut nov = Novelty::new(n);
        assert_eq!(measure(&mut nov, 0, n, &[0, 1]), 1);
        assert_eq!(measure(&mut nov, 0, n, &[2, 3]), 1);
        assert_eq!(measure(&mut nov, 0, n, &[0, 2]), 3);
        assert_eq!(measure(&mut nov, 0, n, &[n as u32 - 1]), 1);
    }
}
