//! A battery drop while a move drains the battery percent by percent (issue 31): the drop is one
//! over-consumption and one repair, not one per percent the move goes on using (the move's energy is
//! counted at its start in the model; the vehicle drains as it goes). Deterministic: MockVehicle.

use crate::support::rover_mock;

use mavtempo_executive::exec::resource_report::LevelVerdict;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_vehicle::mock::Scripted;
use mavtempo_vehicle::ResourceLevel;
use rover_mock::{assert_both_achieved, events, executive, nominal_rover, run};

#[test]
fn a_drop_then_the_move_draining_on_is_one_over_consumption() {
    let mut ex = executive();
    let mut v = nominal_rover();
    let mut first = true;
    let r = run(&mut ex, &mut v, move |v, at, task| {
        // 10 s into the first move (90 % at its start, ~9.5 % for the whole move) the battery reads 70 %:
        // a 15 % drop; then the move drains on, a whole percent every 4 s.
        if task == "move" && first {
            first = false;
            for (k, level) in [70.0, 69.0, 68.0, 67.0, 66.0].into_iter().enumerate() {
                v.at(
                    at + 10_000 + 4_000 * k as u64,
                    Scripted::Resource(ResourceLevel {
                        resource: "BATTERY".into(),
                        level,
                    }),
                );
            }
        }
    });
    let over: Vec<(i64, f64)> = events(&r)
        .into_iter()
        .filter_map(|(t, e)| match e {
            TraceEvent::Level {
                resource,
                level,
                verdict: LevelVerdict::OverConsumption { .. },
                ..
            } if resource == "BATTERY" => Some((t, level)),
            _ => None,
        })
        .collect();
    assert_eq!(over.len(), 1, "one over-consumption for one drop: {over:?}");
    assert_both_achieved(&r);
}
