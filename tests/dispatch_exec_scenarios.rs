//! exploratory
use std::path::Path;
use std::sync::Arc;

use mavtempo::dispatch::{PolicyKind, SupportForm};
use mavtempo::exec::config::ExecConfig;
use mavtempo::exec::cycle::CycleOutcome;
use mavtempo::exec::executive::Executive;
use mavtempo::exec::trace::TraceEvent;
use mavtempo::lang::load_problem_and_domain;
use mavtempo::model::Time;
use mavtempo::plan::PartialPlan;
use mavtempo::planner::{Budget, Search, StepOutcome};
use mavtempo::vehicle::mock::Outcome;
use mavtempo::vehicle::MockVehicle;

const MIN: Time = 60_000;
fn clock(t: Time) -> String {
    let m = t / MIN + 8 * 60;
    format!("{:02}:{:02}", m / 60, m % 60)
}

fn run(problem: &str, kind: PolicyKind, script: &[(&str, Time)]) -> Vec<(Time, String)> {
    let (d, p) = load_problem_and_domain(Path::new(problem)).expect("loads");
    let mut search = Search::new(PartialPlan::new(Arc::new(d), Arc::new(p)).unwrap());
    assert_eq!(search.run(Budget::steps(20_000)), StepOutcome::Solved);
    let cfg = ExecConfig {
        timestep_ms: MIN,
        repair_max_steps: Some(200),
        dispatch: kind,
        ..ExecConfig::default()
    };
    let mut ex = Executive::new(search.into_plan(), cfg);
    let mut v = MockVehicle::new();
    for (task, d) in script {
        v.script(task, Outcome::nominal(*d as u64));
    }
    let mut t = 0;
    loop {
        v.advance_to(t as u64);
        let out = ex.cycle(&mut v, t);
        let CycleOutcome::Continue { next, .. } = out else {
            eprintln!("{out:?}");
            break;
        };
        if t > 12 * 60 * MIN {
            break;
        }
        t = next.map_or(t + MIN, |n| n.min(t + MIN)).max(t + 1);
    }
    let mut out = vec![];
    for c in &ex.cycles {
        for e in &c.events {
            if !matches!(e, TraceEvent::Postponed { .. }) {
                out.push((c.time_ms, e.line()));
            }
        }
    }
    out
}

#[test]
fn explore() {
    for kind in [
        PolicyKind::Earliest,
        PolicyKind::GoalDriven(SupportForm::Marking),
        PolicyKind::Latest,
    ] {
        eprintln!("== {kind}");
        for (t, e) in run(
            "domains/shopping/problems/day.ixt",
            kind,
            &[("go", 16 * MIN), ("buy", 5 * MIN)],
        ) {
            eprintln!("{} {e}", clock(t));
        }
        eprintln!("== auv {kind}");
        for (t, e) in run(
            "domains/auv/problems/vents.ixt",
            kind,
            &[("go", 22 * MIN), ("survey", 10 * MIN), ("sample", 10 * MIN)],
        ) {
            eprintln!("{} {e}", clock(t));
        }
    }
    panic!();
}
