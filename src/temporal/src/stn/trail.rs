//! The STN's undo entries: every change is recorded on the network's [`Trail`](backtrack::Trail) so that
//! `restore(level)` can undo everything after `level`.

use super::network::Stn;
use super::{ConstraintId, Level, Time};

#[derive(Clone, Debug)]
pub(crate) enum Entry {
    /// Old lower bound of a timepoint.
    Lb(u32, Time),
    /// Old upper bound of a timepoint.
    Ub(u32, Time),
    AddTimepoint,
    AddConstraint,
    Remove(u32),
    /// Old bounds of a tightened constraint.
    Weights(u32, Time, Time),
    /// Old execution marker of a timepoint.
    Executed(u32, Option<ConstraintId>),
    /// A batch of undo records of the matrix of paths ([`super::paths`]): its undo log's length before.
    Paths(u32),
}

impl Stn {
    /// The current trail level.
    pub fn save(&mut self) -> Level {
        self.paths_saved();
        self.trail.level()
    }

    /// Undoes everything done after `level` (bounds, constraints, timepoints, executions, removals).
    /// Timepoints and constraints created after `level` no longer exist; their identifiers will be reused.
    /// Restoring a level above the current one does nothing.
    pub fn restore(&mut self, level: Level) {
        self.paths_restoring(level);
        while self.log.last().is_some_and(|e| e.at > level) {
            self.log.pop();
        }
        while let Some(entry) = self.trail.pop_after(level) {
            self.undo(entry);
        }
        self.paths_restored();
    }

    fn undo(&mut self, entry: Entry) {
        match entry {
            Entry::Lb(t, old) => self.lb[t as usize] = old,
            Entry::Ub(t, old) => self.ub[t as usize] = old,
            Entry::AddTimepoint => {
                self.lb.pop();
                self.ub.pop();
                self.out.pop();
                self.inc.pop();
                self.wout.pop();
                self.executed.pop();
                self.paths_pop_timepoint();
            }
            Entry::AddConstraint => {
                if let Some(d) = self.cons.pop() {
                    // Pushed as out[from], inc[to], out[to], inc[from]: pop in reverse.
                    self.inc[d.from as usize].pop();
                    self.out[d.to as usize].pop();
                    self.inc[d.to as usize].pop();
                    self.out[d.from as usize].pop();
                    self.wout[d.to as usize].pop();
                    self.wout[d.from as usize].pop();
                }
            }
            Entry::Remove(c) => {
                // An edge comes back that no logged stamp covers: forget every proof.
                self.cons[c as usize].active = true;
                self.sync_edges(c);
                self.memo.clear();
                self.paths_drop();
            }
            Entry::Weights(c, lb, ub) => {
                let d = &mut self.cons[c as usize];
                d.lb = lb;
                d.ub = ub;
                self.sync_edges(c);
            }
            Entry::Executed(t, old) => self.executed[t as usize] = old,
            Entry::Paths(len) => self.paths_undo(len),
        }
    }

    pub(crate) fn set_lb(&mut self, t: u32, v: Time) {
        self.trail.push(Entry::Lb(t, self.lb[t as usize]));
        self.lb[t as usize] = v;
    }

    pub(crate) fn set_ub(&mut self, t: u32, v: Time) {
        self.trail.push(Entry::Ub(t, self.ub[t as usize]));
        self.ub[t as usize] = v;
    }
}

backtrack::impl_backtrack!(Stn, Level);
