//! Each action binding driven over sockets against the built-in SITL (in process, port 0, manual clock):
//! the right report for each, read against the simulator's ground truth.

use crate::support::reports;

use std::time::{Duration, Instant};

use mavtempo_vehicle::config::VehicleConfig;
use mavtempo_vehicle::link::{LinkOptions, MavlinkVehicle};
use mavtempo_vehicle::{
    ActionReport, ActionStart, Arg, Enu, LinkStatus, ReportStatus, StateValue, Vehicle,
    VehicleEvent,
};
use sitl::{Fault, SimConfig, SimHandle};

fn config(address: &str) -> VehicleConfig {
    let text =
        std::fs::read_to_string(repo!("tests/fixtures/vehicle/bindings.toml")).expect("config");
    let mut cfg = VehicleConfig::parse(&text, "bindings.toml").expect("parses");
    cfg.link.address = address.to_string();
    cfg
}

struct Rig {
    sim: SimHandle,
    v: MavlinkVehicle,
    events: Vec<VehicleEvent>,
}

impl Rig {
    async fn new(sim_cfg: SimConfig) -> Self {
        let sim = sitl::spawn(sim_cfg).await.expect("sim");
        let v = MavlinkVehicle::connect(config(sim.client_address()), LinkOptions::default())
            .await
            .expect("link");
        let mut rig = Self {
            sim,
            v,
            events: Vec::new(),
        };
        rig.until("link up", 20_000, |e| {
            matches!(e, VehicleEvent::Link(LinkStatus::Up { .. }))
        })
        .await;
        // Let position and battery telemetry arrive.
        rig.run_for(2_000).await;
        rig
    }

    /// Steps the sim (100 ms at a time) until an event satisfies `pred`, within `sim_ms` of sim time.
    async fn until(
        &mut self,
        what: &str,
        sim_ms: u64,
        mut pred: impl FnMut(&VehicleEvent) -> bool,
    ) -> VehicleEvent {
        let start = self.sim.now_ms();
        let wall = Instant::now() + Duration::from_secs(60);
        loop {
            while let Some(e) = self.v.try_event() {
                if pred(&e) {
                    return e;
                }
                self.events.push(e);
            }
            assert!(
                self.sim.now_ms() - start <= sim_ms && Instant::now() < wall,
                "{what}: not within {sim_ms} ms of sim time"
            );
            self.sim
                .step(Duration::from_millis(100))
                .await
                .expect("step");
            // Give the companion's tasks a moment to answer what the step produced.
            tokio::time::sleep(Duration::from_millis(2)).await;
        }
    }

    async fn run_for(&mut self, sim_ms: u64) {
        let end = self.sim.now_ms() + sim_ms;
        while self.sim.now_ms() < end {
            self.sim
                .step(Duration::from_millis(100))
                .await
                .expect("step");
            tokio::time::sleep(Duration::from_millis(2)).await;
            while let Some(e) = self.v.try_event() {
                self.events.push(e);
            }
        }
    }

    async fn report(&mut self, id: u64, sim_ms: u64) -> ActionReport {
        match self
            .until(
                &format!("report of action {id}"),
                sim_ms,
                |e| matches!(e, VehicleEvent::Report(r) if r.id == id),
            )
            .await
        {
            VehicleEvent::Report(r) => r,
            _ => unreachable!(),
        }
    }

    /// Starts action `id` and waits (up to `sim_ms`) for its report, which must be nominal.
    async fn nominal(
        &mut self,
        id: u64,
        task: &str,
        args: Vec<(&str, Arg)>,
        sim_ms: u64,
    ) -> ActionReport {
        self.start(id, task, args);
        let r = self.report(id, sim_ms).await;
        assert_eq!(r.status, ReportStatus::Nominal, "{task}: {r:?}");
        r
    }

    fn start(&mut self, id: u64, task: &str, args: Vec<(&str, Arg)>) {
        let args = args.into_iter().map(|(n, a)| (n.to_string(), a)).collect();
        self.v
            .start(ActionStart {
                id,
                task: task.into(),
                args,
            })
            .expect("start");
    }
}

