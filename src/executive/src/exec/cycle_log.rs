//! The executive's record of its cycles, bounded (issue 31; not in the papers): a cycle with events (a
//! launch, a report, a repair step, a goal, …) is kept whole; a run of cycles where nothing happened is kept
//! as one record saying how many they were, when they ran and their longest CPU time. A 12-hour mission
//! that waits most of the time keeps what its busy cycles did, and its memory stays flat while it waits.
//! The cycle times are a fixed-size histogram: count, total and max exact, p50 / p99 exact below 1,024 µs
//! and within 1/64 above.

use serde::Serialize;

use super::trace::{CycleRecord, IdleRun};

/// Cycle times of the executive's CPU (sense + repair + act), µs.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct CycleTimes {
    pub count: usize,
    pub p50_us: u64,
    pub p99_us: u64,
    pub max_us: u64,
    pub total_us: u64,
}

/// The cycles run so far: busy ones whole, idle runs aggregated, the latest as it ran.
#[derive(Clone, Debug, Default)]
pub struct CycleLog {
    records: Vec<CycleRecord>,
    last: Option<CycleRecord>,
    times: TimeHistogram,
}

fn cpu_us(c: &CycleRecord) -> u64 {
    c.sense_us + c.repair_us + c.act_us
}

impl CycleLog {
    /// Records cycle `c` (its index the next one).
    pub fn push(&mut self, c: CycleRecord) {
        self.times.add(cpu_us(&c));
        let fold = c.events.is_empty()
            && self
                .records
                .last()
                .is_some_and(|p| p.events.is_empty() && last_index(p) + 1 == c.index);
        match self.records.last_mut() {
            Some(prev) if fold => {
                let first = IdleRun {
                    cycles: 1,
                    last_index: prev.index,
                    last_time_ms: prev.time_ms,
                    max_us: cpu_us(prev),
                };
                let run = prev.idle.get_or_insert(first);
                run.cycles += 1;
                run.last_index = c.index;
                run.last_time_ms = c.time_ms;
                run.max_us = run.max_us.max(cpu_us(&c));
                prev.sense_us += c.sense_us;
                prev.repair_us += c.repair_us;
                prev.act_us += c.act_us;
            }
            _ => self.records.push(c.clone()),
        }
        self.last = Some(c);
    }

    /// The latest cycle, as it ran (never an aggregate).
    pub fn last(&self) -> Option<&CycleRecord> {
        self.last.as_ref()
    }

    /// How many cycles ran.
    pub fn count(&self) -> u64 {
        self.times.count
    }

    /// The records kept, in order: busy cycles and idle runs.
    pub fn records(&self) -> &[CycleRecord] {
        &self.records
    }

    /// p50 / p99 / max / total of the cycles' CPU time.
    pub fn times(&self) -> CycleTimes {
        self.times.summary()
    }
}

/// The index of the last cycle a record stands for.
pub fn last_index(c: &CycleRecord) -> u64 {
    c.idle.as_ref().map_or(c.index, |r| r.last_index)
}

/// How many cycles a record stands for.
pub fn cycles_of(c: &CycleRecord) -> u64 {
    c.idle.as_ref().map_or(1, |r| r.cycles)
}

/// Values below this are their own bucket.
const EXACT: u64 = 1024;
/// Buckets per power of two above EXACT.
const SUB: u32 = 64;

/// Cycle CPU times: exact below [`EXACT`] µs, in 1/[`SUB`]-of-a-power-of-two buckets above.
#[derive(Clone, Debug, Default)]
struct TimeHistogram {
    buckets: Vec<u64>,
    count: u64,
    total_us: u64,
    max_us: u64,
}

fn bucket(v: u64) -> usize {
    if v < EXACT {
        return v as usize;
    }
    let e = 63 - v.leading_zeros(); // ≥ 10
    let sub = (v >> (e - SUB.trailing_zeros())) & u64::from(SUB - 1);
    (EXACT + u64::from(e - 10) * u64::from(SUB) + sub) as usize
}

/// The least value of bucket `b`.
fn floor_of(b: usize) -> u64 {
    let b = b as u64;
    if b < EXACT {
        return b;
    }
    let e = (b - EXACT) / u64::from(SUB) + 10;
    let sub = (b - EXACT) % u64::from(SUB);
    (1u64 << e) + (sub << (e - u64::from(SUB.trailing_zeros())))
}

impl TimeHistogram {
    fn add(&mut self, us: u64) {
        let b = bucket(us);
        if self.buckets.len() <= b {
            self.buckets.resize(b + 1, 0);
        }
        self.buckets[b] += 1;
        self.count += 1;
        self.total_us = self.total_us.saturating_add(us);
        self.max_us = self.max_us.max(us);
    }

    /// The value of rank `round((count - 1) p)` in sorted order (its bucket's floor).
    fn quantile(&self, p: f64) -> u64 {
        let rank = ((self.count - 1) as f64 * p).round() as u64;
        let mut seen = 0;
        for (b, n) in self.buckets.iter().enumerate() {
            seen += n;
            if seen > rank {
                return floor_of(b).min(self.max_us);
            }
        }
        self.max_us
    }

    fn summary(&self) -> CycleTimes {
        if self.count == 0 {
            return CycleTimes::default();
        }
        CycleTimes {
            count: self.count as usize,
            p50_us: self.quantile(0.5),
            p99_us: self.quantile(0.99),
            max_us: self.max_us,
            total_us: self.total_us,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exec::trace::TraceEvent;
    use mavtempo_temporal::model::Time;

    fn cycle(index: u64, busy: bool, us: u64) -> CycleRecord {
        CycleRecord {
            index,
            time_ms: index as Time * 100,
            sense_us: us,
            events: if busy {
                vec![TraceEvent::GoalAchieved { goal: "g1".into() }]
            } else {
                Vec::new()
            },
            ..CycleRecord::default()
        }
    }

    #[test]
    fn idle_runs_fold_and_busy_cycles_stay() {
        let mut log = CycleLog::default();
        for i in 1..=1000 {
            log.push(cycle(i, i % 250 == 0, i));
        }
        assert_eq!(log.count(), 1000);
        assert_eq!(log.last().map(|c| c.index), Some(1000));
        // 4 busy cycles, 4 idle runs before them.
        let r = log.records();
        assert_eq!(r.len(), 8, "{r:?}");
        assert_eq!(r.iter().map(cycles_of).sum::<u64>(), 1000);
        let run = r[0].idle.as_ref().expect("an idle run");
        assert_eq!((r[0].index, run.last_index, run.cycles), (1, 249, 249));
        assert_eq!(
            (r[0].time_ms, run.last_time_ms, run.max_us),
            (100, 24_900, 249)
        );
        assert_eq!(r[0].sense_us, (1..=249).sum::<u64>());
        assert!(r[1].idle.is_none() && r[1].index == 250 && !r[1].events.is_empty());
    }

    #[test]
    fn cycle_times_are_exact_below_a_millisecond_and_close_above() {
        let mut log = CycleLog::default();
        for i in 1..=101 {
            log.push(cycle(i, false, i * 5));
        }
        let t = log.times();
        assert_eq!((t.count, t.p50_us, t.max_us), (101, 255, 505));
        assert_eq!(t.total_us, (1..=101).map(|i| i * 5).sum::<u64>());
        for v in [1024, 1500, 70_000, 123_456_789] {
            let f = floor_of(bucket(v));
            assert!(f <= v && v - f <= v / 64, "{v} -> {f}");
        }
    }
}
