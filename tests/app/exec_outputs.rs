//! Issue 16: everything a run decides is in its outputs, and one failure does not lose every goal.
//! - The abort is an event of the cycle that aborted; each complete replanning is a record of its own,
//!   handed to the trace's observer (what `run` and `demo` print) and kept in the report as data: the
//!   abort, each attempt's goals, planning steps and end, the outcome, the goals kept and rejected.
//! - A complete replanning whose budget runs out keeps the plan found for the best goal alone rather than
//!   rejecting every goal.
//! - A recharge tops up a nearly full battery without overflowing it (the charger stops at full).

use mavtempo_testkit::mapping;

use std::path::Path;
use std::sync::Arc;

use mavtempo::cli::demo::{run_demo, DemoSetup};
use mavtempo::exec::config::ExecConfig;
use mavtempo::exec::cycle_log::last_index;
use mavtempo::exec::executive::{Executive, Fate};
use mavtempo::exec::mission::MissionEnd;
use mavtempo::exec::outcome::{AbortReason, FateReason};
use mavtempo::exec::replan::{AttemptEnd, AttemptRecord, ReplanOutcome, ReplanResult};
use mavtempo::exec::trace::{CycleRecord, TraceEvent};
use mavtempo::lang::load_problem_and_domain;
use mavtempo::plan::PartialPlan;
use mavtempo::planner::Budget;

const FIG2: &str = include_str!("../../sitl/scenarios/fig2.toml");

/// The demo (stepped: deterministic) with every cycle record its observer saw.
fn demo(setup: &DemoSetup) -> (mavtempo::cli::demo::DemoRun, Vec<CycleRecord>) {
    let mut seen = Vec::new();
    let run = run_demo(setup, &mut |_| {}, &mut |c| seen.push(c.clone()))
        .unwrap_or_else(|e| panic!("demo: {e}"));
    (run, seen)
}

fn has(c: &CycleRecord, f: impl Fn(&TraceEvent) -> bool) -> bool {
    c.events.iter().any(f)
}

