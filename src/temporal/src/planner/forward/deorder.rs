//! Deordering a sequential plan (Bäckström; Kambhampati & Kedar's explanation-based generalisation of
//! plans): two steps stay ordered only where one changes an atom the other reads or changes. Per atom the
//! last step that changed it precedes every later step that touches it, and the steps that read it since
//! its last change precede the next step that changes it; the transitive closure of these precedences
//! orders every interfering pair as in the sequence, and steps with nothing in common are left free to
//! overlap. Each atom's sequence of values is then the sequential plan's, so every condition still holds.

use std::collections::HashMap;

use super::{AtomId, GroundTask};

/// The precedences `(i, j)` (step `i` ends before step `j` starts, `i < j`) of the deordered plan of
/// `steps` (indices into `task.actions`), without duplicates.
pub fn precedences(task: &GroundTask, steps: &[u32]) -> Vec<(usize, usize)> {
    let mut last_writer: HashMap<AtomId, usize> = HashMap::new();
    let mut readers: HashMap<AtomId, Vec<usize>> = HashMap::new();
    let mut out: Vec<(usize, usize)> = Vec::new();
    for (j, &s) in steps.iter().enumerate() {
        let Some(a) = task.actions.get(s as usize) else {
            continue;
        };
        let mut writes: Vec<AtomId> = a.writes(task.atoms.len());
        writes.sort_unstable();
        writes.dedup();
        let mut reads: Vec<AtomId> = a.reads(task.atoms.len());
        reads.retain(|x| writes.binary_search(x).is_err());
        reads.sort_unstable();
        reads.dedup();
        for x in reads.iter().chain(&writes) {
            if let Some(&w) = last_writer.get(x) {
                out.push((w, j));
            }
        }
        for x in &writes {
            for r in readers.remove(x).unwrap_or_default() {
                out.push((r, j));
            }
            last_writer.insert(*x, j);
        }
        for x in reads {
            readers.entry(x).or_default().push(j);
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::super::{Cond, GroundAction, Happening};
    use super::*;

    fn act(pre: &[AtomId], add: &[AtomId], del: &[AtomId]) -> GroundAction {
        GroundAction {
            name: "a".into(),
            args: Vec::new(),
            start: Happening {
                pre: Cond {
                    pos: pre.to_vec(),
                    ..Cond::default()
                },
                add: add.to_vec(),
                del: del.to_vec(),
                ..Happening::default()
            },
            over_all: Cond::default(),
            end: Happening::default(),
            duration: None,
        }
    }

    #[test]
    fn only_interfering_steps_stay_ordered() {
        // 0: makes p; 1: makes q (independent of 0); 2: reads p, deletes r; 3: reads r... after 2 it is
        // false in the sequence, so 3 must be a step that re-adds r: it follows 2 (both change r).
        let task = GroundTask {
            atoms: vec!["p".into(), "q".into(), "r".into()],
            init: vec![2],
            goal: Cond::default(),
            actions: vec![
                act(&[], &[0], &[]),
                act(&[], &[1], &[]),
                act(&[0, 2], &[], &[2]),
                act(&[], &[2], &[]),
            ],
            ..GroundTask::default()
        };
        assert_eq!(precedences(&task, &[0, 1, 2, 3]), vec![(0, 2), (2, 3)]);
    }
}
