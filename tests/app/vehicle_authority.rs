//! Issue 30 item 1 over sockets, against the built-in SITL (in process, port 0, stepped): a ground
//! station's HOLD in the middle of a move gets no command from the companion for as long as it lasts (the
//! simulator counts every command that reaches it), the companion resumes when GUIDED is restored; with
//! `arm = "operator"` (config/ardupilot-rover.toml on the SITL's ArduPilot profile) the companion never
//! sends ARM and waits until someone else arms the vehicle. Also over the same sockets: `[authority]
//! at_end`, and a move started to end still (the next action needs the vehicle still) ends stopped.

use std::sync::Arc;
use std::time::Duration;

use mavtempo::exec::pacer::StepGate;
use mavtempo::sitl_pacer::SitlStepPacer;
use mavtempo::vehicle::authority::AuthorityEvent;
use mavtempo::vehicle::config::VehicleConfig;
use mavtempo::vehicle::link::{LinkOptions, MavlinkVehicle};
use mavtempo::vehicle::{ActionStart, Arg, Enu, ReportStatus, Vehicle, VehicleEvent};
use sitl::{Fault, SimConfig};

fn root(p: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

struct Rig {
    /// Runs the simulator and the link (kept for the rig's life).
    _rt: tokio::runtime::Runtime,
    sim: Arc<sitl::SimHandle>,
    v: MavlinkVehicle,
    pacer: SitlStepPacer,
    events: Vec<VehicleEvent>,
}

impl Rig {
    fn new(config: &str, scenario: &str) -> Rig {
        Self::with(config, scenario, |_| {})
    }

    /// [`Rig::new`] with the loaded configuration changed by `edit`.
    fn with(config: &str, scenario: &str, edit: impl FnOnce(&mut VehicleConfig)) -> Rig {
        let rt = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .enable_all()
            .build()
            .expect("runtime");
        let scenario = sitl::Scenario::load(&root(scenario)).expect("scenario");
        let sim_cfg = SimConfig {
            scenario,
            ..SimConfig::for_tests()
        };
        let sim = Arc::new(rt.block_on(sitl::spawn(sim_cfg)).expect("sim"));
        let mut cfg = VehicleConfig::load(&root(config)).expect("config");
        cfg.link.address = sim.client_address().to_string();
        cfg.link.heartbeat_timeout_ms = 60_000;
        edit(&mut cfg);
        let v = rt
            .block_on(MavlinkVehicle::connect(cfg, LinkOptions::default()))
            .expect("link");
        let pacer = SitlStepPacer::new(
            sim.clone(),
            rt.handle().clone(),
            0,
            500,
            Duration::from_secs(10),
            Arc::new(StepGate::default()),
        );
        Rig {
            _rt: rt,
            sim,
            v,
            pacer,
            events: Vec::new(),
        }
    }

    fn step(&mut self, ms: u64) {
        let end = self.sim.now_ms() + ms;
        while self.sim.now_ms() < end {
            self.pacer.step_settled(&self.v, 100).expect("step");
            while let Some(e) = self.v.try_event() {
                self.events.push(e);
            }
        }
    }

    fn ready(&mut self) -> mavtempo::vehicle::readiness::ReadyReport {
        let pacer = &self.pacer;
        self.v
            .wait_ready(120_000, Duration::from_secs(60), &mut |v| {
                pacer.step_settled(v, 100).is_ok()
            })
    }

    fn snapshot(&self) -> sitl::Snapshot {
        self.sim.snapshot()
    }

    fn move_to(&mut self, id: u64, east: f64) {
        self.v
            .start(ActionStart {
                id,
                task: "move".into(),
                args: vec![
                    ("from".into(), Arg::Symbol("here".into())),
                    (
                        "to".into(),
                        Arg::location("there", Enu::new(east, 0.0, 0.0)),
                    ),
                ],
            })
            .expect("started");
    }

    fn paused(&self) -> bool {
        self.events.iter().any(|e| {
            matches!(e, VehicleEvent::Authority(AuthorityEvent::Paused { why }) if why.contains("HOLD"))
        })
    }

    fn resumed(&self) -> bool {
        self.events
            .iter()
            .any(|e| matches!(e, VehicleEvent::Authority(AuthorityEvent::Resumed { .. })))
    }

    /// A HOLD 4 s into a move, GUIDED again 15 s later: no command reaches the simulator in between.
    fn hold_and_hand_back(&mut self) {
        self.move_to(1, 80.0);
        self.step(4_000);
        assert!(self.snapshot().speed_mps > 0.2, "moving");
        self.sim
            .inject(Fault::ModeChange { mode: 4 })
            .expect("inject");
        self.step(1_000);
        assert!(self.paused(), "{:?}", self.events);
        assert!(self
            .events
            .iter()
            .any(|e| matches!(e, VehicleEvent::Report(r)
            if r.id == 1 && r.status == ReportStatus::Interrupted)));
        let before = self.snapshot().control_commands;
        self.step(15_000);
        let during = self.snapshot();
        assert_eq!(during.custom_mode, 4, "still in HOLD");
        assert_eq!(
            during.control_commands, before,
            "no command from the companion while the operator has the vehicle"
        );
        assert!(!self.resumed());
        self.sim
            .inject(Fault::ModeChange { mode: 15 })
            .expect("inject");
        self.step(1_000);
        assert!(self.resumed(), "{:?}", self.events);
        self.move_to(2, 80.0);
        self.step(2_000);
        assert!(
            self.snapshot().control_commands > before,
            "commanding again"
        );
    }
}

#[test]
fn a_foreign_hold_gets_no_command_until_guided_is_restored() {
    let mut rig = Rig::new("config/sitl-rover.toml", "sitl/scenarios/fig2.toml");
    let ready = rig.ready();
    assert!(ready.ready, "{ready:?}");
    rig.hold_and_hand_back();
}

#[test]
fn on_the_ardupilot_profile_the_operator_arms_and_the_companion_yields_to_a_hold() {
    let mut rig = Rig::new(
        "config/ardupilot-rover.toml",
        "sitl/scenarios/ardupilot-rover.toml",
    );
    let ready = rig.ready();
    assert!(ready.ready, "{ready:?}");
    // The scenario's ground station arms at 25 s; the companion sent no ARM.
    assert!(rig.snapshot().time_ms >= 25_000);
    assert_eq!(ready.arm_attempts, 0);
    assert_eq!(rig.snapshot().arm_commands, 0);
    rig.hold_and_hand_back();
    assert_eq!(
        rig.snapshot().arm_commands,
        0,
        "never an ARM from the companion"
    );
}

/// `[authority] at_end`: the default leaves the rover in HOLD and disarmed when the mission ends; `hold`
/// leaves it armed in HOLD; `none` leaves it as it is (GUIDED, armed).
#[test]
fn at_the_end_of_a_mission_the_default_holds_and_disarms() {
    use mavtempo::vehicle::authority::AtEnd;
    for (at_end, mode, armed) in [
        (None, 4, false),
        (Some(AtEnd::Hold), 4, true),
        (Some(AtEnd::None), 15, true),
    ] {
        let mut rig = Rig::with("config/sitl-rover.toml", "sitl/scenarios/fig2.toml", |c| {
            if let Some(a) = at_end {
                c.authority.at_end = a;
            }
        });
        assert!(rig.ready().ready);
        rig.move_to(1, 10.0);
        rig.step(2_000);
        let moving = rig.snapshot();
        assert!(moving.armed && moving.custom_mode == 15, "{moving:?}");
        let before = rig.events.len();
        rig.v.end_of_mission();
        rig.step(3_000);
        // Its own HOLD and disarm are no operator taking control: no pause after the mission.
        assert!(
            !rig.events[before..]
                .iter()
                .any(|e| matches!(e, VehicleEvent::Authority(AuthorityEvent::Paused { .. }))),
            "{:?}",
            &rig.events[before..]
        );
        let end = rig.snapshot();
        assert_eq!(
            (end.custom_mode, end.armed),
            (mode, armed),
            "at_end {at_end:?}: {} {:?}",
            end.mode,
            end.statustexts
        );
    }
}

/// The rover's ground speed when a move's nominal report arrives, started with `start` or `start_still`.
fn speed_at_report(still: bool) -> f64 {
    let mut rig = Rig::new("config/sitl-rover.toml", "sitl/scenarios/fig2.toml");
    assert!(rig.ready().ready);
    let start = ActionStart {
        id: 7,
        task: "move".into(),
        args: vec![
            ("from".into(), Arg::Symbol("here".into())),
            (
                "to".into(),
                Arg::location("there", Enu::new(12.0, 0.0, 0.0)),
            ),
        ],
    };
    let started = if still {
        rig.v.start_still(start)
    } else {
        rig.v.start(start)
    };
    started.expect("started");
    for _ in 0..600 {
        rig.step(100);
        let done = rig.events.iter().any(|e| {
            matches!(e, VehicleEvent::Report(r) if r.id == 7 && r.status == ReportStatus::Nominal)
        });
        if done {
            return rig.snapshot().speed_mps;
        }
    }
    panic!("no nominal report within 60 s: {:?}", rig.events);
}

/// On the built-in SITL (0.45 m/s, 1.5 m acceptance radius): a move reports as it enters the radius,
/// still rolling; started to end still, it reports once the rover is below `[state] still_below_m_s`.
#[test]
fn a_move_started_to_end_still_reports_once_the_rover_has_stopped() {
    let rolling = speed_at_report(false);
    assert!(
        rolling > 0.3,
        "enters the radius at cruise speed: {rolling}"
    );
    let still = speed_at_report(true);
    assert!(still <= 0.2, "stopped: {still}");
}
