//! The execution cycle (seed 1 §3.2): the executive wakes up when a message arrived, a timepoint is due or a
//! plan repair is in progress; it senses (integrates the messages), repairs for at most μ·ts, and acts. After
//! every step an executable plan is in hand; otherwise execution is aborted and a complete replanning starts.

use super::clock::VehicleClock;
use super::executive::Executive;
use super::failures::PlanChangeKind;
use super::journal::PartTimes;
use super::outcome::AbortReason;
use super::repair_tree::RepairOutcome;
use super::trace::TraceEvent;
use mavtempo_temporal::model::Time;
use mavtempo_vehicle::Vehicle;

/// What the cycle leaves for the caller.
#[derive(Clone, Debug, PartialEq)]
pub enum CycleOutcome {
    /// Next wake-up: this time (a due timepoint), or as soon as a message arrives; `repairing` when a
    /// repair is in progress (wake up at the next cycle).
    Continue { next: Option<Time>, repairing: bool },
    /// The plan is not executable any more: call [`Executive::replan`].
    Aborted(AbortReason),
    /// No action left and every goal settled.
    Finished,
}

pub use super::clock::mission_time;

impl Executive {
    pub fn cycle(&mut self, vehicle: &mut dyn Vehicle, now: Time) -> CycleOutcome {
        // The parts' CPU times are measured on the companion's clock (a manual one in tests).
        let wall = self.wall.clone();
        let t0 = wall.now_us();
        while let Some(ev) = vehicle.try_event() {
            self.integrate(ev, now);
        }
        let t1 = wall.now_us();
        let mut repairing = false;
        if self.operator.is_held() {
            // The operator has the vehicle: time goes on, nothing is commanded, no plan is made.
            self.while_paused(now);
        } else if !self.abort.is_raised() {
            // The repair's μ·ts is mission time: the vehicle's clock, as the pacer reads it.
            let clock = VehicleClock::new(vehicle, self.vehicle.origin_ms());
            match self.repair_phase(now, &clock) {
                RepairOutcome::InProgress => repairing = true,
                RepairOutcome::Solved => self.plan_changed(now, PlanChangeKind::Repair),
                _ => {}
            }
        }
        // Uploads are answered once this cycle's insertion attempt had its share (its verdict, or "to follow").
        self.answer_goal_batches();
        let t2 = wall.now_us();
        let next = if !self.abort.is_raised() && !self.operator.is_held() {
            self.act(vehicle, now)
        } else {
            None
        };
        let aborted = self.abort.reason().cloned();
        if let Some(reason) = &aborted {
            // P_ts keeps no action: every running one is told END, non-preemptive ones too (seed 1 lets
            // those run to their end; a vehicle must not go on doing what no plan accounts for;
            // docs/departures.md). The abort and its stops are
            // this cycle's events.
            let running = self.dispatched.started_actions();
            for a in running {
                let act = self.plan.action(a);
                if !act.removed && !self.plan.is_executed(act.end) {
                    self.stop(vehicle, a);
                }
            }
            self.trace(TraceEvent::Abort {
                reason: reason.clone(),
            });
        }
        let t3 = wall.now_us();
        self.journal.close_cycle(
            now,
            PartTimes {
                sense_us: t1.saturating_sub(t0),
                repair_us: t2.saturating_sub(t1),
                act_us: t3.saturating_sub(t2),
            },
        );
        if let Some(reason) = aborted {
            return CycleOutcome::Aborted(reason);
        }
        let busy = self.plan.live_actions().next().is_some();
        if !busy && !self.goals.any_open() {
            return CycleOutcome::Finished;
        }
        CycleOutcome::Continue { next, repairing }
    }
}
