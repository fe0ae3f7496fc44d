//! The forward search across h_FF's plateaus (issue 32): on Depots (IPC 2002) the relaxed plan ignores
//! that a hoist holds one crate at a time, and the lazy GBFS with its two h_FF lists alone evaluated
//! 41,712 states of p5 before a 252-action plan (p6 and p9: none in 10 s). Its third list, by novelty,
//! crosses the plateau in about 1,500 states. The plan found is replayed on the ground task.

use std::path::Path;

use mavtempo_temporal::pddl::{self, ground::ground};
use mavtempo_temporal::planner::forward::{Forward, ForwardOutcome};

#[test]
fn depots_p5_is_planned_within_a_few_thousand_states() {
    for folder in ["depots-time-automatic", "depots-time-simple-automatic"] {
        let dir = Path::new(repo!("../shared/benchmarks/ipc2002")).join(folder);
        let l = pddl::load(
            &dir.join("domain.pddl"),
            &dir.join("instances/instance-5.pddl"),
        )
        .unwrap_or_else(|e| panic!("{folder}: {e}"));
        let task = ground(&l.domain, &l.problem).unwrap_or_else(|e| panic!("{folder}: {e}"));
        let mut f = Forward::new(task.clone());
        let ForwardOutcome::Plan(plan) = f.run(5_000) else {
            panic!("{folder}: no plan after {} states", f.expanded());
        };
        let mut state = task.initial_state();
        for &a in &plan {
            state = task.actions[a as usize]
                .successor(&state)
                .unwrap_or_else(|| {
                    panic!("{folder}: {} does not apply", task.actions[a as usize].name)
                });
        }
        assert!(
            task.goal.holds(&state),
            "{folder}: the plan's last state misses the goal"
        );
    }
}
