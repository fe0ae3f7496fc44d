//! Contingent durations are not squeezed (src/executive/src/exec/squeeze.rs, docs/stnu.md): a start that
//! could go now but would shorten a running contingent duration has a wait in the plan's dispatchable
//! network (dynamic controllability); it waits until that action ends (while it keeps flexibility),
//! instead of forcing the running action to be stopped short or to time out.
//!
//! The relay domain: the rover drives to b (late-preemptive, 10–100 s, contingent); a picture at b needs the radio
//! relay open (20–30 s, non-preemptive, contingent), so the relay may open up to 25 s before the picture. Dispatched at
//! its earliest, the relay would open at 0 s and the drive would have to end by 25 s; the drive takes 60 s.

use crate::support::mission;

use std::sync::Arc;

use mavtempo_executive::exec::config::ExecConfig;
use mavtempo_executive::exec::executive::{Executive, Fate};
use mavtempo_executive::exec::mission::MissionEnd;
use mavtempo_executive::exec::squeeze::pending_wait;
use mavtempo_executive::exec::trace::TraceEvent;
use mavtempo_temporal::lang::{parse_domain, parse_problem};
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_temporal::planner::{Budget, Search, StepOutcome};
use mavtempo_vehicle::mock::Outcome;
use mavtempo_vehicle::MockVehicle;

const DOMAIN: &str = "domain relay;
type place;
attribute AT(): place;
attribute LINK(): bool;
attribute SHOT(?p: place): bool;

task drive(?from: place, ?to: place) (st, et) {
    ?from != ?to;
    event(AT(): (?from, +oo), st);
    hold(AT(): +oo, (st, et));
    event(AT(): (+oo, ?to), et);
    contingent (et - st) in [10s, 100s];
} latePreemptive

task relay() (st, et) {
    event(LINK(): (false, true), st);
    hold(LINK(): true, (st, et));
    event(LINK(): (true, false), et);
    contingent (et - st) in [20s, 30s];
} nonPreemptive

task snap(?p: place) (st, et) {
    hold(AT(): ?p, (st, et));
    hold(LINK(): true, (st, et));
    event(SHOT(?p): (false, true), et);
    (et - st) in [5s, 5s];
} nonPreemptive
";

const PROBLEM: &str = "problem shot;
domain relay;
horizon 10min;
object a, b: place;
initial {
    AT() = a;
    LINK() = false;
    SHOT(*) = false;
}
goal shot_b priority 1 { hold(SHOT(b): true, (st, et)); }
";

fn planned(domain: &str) -> PartialPlan {
    let d = parse_domain("relay.ixt", domain).expect("domain parses");
    let p = parse_problem("shot.ixt", PROBLEM, &d).expect("problem parses");
    let root = PartialPlan::new(Arc::new(d), Arc::new(p)).expect("root plan");
    let mut search = Search::new(root);
    assert_eq!(search.run(Budget::steps(2_000)), StepOutcome::Solved);
    search.into_plan()
}

fn action_named(plan: &PartialPlan, task: &str) -> mavtempo_temporal::plan::ActionId {
    plan.live_actions()
        .find(|&a| plan.domain().task(plan.action(a).task).name == task)
        .unwrap_or_else(|| panic!("{task} in the plan"))
}

#[test]
fn the_relay_waits_on_the_drive_in_the_dispatchable_network() {
    let mut plan = planned(DOMAIN);
    let drive = action_named(&plan, "drive");
    let relay = action_named(&plan, "relay");
    let (drive_st, drive_et) = (plan.action(drive).start, plan.action(drive).end);
    let relay_st = plan.action(relay).start;
    let t0 = plan.temporal_network().lb(drive_st);
    assert!(
        plan.temporal_network().lb(relay_st) <= t0,
        "the relay could open with the drive"
    );
    // Launched with the drive, then with the drive running: the relay waits for the drive's end, or
    // until the drive's longest duration (100 s) minus the 25 s the relay may open before the picture.
    let dc = plan
        .check_dc()
        .expect("DC: the relay can wait for the drive");
    let w = pending_wait(&plan, &dc, &[drive], relay_st, t0).expect("a wait on the drive");
    assert_eq!(w.action, drive);
    assert!(w.until >= t0 + 75_000, "{w:?}");
    plan.execute_at(drive_st, t0).expect("the drive starts");
    let dc = plan.check_dc().expect("still DC");
    let w = pending_wait(&plan, &dc, &[], relay_st, t0 + 1_000).expect("still waiting");
    assert_eq!(w.action, drive);
    // The drive's end is observed at 60 s: the wait is over (reactive), nothing else holds the relay.
    plan.execute_at(drive_et, 60_000)
        .expect("drive ends at 60 s");
    let dc = plan.check_dc().expect("still DC");
    assert_eq!(pending_wait(&plan, &dc, &[], relay_st, 60_000), None);
}

/// Only durations the domain marks `contingent` are protected: an unmarked drive is the executive's to
/// cut, and nothing waits on it.
#[test]
fn without_the_marker_nothing_waits_on_the_drive() {
    let plan = planned(&DOMAIN.replace("contingent ", ""));
    let relay_st = plan.action(action_named(&plan, "relay")).start;
    let dc = plan
        .check_dc()
        .expect("no contingent link: an STN, consistent");
    assert!(dc.network.links.is_empty());
    assert_eq!(dc.waits_on(relay_st).count(), 0);
}

#[test]
fn the_relay_waits_for_the_drive_instead_of_cutting_it_short() {
    let mut ex = Executive::new(
        planned(DOMAIN),
        ExecConfig {
            timestep_ms: 1_000,
            ..ExecConfig::default()
        },
    );
    let mut v = MockVehicle::new();
    v.script("drive", Outcome::nominal(60_000));
    v.script("relay", Outcome::nominal(25_000));
    v.script("snap", Outcome::nominal(5_000));
    let r = mission::run_mock(&mut ex, &mut v, 600_000);
    assert_eq!(r.end, MissionEnd::Finished, "{:?}", r.goals);
    assert_eq!(r.goals[0].fate, Fate::Achieved, "{:?}", r.goals);
    let events: Vec<(u64, &TraceEvent)> = r
        .cycles
        .iter()
        .flat_map(|c| c.events.iter().map(move |e| (c.time_ms as u64, e)))
        .collect();
    assert!(
        !events
            .iter()
            .any(|(_, e)| matches!(e, TraceEvent::Stop { .. } | TraceEvent::Abort { .. })),
        "nothing stopped or aborted: {events:?}"
    );
    let relay_start = events
        .iter()
        .find_map(|(t, e)| match e {
            TraceEvent::Launch { action, .. } if action.starts_with("relay") => Some(*t),
            _ => None,
        })
        .expect("the relay is launched");
    assert!(relay_start >= 60_000, "relay opened at {relay_start} ms");
    assert_eq!(r.counters.replans, 0);
}
