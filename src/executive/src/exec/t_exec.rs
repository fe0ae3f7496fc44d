//! The execution time of a timepoint (seed 1 §3.5, Figure 1): start and goal timepoints and the end of an
//! early-preemptive action at `T_lb`; the end of a late-preemptive action at `T_ub − ts`; the end of a
//! non-preemptive action at `T_ub` (it cannot be commanded: reaching it without a report is a timeout).

use crate::model::{Preemption, Time};

/// What a timepoint is, for execution.
#[derive(Copy, Clone, Eq, PartialEq, Debug)]
pub enum TpKind {
    Start,
    Goal,
    End(Preemption),
}

/// t_exec for a timepoint of kind `kind` with bounds `[lb, ub]` and timestep `ts`.
pub fn t_exec(kind: TpKind, lb: Time, ub: Time, ts: Time) -> Time {
    match kind {
        TpKind::Start | TpKind::Goal | TpKind::End(Preemption::EarlyPreemptive) => lb,
        TpKind::End(Preemption::LatePreemptive) => (ub - ts).max(lb),
        TpKind::End(Preemption::NonPreemptive) => ub,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_of_timepoint_has_the_papers_execution_time() {
        let (lb, ub, ts) = (10_000, 50_000, 2_000);
        assert_eq!(t_exec(TpKind::Start, lb, ub, ts), lb);
        assert_eq!(t_exec(TpKind::Goal, lb, ub, ts), lb);
        assert_eq!(
            t_exec(TpKind::End(Preemption::EarlyPreemptive), lb, ub, ts),
            lb
        );
        assert_eq!(
            t_exec(TpKind::End(Preemption::LatePreemptive), lb, ub, ts),
            ub - ts
        );
        assert_eq!(
            t_exec(TpKind::End(Preemption::NonPreemptive), lb, ub, ts),
            ub
        );
        // Less than one timestep of flexibility: not before the lower bound.
        assert_eq!(
            t_exec(TpKind::End(Preemption::LatePreemptive), lb, lb + 500, ts),
            lb
        );
    }
}
