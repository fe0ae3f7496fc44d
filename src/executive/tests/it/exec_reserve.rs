//! A battery margin that a declared fault size would exhaust is said (issue 31, seed 62288516): with
//! `[exec.reserve] BATTERY = F`, a goal accepted into a plan that may leave the battery under F is
//! followed by a warning in the trace; with a reserve the plan keeps, no warning.

use crate::support::picture_goal;
use crate::support::rover_mock;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::mission::MissionReport;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_vehicle::mock::Scripted;
use picture_goal::picture;
use rover_mock::{events, executive_with, nominal_rover, rover_config, run};

/// rover_two (battery 90 %, two pictures) with a picture 5 m from home uploaded 10 s in.
fn mission(reserve: f64) -> MissionReport {
    let mut cfg = rover_config();
    cfg.reserve.insert("BATTERY".into(), reserve);
    assert_eq!(cfg.validate(), Ok(()));
    let mut ex = executive_with(cfg);
    let mut v = nominal_rover();
    v.at(10_000, Scripted::Goals(vec![picture("g6", 5.0, 0.0, 1)]));
    run(&mut ex, &mut v, |_, _, _| {})
}

fn warnings(r: &MissionReport) -> Vec<(String, f64, f64)> {
    events(r)
        .into_iter()
        .filter_map(|(_, e)| match e {
            TraceEvent::ReserveShort {
                resource,
                lowest,
                reserve,
            } => Some((resource, lowest, reserve)),
            _ => None,
        })
        .collect()
}

#[test]
fn a_plan_that_may_leave_less_than_the_declared_fault_is_said() {
    let r = mission(80.0);
    let accepted = events(&r)
        .iter()
        .any(|(_, e)| matches!(e, TraceEvent::GoalAccepted { goal } if goal == "g6"));
    assert!(accepted, "g6 accepted");
    let w = warnings(&r);
    assert!(!w.is_empty(), "a warning");
    for (resource, lowest, reserve) in w {
        assert_eq!(resource, "BATTERY");
        assert!(lowest < reserve && lowest > 0.0, "{lowest} vs {reserve}");
        let line = TraceEvent::ReserveShort {
            resource,
            lowest,
            reserve,
        }
        .line();
        assert!(line.contains("would exhaust it"), "{line}");
    }
    // A reserve the plan keeps: no warning.
    assert!(warnings(&mission(10.0)).is_empty());
}

#[test]
fn a_negative_or_infinite_fault_size_is_refused() {
    for bad in ["-1.0", "inf", "nan"] {
        let text = format!("[reserve]\nBATTERY = {bad}\n");
        let cfg: ExecConfig = toml::from_str(&text).expect("parses");
        assert!(cfg.validate().is_err(), "{bad}");
    }
}
