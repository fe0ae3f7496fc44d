//! The flaw candidates of one kind (threat or unary pairs) with the indices of those not resolved yet, so that
//! a flaw pass costs the number of pending candidates, not the number ever recorded: in a plan of n actions
//! on one attribute there are ~n² (event, link) pairs, nearly all resolved for good once ordered, and the
//! executive asks for the flaws several times a cycle.
//!
//! `pending` always holds every index whose candidate is not done, in increasing order (so flaws come out
//! in the order the candidates were recorded, as the planner's choices expect); it may also hold indices of
//! done candidates until the next [`CandidateSet::pending`] sweep drops them.

use super::Candidate;

#[derive(Clone, Debug)]
pub(crate) struct CandidateSet<A, B> {
    items: Vec<Candidate<A, B>>,
    pending: Vec<usize>,
    /// Indices were reopened out of order (trail restore): sort before the next sweep.
    unsorted: bool,
}

impl<A: Copy, B: Copy> CandidateSet<A, B> {
    pub fn new() -> Self {
        CandidateSet {
            items: Vec::new(),
            pending: Vec::new(),
            unsorted: false,
        }
    }

    pub fn len(&self) -> usize {
        self.items.len()
    }

    pub fn get(&self, i: usize) -> Candidate<A, B> {
        self.items[i]
    }

    pub fn push(&mut self, a: A, b: B) {
        self.pending.push(self.items.len());
        self.items.push(Candidate { a, b, done: false });
    }

    pub fn clear(&mut self) {
        self.items.clear();
        self.pending.clear();
        self.unsorted = false;
    }

    pub fn set_done(&mut self, i: usize) {
        self.items[i].done = true;
    }

    /// Undoes [`Self::set_done`] (trail restore).
    pub fn reopen(&mut self, i: usize) {
        if self.items[i].done {
            self.items[i].done = false;
            self.pending.push(i);
            self.unsorted = true;
        }
    }

    /// Forgets the candidates recorded at or after `len` (trail restore).
    pub fn truncate(&mut self, len: usize) {
        self.items.truncate(len);
        if self.unsorted {
            self.pending.retain(|&i| i < len);
        } else {
            let keep = self.pending.partition_point(|&i| i < len);
            self.pending.truncate(keep);
        }
    }

    /// The indices of the candidates not done, in increasing order (drops the done ones from the list).
    pub fn pending(&mut self) -> Vec<usize> {
        if self.unsorted {
            self.pending.sort_unstable();
            self.pending.dedup();
            self.unsorted = false;
        }
        let items = &self.items;
        self.pending.retain(|&i| !items[i].done);
        self.pending.clone()
    }
}