/// Seed 1 Fig. 2's e2: the timeout, the abort and the stops are one cycle's events; the replanning that
/// follows is the next record, with its attempts, its end and g2's rejection; the report keeps it as data.
#[test]
fn fig2_abort_and_replanning_reach_the_trace_and_the_report() {
    let (run, seen) = demo(&DemoSetup::default());
    // Every cycle with events the report keeps was handed to the trace's observer, in order; the idle
    // ones are in the report's runs (src/executive/src/exec/cycle_log.rs).
    let busy = |cs: &[CycleRecord]| {
        cs.iter()
            .filter(|c| !c.events.is_empty())
            .map(|c| c.index)
            .collect::<Vec<_>>()
    };
    let printed: Vec<u64> = seen.iter().map(|c| c.index).collect();
    let kept = busy(&run.report.cycles);
    assert_eq!(busy(&seen), kept);
    assert!(printed.iter().all(|i| run
        .report
        .cycles
        .iter()
        .any(|c| (c.index..=last_index(c)).contains(i))));
    for c in &run.report.cycles {
        let interesting = has(c, |e| {
            matches!(
                e,
                TraceEvent::Abort { .. }
                    | TraceEvent::Replan { .. }
                    | TraceEvent::ReplanDone { .. }
                    | TraceEvent::GoalRejected { .. }
            )
        });
        assert!(
            !interesting || printed.contains(&c.index),
            "cycle {}",
            c.index
        );
    }
    let at = seen
        .iter()
        .position(|c| has(c, |e| matches!(e, TraceEvent::Timeout { .. })))
        .expect("e2's timeout");
    assert!(
        has(&seen[at], |e| matches!(
            e,
            TraceEvent::Abort {
                reason: AbortReason::Timeout { .. }
            }
        )),
        "the abort is in the cycle that timed out: {:?}",
        seen[at].events
    );
    let replanning = &seen[at + 1];
    assert!(replanning.time_ms >= seen[at].time_ms);
    let attempts: Vec<(u32, u64, AttemptEnd)> = replanning
        .events
        .iter()
        .filter_map(|e| match e {
            TraceEvent::Replan(AttemptRecord {
                attempt,
                steps,
                end,
                goals,
                ..
            }) => {
                assert!(!goals.is_empty());
                Some((*attempt, *steps, *end))
            }
            _ => None,
        })
        .collect();
    assert!(attempts.len() >= 2, "{:?}", replanning.events);
    assert_eq!(attempts.last().map(|a| a.2), Some(AttemptEnd::Solved));
    assert!(has(replanning, |e| matches!(
        e,
        TraceEvent::GoalRejected { goal, .. } if goal == "g2"
    )));
    let done = replanning
        .events
        .iter()
        .find_map(|e| match e {
            TraceEvent::ReplanDone {
                outcome,
                kept,
                rejected,
                steps,
                ..
            } => Some((*outcome, kept.clone(), rejected.clone(), *steps)),
            _ => None,
        })
        .expect("the replanning's end");
    assert_eq!(done.0, ReplanOutcome::NewPlan);
    assert_eq!(done.2, ["g2"]);
    assert!(done.1.contains(&"g3".to_string()), "{:?}", done.1);
    // The report: the same replanning as data.
    let rec = &run.report.replannings[0];
    assert!(
        matches!(rec.abort, AbortReason::Timeout { .. }),
        "{}",
        rec.abort
    );
    assert_eq!(rec.outcome, ReplanOutcome::NewPlan);
    assert_eq!(rec.kept, done.1);
    assert_eq!(rec.rejected.len(), 1);
    assert_eq!(rec.rejected[0].goal, "g2");
    assert!(
        matches!(
            rec.rejected[0].reason,
            FateReason::Abandoned {
                end: AttemptEnd::TimeLimit,
                ..
            }
        ),
        "{:?}",
        rec.rejected[0].reason
    );
    assert_eq!(
        rec.attempts
            .iter()
            .map(|a| (a.attempt, a.steps, a.end))
            .collect::<Vec<_>>(),
        attempts
    );
    assert!(rec.steps >= attempts.iter().map(|a| a.1).sum::<u64>());
    assert_eq!(rec.steps, done.3);
    // And in the JSON.
    let json = serde_json::to_value(&run.report).expect("JSON");
    let r = &json["replannings"][0];
    assert_eq!(r["outcome"], "new_plan");
    assert_eq!(r["attempts"][0]["end"], "time_limit");
    assert_eq!(r["rejected"][0]["goal"], "g2");
}

/// Navigation fails for good 5 s in: the replanning that ends the mission is handed to the observer and
/// kept in the report, every goal rejected with its reason.
#[test]
fn the_replanning_that_ends_a_mission_reaches_the_observer_and_the_report() {
    let mut file = tempfile::NamedTempFile::new().unwrap_or_else(|e| panic!("temp file: {e}"));
    std::io::Write::write_all(
        &mut file,
        format!(
            "{FIG2}\n[[faults]]\nwhen = {{ at_s = 5.0 }}\nfault = {{ kind = \"nav_fails\", duration_s = 5000.0 }}\n"
        )
        .as_bytes(),
    )
    .unwrap_or_else(|e| panic!("write scenario: {e}"));
    let setup = DemoSetup {
        upload: false,
        scenario: Some(file.path().to_path_buf()),
        ..DemoSetup::default()
    };
    let (run, seen) = demo(&setup);
    assert_eq!(run.report.end, MissionEnd::NoGoals);
    let last = seen.last().expect("records");
    assert!(
        has(last, |e| matches!(
            e,
            TraceEvent::ReplanDone {
                outcome: ReplanOutcome::NoGoals,
                ..
            }
        )),
        "{:?}",
        last.events
    );
    let rec = run.report.replannings.last().expect("a replanning");
    assert_eq!(rec.outcome, ReplanOutcome::NoGoals);
    assert!(rec.kept.is_empty());
    assert_ne!(rec.abort, AbortReason::Unstated);
    let rejected_here: Vec<&str> = rec.rejected.iter().map(|r| r.goal.as_str()).collect();
    for g in &run.report.goals {
        assert_eq!(g.fate, Fate::Rejected, "{g:?}");
        assert!(g.reason.is_some());
        let by_a_replanning = run
            .report
            .replannings
            .iter()
            .any(|r| r.rejected.iter().any(|x| x.goal == g.name));
        // Or by the failure ban: the rover stands where navigation failed (a new place, issue 31), the
        // move from there fails three times in a row and is not tried again.
        let by_the_ban = matches!(g.reason, Some(FateReason::InstanceBanned { .. }));
        assert!(
            by_a_replanning || by_the_ban,
            "{} in {rejected_here:?}: {:?}",
            g.name,
            g.reason
        );
    }
}

