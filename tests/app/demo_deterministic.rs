//! The stepped demo (`mavtempo demo` without `--speedup`) is reproducible: the Fig. 2 mission with its SITL
//! faults and the ground station's upload of g6 and g7, run twice in process over real sockets, gives the
//! same cycles, repairs, replannings, goal fates and trace, event for event. (Only the measured CPU times
//! of each cycle part may differ.)

use mavtempo::cli::demo::{run_demo, DemoRun, DemoSetup};
use mavtempo::exec::trace::CycleRecord;

/// The trace as `demo` prints it, without the measured µs: time, cycle index, each event's line.
fn trace_text(cycles: &[CycleRecord]) -> String {
    let mut text = String::new();
    for c in cycles {
        text += &format!("[{} ms] cycle {}\n", c.time_ms, c.index);
        for e in &c.events {
            text += &format!("    {}\n", e.line());
        }
    }
    text
}

fn run() -> (DemoRun, Vec<String>) {
    let mut said = Vec::new();
    let run = run_demo(
        &DemoSetup::default(),
        &mut |line: &str| said.push(line.to_string()),
        &mut |_| {},
    )
    .unwrap_or_else(|e| panic!("demo: {e}"));
    // The SITL's port changes from run to run; the rest of what the demo says must not.
    said.retain(|l| !l.starts_with("SITL vehicle at"));
    (run, said)
}

#[test]
fn the_stepped_demo_gives_the_same_mission_twice() {
    let (a, said_a) = run();
    let (b, said_b) = run();
    let (ra, rb) = (&a.report, &b.report);
    assert_eq!(ra.end, rb.end);
    assert_eq!(ra.duration_ms, rb.duration_ms);
    assert_eq!(ra.cycles.len(), rb.cycles.len(), "cycle count");
    assert_eq!(
        ra.counters, rb.counters,
        "repairs, repair steps, replans, launches"
    );
    assert_eq!(ra.goals, rb.goals, "goal fates and reasons");
    assert_eq!(ra.plan_changes, rb.plan_changes);
    assert_eq!(ra.resources, rb.resources);
    let (ta, tb) = (trace_text(&ra.cycles), trace_text(&rb.cycles));
    if ta != tb {
        let first = ta
            .lines()
            .zip(tb.lines())
            .position(|(x, y)| x != y)
            .unwrap_or(0);
        let around = |t: &str| {
            t.lines()
                .skip(first.saturating_sub(5))
                .take(12)
                .collect::<Vec<_>>()
                .join("\n")
        };
        panic!(
            "traces differ at line {first}:\n--- first run\n{}\n--- second run\n{}",
            around(&ta),
            around(&tb)
        );
    }
    assert_eq!(said_a, said_b);
    assert_eq!(a.upload, b.upload);
    // The story did happen: g6 and g7 came over MAVLink and were accepted, repairs and replans took place.
    assert!(
        a.upload.as_deref().is_some_and(|u| u.contains("accepted")),
        "{:?}",
        a.upload
    );
    assert!(ra.goals.iter().any(|g| g.name == "g7"));
    assert!(ra.counters.repairs > 0 && ra.counters.replans > 0);
}
