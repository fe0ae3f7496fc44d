//! The dispatch decision: when to execute a controllable timepoint. The executive asks a [`DispatchPolicy`];
//! the default, [`Earliest`], is IxTeT-eXeC's rule (seed 1 §3.5, [`super::t_exec`]). Other policies (latest,
//! goal-driven, seed 2) plug in here (issue 8).

use super::t_exec::{t_exec, TpKind};
use crate::model::Time;
use crate::plan::PartialPlan;
use crate::stn::Timepoint;

/// What the policy sees of one executable timepoint.
#[derive(Copy, Clone, Debug)]
pub struct Candidate {
    pub tp: Timepoint,
    pub kind: TpKind,
    pub lb: Time,
    pub ub: Time,
}

pub trait DispatchPolicy {
    /// The time at which `c` should be executed; the executive executes it in the cycle that contains it.
    fn exec_time(&mut self, plan: &PartialPlan, c: &Candidate, ts: Time) -> Time;

    fn name(&self) -> &'static str;
}

/// Seed 1 §3.5: everything as early as possible, except the ends of late-preemptive actions (`ub − ts`) and
/// of non-preemptive ones (`ub`, the report is awaited).
#[derive(Copy, Clone, Debug, Default)]
pub struct Earliest;

impl DispatchPolicy for Earliest {
    fn exec_time(&mut self, _plan: &PartialPlan, c: &Candidate, ts: Time) -> Time {
        t_exec(c.kind, c.lb, c.ub, ts)
    }

    fn name(&self) -> &'static str {
        "earliest"
    }
}
