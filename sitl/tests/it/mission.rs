//! Mission protocol and AUTO over a real socket, as an independent ground station sees them.
#![allow(deprecated)]

use crate::support::*;
use mavlink::dialects::ardupilotmega::*;
use sitl::SimConfig;

#[tokio::test]
async fn three_waypoint_mission_runs_in_auto() {
    let sim = sitl::spawn(SimConfig::for_tests()).await.expect("spawn");
    let mut gcs = Gcs::connect(sim.local_addr()).await;
    let items = vec![
        waypoint(HOME, 0.0, 0.0),
        waypoint(HOME, 30.0, 0.0),
        waypoint(HOME, 30.0, 30.0),
        waypoint(HOME, 0.0, 30.0),
    ];
    assert_eq!(
        gcs.upload(&items).await,
        MavMissionResult::MAV_MISSION_ACCEPTED
    );
    assert_eq!(sim.snapshot().mission_total, 3);
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(gcs.set_mode(10).await, MavResult::MAV_RESULT_ACCEPTED);
    let s = run_until(&sim, 120, |s| s.mission_complete).await;
    assert!(
        s.north_m.abs() < 3.5 && (s.east_m - 30.0).abs() < 3.5,
        "{s:?}"
    );
    let mut reached = Vec::new();
    while reached.last() != Some(&3) {
        reached.push(expect_msg!(gcs, MISSION_ITEM_REACHED).await.seq);
    }
    assert_eq!(reached, vec![1, 2, 3]);
    assert!(s.statustexts.iter().any(|t| t == "Mission Complete"));
    assert_eq!(s.mode, "AUTO");
    assert!(s.armed);
    sim.stop().await;
}
