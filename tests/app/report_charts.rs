//! Issue 18: the charts' data drawn from a mission report are the report's: one bar per launch, where the
//! trace puts its start and its report; the marks at the trace's repairs, replannings and goal events;
//! each reservoir's bounds and reported levels equal to the report's samples. On the Fig. 2 story.

use mavtempo::cli::demo::{run_demo, DemoSetup};
use mavtempo::exec::mission::MissionReport;
use mavtempo::exec::trace::TraceEvent;
use mavtempo::report::data::{Charts, MarkKind};
use mavtempo::report::{charts_of, html, parse_report, ReportError};

fn fig2() -> MissionReport {
    run_demo(&DemoSetup::default(), &mut |_| {}, &mut |_| {})
        .unwrap_or_else(|e| panic!("demo: {e}"))
        .report
}

/// The times at which the trace has `f`.
fn times(r: &MissionReport, f: impl Fn(&TraceEvent) -> bool) -> Vec<i64> {
    r.cycles
        .iter()
        .flat_map(|c| c.events.iter().filter(|e| f(e)).map(move |_| c.time_ms))
        .collect()
}

fn marks(c: &Charts, kind: MarkKind) -> Vec<(i64, String)> {
    c.marks
        .iter()
        .filter(|m| m.kind == kind)
        .map(|m| (m.time_ms, m.label.clone()))
        .collect()
}

#[test]
fn fig2_charts_follow_the_trace_and_the_bounds_of_the_report() {
    let r = fig2();
    let c = charts_of(&r).unwrap_or_else(|e| panic!("charts: {e}"));

    // One bar per launch, starting when the trace launched it; closed when its report came.
    assert_eq!(c.bars.len() as u64, r.counters.launches);
    let launches = times(&r, |e| matches!(e, TraceEvent::Launch { .. }));
    let starts: Vec<i64> = c.bars.iter().map(|b| b.start_ms).collect();
    assert_eq!(starts, launches);
    for b in &c.bars {
        let reported = times(&r, |e| {
            matches!(e, TraceEvent::Report { action, status, .. }
                if *action == b.action && status.to_string() == b.status)
        });
        let end = b
            .end_ms
            .unwrap_or_else(|| panic!("{} never reported", b.action));
        assert!(
            reported.contains(&end),
            "{}: end {end} not in {reported:?}",
            b.action
        );
        let (lb, _) = b
            .planned_end_ms
            .unwrap_or_else(|| panic!("{}: no window", b.action));
        assert!(
            lb >= b.start_ms,
            "{}: planned end before its start",
            b.action
        );
    }
    // e1: the first picture of p1 failed; e6: the recharge was stopped by the plan (interrupted).
    let p1 = c.bars.iter().find(|b| b.action == "take_picture(p1)");
    assert_eq!(p1.map(|b| b.status.as_str()), Some("failed"));
    assert!(c
        .bars
        .iter()
        .any(|b| b.action.starts_with("recharge") && b.status == "interrupted"));

    // Marks where the trace has its events: e1's repair, e2's abort and replanning, g6/g7 arriving.
    let repairs = times(&r, |e| matches!(e, TraceEvent::RepairDone { .. }));
    assert_eq!(
        marks(&c, MarkKind::Repair)
            .iter()
            .map(|m| m.0)
            .collect::<Vec<_>>(),
        repairs
    );
    assert!(repairs.len() as u64 >= r.counters.repairs.min(1));
    let aborts = marks(&c, MarkKind::Abort);
    assert_eq!(aborts.len(), 1, "{aborts:?}");
    let replans = marks(&c, MarkKind::Replan);
    assert_eq!(replans.len(), r.replannings.len());
    assert!(replans[0].0 >= aborts[0].0);
    let arrivals: Vec<String> = marks(&c, MarkKind::GoalArrival)
        .into_iter()
        .map(|m| m.1)
        .collect();
    assert_eq!(arrivals, ["g6", "g7"]);
    assert_eq!(
        marks(&c, MarkKind::GoalRejected)
            .into_iter()
            .map(|m| m.1)
            .collect::<Vec<_>>(),
        ["g2"]
    );
    assert_eq!(marks(&c, MarkKind::GoalAchieved).len(), 6);

    // Reservoirs only, with the report's bounds at every sample and its reported levels.
    let names: Vec<&str> = c.series.iter().map(|s| s.resource.as_str()).collect();
    assert_eq!(names, ["STORAGE", "BATTERY"]);
    for s in &c.series {
        let samples: Vec<_> = r
            .resources
            .iter()
            .filter(|x| x.resource == s.resource)
            .collect();
        for x in &samples {
            assert_eq!(Charts::bounds_at(s, x.time_ms), Some((x.lb, x.ub)), "{x:?}");
        }
        let reported: Vec<(i64, f64)> = samples
            .iter()
            .filter_map(|x| x.reported.map(|l| (x.time_ms, l)))
            .collect();
        assert!(!reported.is_empty(), "{}: no reported level", s.resource);
        assert_eq!(s.reported, reported);
    }
    // Fig. 8: the storage level stays inside its theoretical bounds.
    let storage = &c.series[0];
    for &(t, level) in &storage.reported {
        let (lb, ub) = Charts::bounds_at(storage, t).unwrap_or((f64::NAN, f64::NAN));
        assert!(
            lb - 1e-6 <= level && level <= ub + 1e-6,
            "{t}: {level} not in [{lb}, {ub}]"
        );
    }

    // The map: the track and the places named by the goals.
    assert!(c.track.len() > 10);
    for (place, goal) in [("p1", "g1"), ("p5", "g5"), ("g6_loc", "g6")] {
        let p = c.places.iter().find(|p| p.name == place);
        assert_eq!(p.map(|p| p.goals.clone()), Some(vec![goal.to_string()]));
    }

    // The page holds the goals, the charts and the counters.
    let page = html::page("fig2", &c).unwrap_or_else(|e| panic!("page: {e}"));
    assert!(page.contains("data-goal=\"g7\""));
    assert!(page.contains("abandoned by complete replanning"));
    assert_eq!(page.matches("<svg").count(), 4);
    assert!(page.contains("take_picture(p1)"));
}

