//! What the executive records of a mission: the cycles (busy ones whole, idle runs aggregated), the events
//! of the cycle under way, the counters of the summary and the complete replannings. Events enter only
//! through [`Journal::trace`] and leave only with the record of their cycle, so none is lost or counted twice;
//! insertion steps are counted among the repair steps.

use serde::Serialize;

use super::cycle_log::CycleLog;
use super::replan_record::ReplanRecord;
use super::trace::{CycleRecord, TraceEvent};
use mavtempo_temporal::model::Time;

/// Counters for the summary.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Counters {
    pub repairs: u64,
    pub repair_steps: u64,
    /// The part of `repair_steps` spent inserting new goals (src/executive/src/exec/goal_insertion.rs).
    pub insertion_steps: u64,
    pub replans: u64,
    pub launches: u64,
}

/// The CPU time of a cycle's three parts, µs.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct PartTimes {
    pub(crate) sense_us: u64,
    pub(crate) repair_us: u64,
    pub(crate) act_us: u64,
}

#[derive(Default)]
pub(crate) struct Journal {
    cycles: CycleLog,
    /// Events of the current cycle.
    pending: Vec<TraceEvent>,
    counters: Counters,
    /// The complete replannings of this mission: abort, attempts, steps, outcome, goals kept and rejected.
    replannings: Vec<ReplanRecord>,
}

impl Journal {
    pub(crate) fn trace(&mut self, e: TraceEvent) {
        tracing::debug!("{}", e.line());
        self.pending.push(e);
    }

    /// The events traced since the last cycle record.
    pub(crate) fn pending(&self) -> &[TraceEvent] {
        &self.pending
    }

    /// The cycle at `now` ended: its record takes the events traced since the last one.
    pub(crate) fn close_cycle(&mut self, now: Time, times: PartTimes) {
        let record = CycleRecord {
            index: self.cycles.count() + 1,
            time_ms: now,
            sense_us: times.sense_us,
            repair_us: times.repair_us,
            act_us: times.act_us,
            events: std::mem::take(&mut self.pending),
            idle: None,
        };
        self.cycles.push(record);
    }

    /// The events traced since the last cycle as a record of their own at `now`, when there are any.
    pub(crate) fn flush(&mut self, now: Time) -> Option<CycleRecord> {
        if self.pending.is_empty() {
            return None;
        }
        let c = CycleRecord {
            index: self.cycles.count() + 1,
            time_ms: now,
            events: std::mem::take(&mut self.pending),
            ..CycleRecord::default()
        };
        self.cycles.push(c.clone());
        Some(c)
    }

    pub(crate) fn cycles(&self) -> &CycleLog {
        &self.cycles
    }

    pub(crate) fn counters(&self) -> &Counters {
        &self.counters
    }

    /// A plan repair (or a goal's insertion) found a plan.
    pub(crate) fn repaired(&mut self) {
        self.counters.repairs += 1;
    }

    /// Steps of plan repair.
    pub(crate) fn repair_steps(&mut self, steps: u64) {
        self.counters.repair_steps += steps;
    }

    /// Steps of a goal's insertion attempt: repair steps too.
    pub(crate) fn insertion_steps(&mut self, steps: u64) {
        self.counters.repair_steps += steps;
        self.counters.insertion_steps += steps;
    }

    pub(crate) fn launched(&mut self) {
        self.counters.launches += 1;
    }

    /// A complete replanning starts.
    pub(crate) fn replanning(&mut self) {
        self.counters.replans += 1;
    }

    /// A complete replanning ended.
    pub(crate) fn replanned(&mut self, record: ReplanRecord) {
        self.replannings.push(record);
    }

    pub(crate) fn replannings(&self) -> &[ReplanRecord] {
        &self.replannings
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_leave_with_their_cycle_and_insertion_steps_are_repair_steps() {
        let mut j = Journal::default();
        assert!(j.flush(0).is_none());
        j.trace(TraceEvent::RepairDone { steps: 3 });
        j.close_cycle(10, PartTimes::default());
        assert!(j.pending().is_empty());
        assert_eq!(j.cycles().count(), 1);
        j.trace(TraceEvent::RepairDone { steps: 4 });
        let flushed = j.flush(20).map(|c| (c.index, c.events.len()));
        assert_eq!(flushed, Some((2, 1)));
        assert!(j.flush(30).is_none());
        j.repair_steps(5);
        j.insertion_steps(2);
        assert_eq!(
            (j.counters().repair_steps, j.counters().insertion_steps),
            (7, 2)
        );
    }
}