fn to(east: f64, north: f64) -> Vec<(&'static str, Arg)> {
    vec![("to", Arg::location("L1", Enu::new(east, north, 0.0)))]
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn move_reaches_its_destination_and_return_home_comes_back() {
    let mut rig = Rig::new(SimConfig::for_tests()).await;
    let r = rig.nominal(1, "move", to(30.0, 20.0), 60_000).await;
    let s = rig.sim.snapshot();
    assert!(
        (s.east_m - 30.0).hypot(s.north_m - 20.0) <= 3.5,
        "vehicle at ({}, {})",
        s.east_m,
        s.north_m
    );
    assert!(
        r.resources.iter().any(|l| l.resource == "battery"),
        "final battery level reported"
    );
    rig.nominal(2, "return_home", vec![], 60_000).await;
    let s = rig.sim.snapshot();
    assert!(
        s.east_m.hypot(s.north_m) <= 3.5,
        "home: ({}, {})",
        s.east_m,
        s.north_m
    );
    assert_eq!(s.mode, "RTL");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn stopped_move_is_interrupted_at_the_reached_position_and_the_rover_holds() {
    let mut rig = Rig::new(SimConfig::for_tests()).await;
    rig.start(1, "move", to(200.0, 0.0));
    rig.run_for(8_000).await;
    let before = rig.sim.snapshot();
    assert!(before.east_m > 5.0, "moving east: {}", before.east_m);
    rig.v.stop(1).expect("running");
    let r = rig.report(1, 1_000).await;
    assert_eq!(r.status, ReportStatus::Interrupted);
    let Some((var, StateValue::Position(p))) = r.state.first() else {
        panic!("{r:?}")
    };
    assert_eq!(var, "position");
    // The reported position is the vehicle's (telemetry is at most a few hundred ms old).
    assert!(
        (p.east - before.east_m).abs() < 5.0 && (p.north - before.north_m).abs() < 1.0,
        "{p:?} vs {before:?}"
    );
    rig.run_for(10_000).await;
    let after = rig.sim.snapshot();
    assert_eq!(after.mode, "HOLD");
    assert!(after.speed_mps < 0.1, "stopped, speed {}", after.speed_mps);
    assert!(
        after.east_m - before.east_m < 30.0,
        "stopped short of the destination: {}",
        after.east_m
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn move_fails_when_the_reposition_is_denied_and_on_a_navigation_failure() {
    let mut rig = Rig::new(SimConfig::for_tests()).await;
    rig.sim
        .inject(Fault::CommandFails {
            command: 192,
            result: sitl::FailResult::Denied,
            count: 1,
        })
        .expect("inject");
    rig.start(1, "move", to(50.0, 0.0));
    let r = rig.report(1, 10_000).await;
    reports::assert_failed(&r, "DENIED");
    rig.start(2, "move", to(100.0, 0.0));
    rig.run_for(4_000).await;
    rig.sim
        .inject(Fault::NavFails { duration_s: 0.0 })
        .expect("inject");
    let r = rig.report(2, 5_000).await;
    reports::assert_failed(&r, "no map available");
    assert!(
        matches!(r.state.first(), Some((_, StateValue::Position(_)))),
        "failed move reports its position"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn survey_runs_the_lawnmower_mission_to_its_last_item() {
    // Both request kinds: MISSION_REQUEST_INT, and the legacy MISSION_REQUEST real ArduPilot sends.
    for kind in [
        sitl::MissionRequestKind::Int,
        sitl::MissionRequestKind::Legacy,
    ] {
        let mut rig = Rig::new(SimConfig {
            mission_request: kind,
            ..SimConfig::for_tests()
        })
        .await;
        rig.start(
            1,
            "survey",
            vec![("area", Arg::location("Z1", Enu::new(25.0, 25.0, 0.0)))],
        );
        let r = rig.report(1, 240_000).await;
        assert_eq!(r.status, ReportStatus::Nominal, "{kind:?}: {r:?}");
        let s = rig.sim.snapshot();
        assert_eq!(s.mission_total, 8, "4 rows of 2 points");
        assert!(s.mission_complete);
        // The last point of the lawnmower: row 4 (north 25 - 15 + 30 = 40) ends on the west side (x = 5).
        assert!(
            (s.east_m - 5.0).hypot(s.north_m - 40.0) < 5.0,
            "({}, {})",
            s.east_m,
            s.north_m
        );
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pictures_succeed_or_fail_and_download_empties_the_storage() {
    let mut rig = Rig::new(SimConfig::for_tests()).await;
    rig.nominal(1, "take_picture", vec![], 10_000).await;
    assert_eq!(rig.sim.snapshot().pictures_ok, 1);
    rig.sim
        .inject(Fault::PictureFails { count: 1 })
        .expect("inject");
    rig.start(2, "take_picture", vec![]);
    let r = rig.report(2, 10_000).await;
    reports::assert_failed(&r, "capture_result 0");
    rig.run_for(1_000).await;
    let used = rig.sim.snapshot().storage_used_mib;
    assert!(used > 0.0, "the first picture is stored");
    // The storage level (available MiB) was reported after the captures.
    assert!(rig
        .events
        .iter()
        .any(|e| matches!(e, VehicleEvent::Resource(l) if l.resource == "storage")));
    let r = rig.nominal(3, "download", vec![], 60_000).await;
    assert!(rig.sim.snapshot().storage_used_mib <= 1e-6);
    let storage = r
        .resources
        .iter()
        .find(|l| l.resource == "storage")
        .expect("storage level in the report");
    assert!(
        (storage.level - rig.sim.snapshot().storage_capacity_mib).abs() < 1e-3,
        "{storage:?}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn sample_runs_the_servo_sequence() {
    let mut rig = Rig::new(SimConfig::for_tests()).await;
    rig.nominal(1, "sample", vec![], 10_000).await;
    let texts = rig.sim.snapshot().statustexts;
    assert!(
        texts.iter().any(|t| t == "Sampler deployed")
            && texts.iter().any(|t| t == "Sampler retracted"),
        "{texts:?}"
    );
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn recharge_holds_until_the_battery_is_back() {
    let mut rig = Rig::new(SimConfig::for_tests()).await;
    rig.sim
        .inject(Fault::BatteryDrop { percent: 10.0 })
        .expect("inject");
    rig.run_for(1_500).await;
    let low = rig.sim.snapshot().battery_pct;
    let target = (low + 2.0).floor();
    let r = rig
        .nominal(1, "recharge", vec![("level", Arg::Number(target))], 120_000)
        .await;
    let level = r
        .resources
        .iter()
        .find(|l| l.resource == "battery")
        .expect("battery")
        .level;
    assert!(level >= target, "{level} < {target}");
    assert_eq!(rig.sim.snapshot().mode, "HOLD");
}