#[test]
fn a_malformed_report_is_an_error_at_its_line_and_column() {
    let text = "{\n  \"duration_ms\": 5,\n  \"cycles\": [ {\"time_ms\": oops} ]\n}\n";
    match parse_report("run.json", text) {
        Err(ReportError::Parse(l)) => {
            assert_eq!((l.file.as_str(), l.line), ("run.json", 3));
            assert_eq!(l.col, 27, "{l}"); // under the `o` of `oops`
            assert!(l.source_line.contains("oops"));
        }
        other => panic!("{other:?}"),
    }
    // Not a report: an array, an object without cycles.
    for (text, what) in [
        ("\n [1, 2]", "expected a JSON object"),
        ("{\"goals\": []}", "missing field"),
    ] {
        match parse_report("x.json", text) {
            Err(ReportError::Parse(l)) => assert!(l.message.contains(what), "{l}"),
            other => panic!("{text}: {other:?}"),
        }
    }
    // A report of an older version (no track, no reservoirs) still reads.
    let old = "{\"duration_ms\": 1000, \"goals\": [{\"name\": \"g1\", \"fate\": \"achieved\"}], \
               \"cycles\": [{\"time_ms\": 10, \"events\": [{\"kind\": \"launch\", \"action\": \"a\", \"vid\": 1}, \
               {\"kind\": \"timeout\", \"timepoint\": \"x\"}]}]}";
    let v = parse_report("old.json", old).unwrap_or_else(|e| panic!("{e}"));
    let c = Charts::from_report(&v);
    assert_eq!((c.bars.len(), c.goals.len(), c.now_ms), (1, 1, 1000));
}
