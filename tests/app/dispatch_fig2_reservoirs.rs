//! Goal-driven dispatch on Fig. 2 (seed 1's rover): a `download_images` serves the operator's pictures
//! through the storage reservoir it frees, not through a causal link. Deferring it to its latest start as
//! if it served no goal (seed 2's support followed over causal links only) lost g5, g6 and g7 ("no room
//! left for its pictures"); following the reservoir too, goal-driven keeps every goal `earliest` keeps.

use std::collections::BTreeMap;

use mavtempo::cli::demo::{run_demo, DemoSetup};
use mavtempo::dispatch::{PolicyKind, SupportForm};
use mavtempo::exec::executive::Fate;

fn fates(dispatch: PolicyKind) -> BTreeMap<String, bool> {
    let setup = DemoSetup {
        dispatch,
        ..DemoSetup::default()
    };
    let run = run_demo(&setup, &mut |_: &str| {}, &mut |_| {})
        .unwrap_or_else(|e| panic!("demo under {dispatch}: {e}"));
    run.report
        .goals
        .iter()
        .map(|g| (g.name.clone(), g.fate == Fate::Achieved))
        .collect()
}

#[test]
fn goal_driven_keeps_every_goal_earliest_keeps_on_fig2() {
    let earliest = fates(PolicyKind::Earliest);
    for form in [SupportForm::Marking, SupportForm::Search] {
        let goal_driven = fates(PolicyKind::GoalDriven(form));
        for (goal, achieved) in &earliest {
            if *achieved {
                assert_eq!(
                    goal_driven.get(goal),
                    Some(&true),
                    "{goal} achieved under earliest, not under goal-driven ({form:?}): {goal_driven:?}"
                );
            }
        }
    }
    // The uploaded pictures need storage the downloads free.
    assert_eq!(earliest.get("g6"), Some(&true), "{earliest:?}");
    assert_eq!(earliest.get("g7"), Some(&true), "{earliest:?}");
}