fn fig2_executive(cfg: ExecConfig) -> Executive {
    let (d, p) =
        load_problem_and_domain(Path::new("domains/rover/problems/fig2.ixt")).expect("fig2 loads");
    let plan = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mapping = mapping::rover(&plan);
    Executive::new(plan, cfg).with_mapping(mapping)
}

/// A replanning whose step budget is too small for any attempt: the plan found for g3 alone (the highest
/// priority) is kept and the others are rejected with the reason; it used to end with every goal rejected.
#[test]
fn a_replanning_out_of_steps_keeps_the_best_goal_planned_alone() {
    let mut ex = fig2_executive(ExecConfig {
        replan_max_steps: 40,
        ..ExecConfig::default()
    });
    let test_abort = AbortReason::Timeout {
        timepoint: "a test's".into(),
    };
    ex.abort_with(test_abort.clone());
    let result = ex.replan(&|| 0, &mut |_| {});
    let ReplanResult::Plan(plan) = result else {
        panic!("expected a plan, got {result:?}");
    };
    let active: Vec<String> = plan
        .goals()
        .iter()
        .filter(|g| g.active)
        .map(|g| plan.problem().goals[g.goal.index()].name.clone())
        .collect();
    assert_eq!(active, ["g3"]);
    let rec = ex.replannings().last().expect("record");
    assert_eq!(rec.outcome, ReplanOutcome::NewPlan);
    assert_eq!(rec.kept, ["g3"]);
    assert_eq!(rec.rejected.len(), 4, "{:?}", rec.rejected);
    assert!(
        rec.rejected.iter().all(|r| matches!(
            r.reason.cause(),
            FateReason::ReplanBudgetSpent { abort, .. } | FateReason::Abandoned { abort, .. }
                if *abort == test_abort
        )),
        "{:?}",
        rec.rejected
    );
    // The whole replanning stays within twice the cap, plus the single-goal searches (300 steps each).
    let attempts: u64 = rec.attempts.iter().map(|a| a.steps).sum();
    assert!(attempts <= 80, "{attempts}");
    assert!(rec.steps <= 80 + 5 * 300, "{}", rec.steps);
    let g3 = ex.fates().values().find(|f| f.name == "g3").expect("g3");
    assert_eq!(g3.fate, Fate::Pending);
}

#[test]
fn a_failed_move_leaves_the_rover_still() {
    let (d, p) =
        load_problem_and_domain(Path::new("domains/rover/problems/fig2.ixt")).expect("fig2 loads");
    let mut search = mavtempo::planner::Search::new(
        PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan"),
    );
    assert_eq!(
        search.run(Budget::steps(50_000)),
        mavtempo::planner::StepOutcome::Solved
    );
    let plan = search.into_plan();
    let m = mapping::rover(&plan);
    let mut ex = Executive::new(plan, ExecConfig::default()).with_mapping(m);
    let a = ex
        .plan()
        .live_actions()
        .find(|&a| ex.plan().domain().task(ex.plan().action(a).task).name == "move")
        .expect("a move");
    let report = mavtempo::vehicle::ActionReport {
        id: 1,
        status: mavtempo::vehicle::ReportStatus::Failed,
        time_ms: 5_000,
        resources: Vec::new(),
        state: vec![(
            "position".into(),
            mavtempo::vehicle::StateValue::Position(mavtempo::vehicle::Enu::new(0.0, 0.0, 0.0)),
        )],
        reason: Some("battery empty".into()),
    };
    mavtempo::exec::state_update::integrate_state(&mut ex, a, &report, 5_000);
    let status = ex
        .plan()
        .domain()
        .attr_id("ROBOT_STATUS")
        .expect("ROBOT_STATUS");
    let still = ex.plan().problem().object_id("STILL").expect("STILL");
    assert_eq!(
        ex.state().get(&(status, Vec::new())),
        Some(mavtempo::model::Value::Obj(still))
    );
}
