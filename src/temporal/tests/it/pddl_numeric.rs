//! PDDL numeric fluents (issue 32): reservoirs for guarded decreases, increases and fills, durations that
//! depend on a fluent fixed once the plan's accesses are ordered, the replay's numeric semantics, and every
//! construct the translation cannot express soundly refused at its place.

use std::path::{Path, PathBuf};

use mavtempo_temporal::model::ResourceKind;
use mavtempo_temporal::pddl::{self, simulate, writer, Src};
use mavtempo_temporal::planner::Budget;

fn fixture(name: &str) -> PathBuf {
    Path::new(repo!("tests/fixtures/pddl")).join(name)
}

fn fixture_text(name: &str) -> String {
    std::fs::read_to_string(fixture(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The translation of `domain` with `problem` (texts named `d.pddl`, `p.pddl`), or its error text.
fn read(domain: &str, problem: &str) -> Result<pddl::Loaded, String> {
    let (ds, ps) = (Src::new("d.pddl", domain), Src::new("p.pddl", problem));
    let d = pddl::parse_domain(&ds).map_err(|e| e.to_string())?;
    let p = pddl::parse_problem(&ps).map_err(|e| e.to_string())?;
    let translated = pddl::translate(&ds, &d, &ps, &p).map_err(|e| e.to_string())?;
    Ok(pddl::Loaded {
        domain: d,
        problem: p,
        translated,
    })
}

#[test]
fn a_battery_with_a_recharge_at_a_rate_is_planned_checked_and_replayed() {
    let l = read(&fixture_text("charge.pddl"), &fixture_text("charge-1.pddl"))
        .unwrap_or_else(|e| panic!("{e}"));
    let t = &l.translated;
    // One reservoir for `charge(r1)`, capacity 10 (the recharge's fill value), starting at 3, and its lock.
    let charge = t
        .domain
        .resources
        .iter()
        .position(|r| r.name == "charge(r1)")
        .unwrap_or_else(|| panic!("{:?}", t.domain.resources));
    assert_eq!(t.domain.resources[charge].kind, ResourceKind::Reservoir);
    assert_eq!(t.domain.resources[charge].capacity, 10.0);
    assert_eq!(t.problem.resources[charge].level, 3.0);
    assert!(t
        .domain
        .resources
        .iter()
        .any(|r| r.name == "charge(r1)-lock"));
    // `walked` only feeds the metric: left out, with a note that says so.
    assert!(
        t.notes
            .iter()
            .any(|n| n.contains("walked") && n.contains("left out")),
        "{:?}",
        t.notes
    );
    let s = pddl::solve(&l, Budget::steps(200_000)).unwrap_or_else(|e| panic!("{e}"));
    let text = s.ipc.to_string();
    let steps = writer::parse_ipc(&text).unwrap_or_default();
    assert_eq!(
        simulate::simulate(&l.domain, &l.problem, &steps),
        Ok(s.ipc.makespan_ms()),
        "{text}"
    );
    // The recharge's duration is the PDDL one, (10 - charge at its start) / 2: 3.5 s from 3, 4 s from 2.
    let recharge = steps
        .iter()
        .find(|s| s.action == "recharge")
        .unwrap_or_else(|| panic!("no recharge in\n{text}"));
    assert!(
        [3_500, 4_000].contains(&recharge.duration_ms),
        "{recharge:?}"
    );
}

/// The forward search reads numeric fluents as state: from 3, `go s1 s2` (4) does not apply until the
/// recharge (to 10 at rate 2, `?duration` evaluated in the state at its start) has run; its plan, deordered
/// and completed with the reservoirs, passes the checker and the replay. Before, the forward search stepped
/// aside on any numeric effect and the POCL searches planned such domains alone.
#[test]
fn the_forward_search_plans_numeric_fluents_as_state() {
    let l = read(&fixture_text("charge.pddl"), &fixture_text("charge-1.pddl"))
        .unwrap_or_else(|e| panic!("{e}"));
    let mut hybrid = pddl::Hybrid::new(&l, None);
    let planned = hybrid.slice(100_000, std::time::Duration::MAX);
    assert!(planned.is_ok(), "stepped aside: {:?}", hybrid.aside);
    let task = pddl::ground::ground(&l.domain, &l.problem).unwrap_or_else(|e| panic!("{e}"));
    // `walked` only feeds the metric: not a state variable; `charge r1` is.
    assert_eq!(task.nums, vec!["(charge r1)".to_string()]);
    let go = task
        .actions
        .iter()
        .position(|a| a.name == "go" && a.args == ["r1", "s1", "s2"])
        .unwrap_or_else(|| panic!("no go r1 s1 s2"));
    let recharge = task
        .actions
        .iter()
        .position(|a| a.name == "recharge" && a.args == ["r1", "s1"])
        .unwrap_or_else(|| panic!("no recharge r1 s1"));
    let init = task.initial_state();
    assert!(task.actions[go].successor(&init).is_none(), "3 < 4");
    let full = task.actions[recharge]
        .successor(&init)
        .unwrap_or_else(|| panic!("the recharge applies"));
    assert_eq!(&full.nums[..], &[10.0]);
    let there = task.actions[go]
        .successor(&full)
        .unwrap_or_else(|| panic!("10 >= 4"));
    assert_eq!(&there.nums[..], &[6.0]);
}

#[test]
fn the_replay_simulates_numeric_fluents() {
    use simulate::SimulateError as E;
    let l = read(&fixture_text("charge.pddl"), &fixture_text("charge-1.pddl"))
        .unwrap_or_else(|e| panic!("{e}"));
    let run = |plan: &str| {
        let steps = writer::parse_ipc(plan).unwrap_or_default();
        simulate::simulate(&l.domain, &l.problem, &steps)
    };
    let good = "0.000: (look r1 s1) [1.000]\n1.010: (recharge r1 s1) [4.000]\n\
                5.020: (go r1 s1 s2) [4.000]\n9.030: (look r1 s2) [1.000]\n";
    assert_eq!(run(good), Ok(10_030));
    // Without the recharge the move's guard `(>= (charge r1) 4)` fails (2 left).
    let flat =
        "0.000: (look r1 s1) [1.000]\n1.010: (go r1 s1 s2) [4.000]\n5.020: (look r1 s2) [1.000]\n";
    assert!(
        matches!(run(flat), Err(E::Numeric { step: 2, .. })),
        "{:?}",
        run(flat)
    );
    // A recharge whose duration is not (10 - 2) / 2 breaks its duration in the state at its start.
    let long = good.replace("[4.000]\n5.020", "[3.000]\n5.020");
    assert!(
        matches!(run(&long), Err(E::StateDuration { step: 2, .. })),
        "{:?}",
        run(&long)
    );
    // Two accesses to `charge r1` within ε interfere (the look's guard reads what the recharge changes).
    let close = "0.000: (recharge r1 s1) [3.500]\n3.500: (look r1 s1) [1.000]\n";
    assert!(
        matches!(run(close), Err(E::Interfere { .. })),
        "{:?}",
        run(close)
    );
}

/// A domain around one action whose numeric part is `condition` and `effect` (a `go` with a fuel), and a
/// `fill` that reads the fuel (else it would only feed a metric, and its effects would be left out).
fn one_action(condition: &str, effect: &str, duration: &str) -> String {
    format!(
        "(define (domain d) (:requirements :typing :durative-actions :fluents)
  (:types car)
  (:predicates (ready ?c - car) (done ?c - car))
  (:functions (fuel ?c - car) (tank ?c - car))
  (:durative-action go :parameters (?c - car)
    :duration {duration}
    :condition (and (at start (ready ?c)) {condition})
    :effect (and (at end (done ?c)) {effect}))
  (:durative-action fill :parameters (?c - car)
    :duration (= ?duration 1)
    :condition (and (at start (ready ?c)) (at start (< (fuel ?c) (tank ?c))))
    :effect (at end (assign (fuel ?c) (tank ?c)))))"
    )
}

const PROBLEM: &str = "(define (problem p) (:domain d) (:objects c1 - car)
  (:init (ready c1) (= (fuel c1) 5) (= (tank c1) 20)) (:goal (done c1)))";

#[test]
fn what_a_reservoir_cannot_express_is_refused_at_its_place() {
    let d = "(= ?duration 2)";
    // (condition, effect, duration, line:col expected, words expected). Line 7 is the condition, 8 the
    // effect, 6 the duration (in `one_action`'s text).
    let cases: &[(&str, &str, &str, &str, &str)] = &[
        // A decrease nothing guards could take the fuel below 0.
        (
            "",
            "(at end (decrease (fuel ?c) 3))",
            d,
            "d.pddl:8:45:",
            "no `>=` condition",
        ),
        // A guard of another amount.
        (
            "(at start (>= (fuel ?c) 4))",
            "(at end (decrease (fuel ?c) 3))",
            d,
            "d.pddl:8:45:",
            "no `>=` condition",
        ),
        // A guard at the end for a decrease at the start.
        (
            "(at end (>= (fuel ?c) 3))",
            "(at start (decrease (fuel ?c) 3))",
            d,
            "d.pddl:8:47:",
            "no `>=` condition",
        ),
        // A guard alone.
        (
            "(at start (>= (fuel ?c) 3))",
            "",
            d,
            "d.pddl:7:53:",
            "without a decrease",
        ),
        // `>` and `=` on a fluent.
        (
            "(at start (> (fuel ?c) 3))",
            "",
            d,
            "d.pddl:7:53:",
            "compared with `>` or `=`",
        ),
        // An upper bound below the capacity.
        (
            "(at start (<= (fuel ?c) 8))",
            "",
            d,
            "d.pddl:7:53:",
            "upper bound",
        ),
        // An increase of a fluent that `fill` fills to its tank.
        (
            "",
            "(at end (increase (fuel ?c) 1))",
            d,
            "d.pddl:8:45:",
            "an increase of a fluent that actions also fill",
        ),
        // Scaling.
        (
            "",
            "(at end (scale-up (fuel ?c) 2))",
            d,
            "d.pddl:8:45:",
            "`scale-up`",
        ),
        // An amount that depends on `?duration` outside a recharge.
        (
            "",
            "(at end (decrease (fuel ?c) (* ?duration 2)))",
            d,
            "d.pddl:8:45:",
            "depends on `?duration`",
        ),
        // A duration that depends on the fuel other than as a fill at a rate.
        (
            "",
            "",
            "(= ?duration (fuel ?c))",
            "d.pddl:6:28:",
            "`(= ?duration (/ (- v f) r))`",
        ),
    ];
    for (cond, eff, dur, at, words) in cases {
        let got = match read(&one_action(cond, eff, dur), PROBLEM) {
            Ok(_) => "accepted".to_string(),
            Err(e) => e,
        };
        assert!(
            got.starts_with(at) && got.contains(words),
            "{cond} | {eff} | {dur}: expected {at} … {words}, got: {got}"
        );
    }
    // A fluent that starts below 0, at its place in the problem.
    let e = read(
        &one_action("", "", d),
        &PROBLEM.replace("(= (fuel c1) 5)", "(= (fuel c1) -1)"),
    )
    .err()
    .unwrap_or_default();
    assert!(
        e.starts_with("p.pddl:2:24:") && e.contains("below 0"),
        "{e}"
    );
    // Filled to two values.
    let twice = one_action("", "", d).replace(
        "(at end (done ?c)) )",
        "(at end (done ?c)) (at end (assign (fuel ?c) 7)))",
    );
    let e = read(&twice, PROBLEM).err().unwrap_or_default();
    assert!(e.contains("filled to"), "{e}");
}
