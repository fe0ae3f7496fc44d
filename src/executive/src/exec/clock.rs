//! The executive's clock (seed 1 §3.2: time is injected): mission time, ms since the plan's origin. The
//! mission loop reads its pacer (the vehicle's clock, a SITL's, or a manual one); plan repair and complete
//! replanning read it to stop at their budgets (μ·ts, the time limit l). Tests move a [`ManualClock`] by
//! hand, or give a closure.

use std::cell::Cell;

use mavtempo_temporal::model::Time;

/// Mission time, ms since the plan's origin.
pub trait Clock {
    fn now(&self) -> Time;
}

/// Any `Fn() -> Time` is a clock (e.g. `&|| 0`, a clock that does not move).
impl<F: Fn() -> Time> Clock for F {
    fn now(&self) -> Time {
        self()
    }
}

/// A clock moved by hand: it reads what it was last set to.
#[derive(Debug, Default)]
pub struct ManualClock(Cell<Time>);

impl ManualClock {
    pub fn new(at: Time) -> Self {
        ManualClock(Cell::new(at))
    }

    pub fn set(&self, at: Time) {
        self.0.set(at);
    }

    /// Moves the clock `by` ms on.
    pub fn advance(&self, by: Time) {
        self.0.set(self.0.get().saturating_add(by));
    }
}

impl Clock for ManualClock {
    fn now(&self) -> Time {
        self.0.get()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_manual_clock_reads_what_it_was_set_to_and_a_closure_is_a_clock() {
        let c = ManualClock::new(5);
        assert_eq!(c.now(), 5);
        c.advance(1_300);
        assert_eq!(c.now(), 1_305);
        c.set(42);
        let as_dyn: &dyn Clock = &c;
        assert_eq!(as_dyn.now(), 42);
        let fixed: &dyn Clock = &|| 7;
        assert_eq!(fixed.now(), 7);
    }
}
