//! Every action binding of tests/fixtures/vehicle/bindings.toml, driven in memory (no sockets, manual clock)
//! against a scripted autopilot that answers like ArduPilot Rover; each report kind is checked.

// ArduPilot asks for items with the legacy MISSION_REQUEST: the scripted autopilot does too.
#![allow(deprecated)]

use crate::support::reports;

use mavlink::dialects::ardupilotmega::*;
use mavlink::MavHeader;
use mavtempo_vehicle::config::VehicleConfig;
use mavtempo_vehicle::driver::Driver;
use mavtempo_vehicle::{ActionStart, Arg, Enu, LinkStatus, ReportStatus, StateValue, VehicleEvent};

const FIXTURE: &str = repo!("tests/fixtures/vehicle/bindings.toml");

fn config() -> VehicleConfig {
    VehicleConfig::load(std::path::Path::new(FIXTURE)).expect("shipped config parses")
}

/// The fixture for a PX4 autopilot (the same bindings).
fn px4_config() -> VehicleConfig {
    let text = std::fs::read_to_string(FIXTURE).expect("fixture readable");
    let cfg = VehicleConfig::parse(&format!("autopilot = \"px4\"\n{text}"), "px4 fixture")
        .expect("fixture parses");
    assert_eq!(cfg.autopilot, mavtempo_vehicle::config::Autopilot::Px4);
    cfg
}

/// The fixture with `[authority] on_foreign_mode = "repair"`: a foreign mode fails the running motion.
fn repair_config() -> VehicleConfig {
    let text = std::fs::read_to_string(FIXTURE).expect("fixture readable");
    VehicleConfig::parse(
        &format!("{text}\n[authority]\non_foreign_mode = \"repair\"\n"),
        "repair fixture",
    )
    .expect("fixture parses")
}

/// The fixture with `[authority] arm = "operator"`.
fn operator_config() -> VehicleConfig {
    let text = std::fs::read_to_string(FIXTURE).expect("fixture readable");
    VehicleConfig::parse(
        &format!("{text}\n[authority]\narm = \"operator\"\n"),
        "operator fixture",
    )
    .expect("fixture parses")
}

/// A scripted ArduPilot-like autopilot: answers commands and the mission protocol, holds a position.
struct Autopilot {
    mode: u32,
    armed: bool,
    /// Result given to the next command with this id (default ACCEPTED).
    results: Vec<(MavCmd, MavResult)>,
    /// Commands seen, in order.
    seen: Vec<MavMessage>,
    mission: Vec<MISSION_ITEM_INT_DATA>,
    upload_count: Option<u16>,
    /// CAMERA_IMAGE_CAPTURED result to send, or none at all.
    capture: Option<bool>,
    /// Confirm pictures as ArduPilot's camera library does: CAMERA_FEEDBACK, no CAMERA_IMAGE_CAPTURED.
    feedback: bool,
    images: u16,
    answer_commands: bool,
}

impl Autopilot {
    fn new() -> Self {
        Self {
            mode: 0,
            armed: false,
            results: Vec::new(),
            seen: Vec::new(),
            mission: Vec::new(),
            upload_count: None,
            capture: Some(true),
            feedback: false,
            images: 0,
            answer_commands: true,
        }
    }

    fn heartbeat(&self) -> MavMessage {
        MavMessage::HEARTBEAT(HEARTBEAT_DATA {
            custom_mode: self.mode,
            mavtype: MavType::MAV_TYPE_GROUND_ROVER,
            autopilot: MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
            base_mode: if self.armed {
                MavModeFlag::MAV_MODE_FLAG_SAFETY_ARMED
            } else {
                MavModeFlag::empty()
            },
            system_status: MavState::MAV_STATE_ACTIVE,
            mavlink_version: 3,
        })
    }

    fn result_for(&mut self, cmd: MavCmd) -> MavResult {
        match self.results.iter().position(|(c, _)| *c == cmd) {
            Some(i) => self.results.remove(i).1,
            None => MavResult::MAV_RESULT_ACCEPTED,
        }
    }

    /// Answers what the companion sent.
    fn respond(&mut self, sent: Vec<MavMessage>) -> Vec<MavMessage> {
        let mut replies = Vec::new();
        for m in sent {
            match &m {
                MavMessage::COMMAND_LONG(c) => {
                    self.seen.push(m.clone());
                    if !self.answer_commands {
                        continue;
                    }
                    let result = self.result_for(c.command);
                    if result == MavResult::MAV_RESULT_ACCEPTED {
                        match c.command {
                            MavCmd::MAV_CMD_DO_SET_MODE => self.mode = c.param2 as u32,
                            MavCmd::MAV_CMD_COMPONENT_ARM_DISARM => self.armed = c.param1 == 1.0,
                            _ => {}
                        }
                    }
                    replies.push(ack(c.command, result));
                    let captured = c.command == MavCmd::MAV_CMD_IMAGE_START_CAPTURE
                        && result == MavResult::MAV_RESULT_ACCEPTED;
                    if captured && self.feedback {
                        self.images += 1;
                        replies.push(MavMessage::CAMERA_FEEDBACK(CAMERA_FEEDBACK_DATA {
                            img_idx: self.images,
                            completed_captures: self.images,
                            ..Default::default()
                        }));
                        continue;
                    }
                    if let (
                        MavCmd::MAV_CMD_IMAGE_START_CAPTURE,
                        MavResult::MAV_RESULT_ACCEPTED,
                        Some(ok),
                    ) = (c.command, result, self.capture)
                    {
                        replies.push(MavMessage::CAMERA_IMAGE_CAPTURED(
                            CAMERA_IMAGE_CAPTURED_DATA {
                                image_index: 1,
                                capture_result: if ok {
                                    MavBool::MAV_BOOL_TRUE
                                } else {
                                    MavBool::MAV_BOOL_FALSE
                                },
                                ..Default::default()
                            },
                        ));
                    }
                }
                MavMessage::COMMAND_INT(c) => {
                    self.seen.push(m.clone());
                    let result = self.result_for(c.command);
                    if result == MavResult::MAV_RESULT_ACCEPTED
                        && c.command == MavCmd::MAV_CMD_DO_REPOSITION
                    {
                        self.mode = 15;
                    }
                    replies.push(ack(c.command, result));
                }
                MavMessage::MISSION_COUNT(c) => {
                    self.upload_count = Some(c.count);
                    self.mission.clear();
                    // ArduPilot asks with the legacy MISSION_REQUEST.
                    replies.push(MavMessage::MISSION_REQUEST(MISSION_REQUEST_DATA {
                        seq: 0,
                        target_system: 1,
                        target_component: 191,
                        mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
                    }));
                }
                MavMessage::MISSION_ITEM_INT(it) => {
                    self.mission.push(it.clone());
                    let n = self.upload_count.unwrap_or(0);
                    if (self.mission.len() as u16) < n {
                        replies.push(MavMessage::MISSION_REQUEST(MISSION_REQUEST_DATA {
                            seq: self.mission.len() as u16,
                            target_system: 1,
                            target_component: 191,
                            mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
                        }));
                    } else {
                        replies.push(MavMessage::MISSION_ACK(MISSION_ACK_DATA {
                            mavtype: MavMissionResult::MAV_MISSION_ACCEPTED,
                            ..Default::default()
                        }));
                    }
                }
                _ => {}
            }
        }
        replies
    }
}

fn ack(command: MavCmd, result: MavResult) -> MavMessage {
    MavMessage::COMMAND_ACK(COMMAND_ACK_DATA {
        command,
        result,
        ..Default::default()
    })
}

fn position(cfg: &VehicleConfig, at: Enu) -> MavMessage {
    let (lat, lon, alt) = cfg.home.to_global(at);
    MavMessage::GLOBAL_POSITION_INT(GLOBAL_POSITION_INT_DATA {
        time_boot_ms: 1000,
        lat: (lat * 1e7).round() as i32,
        lon: (lon * 1e7).round() as i32,
        alt: (alt * 1e3) as i32,
        ..Default::default()
    })
}

struct Bench {
    d: Driver,
    ap: Autopilot,
    now: u64,
    events: Vec<VehicleEvent>,
}

const AP: MavHeader = MavHeader {
    system_id: 1,
    component_id: 1,
    sequence: 0,
};

impl Bench {
    fn new() -> Self {
        Self::with(config())
    }

    fn with(cfg: VehicleConfig) -> Self {
        let mut b = Self {
            d: Driver::new(cfg),
            ap: Autopilot::new(),
            now: 0,
            events: Vec::new(),
        };
        b.feed(b.ap.heartbeat());
        b
    }

    /// Delivers a message from the autopilot and lets the conversation run to quiescence.
    fn feed(&mut self, msg: MavMessage) {
        self.d.handle(AP, &msg, self.now);
        self.settle();
    }

    fn settle(&mut self) {
        for _ in 0..1000 {
            let out: Vec<MavMessage> = self
                .d
                .take_outgoing()
                .into_iter()
                .filter(|m| !matches!(m, MavMessage::HEARTBEAT(_)))
                .collect();
            if out.is_empty() {
                break;
            }
            for r in self.ap.respond(out) {
                self.d.handle(AP, &r, self.now);
            }
        }
        self.events.extend(self.d.take_events());
    }

    fn tick(&mut self, ms: u64) {
        self.now += ms;
        self.d.tick(self.now);
        self.settle();
    }

    fn start(&mut self, id: u64, task: &str, args: Vec<(&str, Arg)>) {
        self.try_start(id, task, args).expect("start accepted");
    }

    fn try_start(
        &mut self,
        id: u64,
        task: &str,
        args: Vec<(&str, Arg)>,
    ) -> Result<(), mavtempo_vehicle::VehicleError> {
        let args = args.into_iter().map(|(n, a)| (n.to_string(), a)).collect();
        let started = self.d.start(
            ActionStart {
                id,
                task: task.into(),
                args,
            },
            self.now,
        );
        self.settle();
        started
    }

    /// The report of action `id`, which must be a failure naming `why`.
    fn failed(&mut self, id: u64, why: &str) -> mavtempo_vehicle::ActionReport {
        let r = self.report(id).expect("report");
        reports::assert_failed(&r, why);
        r
    }

    fn report(&mut self, id: u64) -> Option<mavtempo_vehicle::ActionReport> {
        let i = self
            .events
            .iter()
            .position(|e| matches!(e, VehicleEvent::Report(r) if r.id == id))?;
        match self.events.remove(i) {
            VehicleEvent::Report(r) => Some(r),
            _ => None,
        }
    }
}

fn to(at: Enu) -> Vec<(&'static str, Arg)> {
    vec![("to", Arg::location("L2", at))]
}

#[test]
fn link_comes_up_on_the_autopilot_heartbeat_and_adopts_its_system_id() {
    let mut d = Driver::new(config());
    let h = MavHeader {
        system_id: 42,
        component_id: 1,
        sequence: 0,
    };
    d.handle(h, &Autopilot::new().heartbeat(), 0);
    assert_eq!(d.system_id, 42);
    assert!(matches!(
        d.take_events()[..],
        [VehicleEvent::Link(LinkStatus::Up { system_id: 42 })]
    ));
    d.tick(100);
    let out = d.take_outgoing();
    assert!(out.iter().any(|m| matches!(m, MavMessage::HEARTBEAT(h) if h.mavtype == MavType::MAV_TYPE_ONBOARD_CONTROLLER)));
}

#[test]
fn move_is_nominal_within_the_acceptance_radius() {
    let mut b = Bench::new();
    let dest = Enu::new(30.0, 40.0, 0.0);
    b.start(1, "move", to(dest));
    // Disarmed rover: ARM first, then DO_REPOSITION with the change-mode flag over COMMAND_INT.
    assert!(
        matches!(&b.ap.seen[0], MavMessage::COMMAND_LONG(c) if c.command == MavCmd::MAV_CMD_COMPONENT_ARM_DISARM)
    );
    let MavMessage::COMMAND_INT(rep) = &b.ap.seen[1] else {
        panic!("expected COMMAND_INT, got {:?}", b.ap.seen[1])
    };
    assert_eq!(rep.command, MavCmd::MAV_CMD_DO_REPOSITION);
    assert_eq!(rep.param2, 1.0);
    let (lat, lon, _) = b.d.config().home.to_global(dest);
    assert_eq!(
        (rep.x, rep.y),
        ((lat * 1e7).round() as i32, (lon * 1e7).round() as i32)
    );
    let cfg = config();
    b.feed(position(&cfg, Enu::new(10.0, 10.0, 0.0)));
    assert!(b.report(1).is_none(), "not there yet");
    b.feed(position(&cfg, Enu::new(29.0, 38.5, 0.0)));
    let r = b.report(1).expect("report");
    assert_eq!(r.status, ReportStatus::Nominal);
    assert!(r.state.is_empty());
}

#[test]
fn stopped_move_is_interrupted_with_the_reached_position_and_holds() {
    let mut b = Bench::new();
    b.start(1, "move", to(Enu::new(100.0, 0.0, 0.0)));
    let cfg = config();
    b.feed(position(&cfg, Enu::new(42.0, 1.0, 0.0)));
    b.d.stop(1, b.now).expect("running");
    b.settle();
    let r = b.report(1).expect("report");
    assert_eq!(r.status, ReportStatus::Interrupted);
    let StateValue::Position(p) = &r.state[0].1 else {
        panic!("{:?}", r.state)
    };
    assert_eq!(r.state[0].0, "position");
    assert!(
        (p.east - 42.0).abs() < 0.1 && (p.north - 1.0).abs() < 0.1,
        "{p:?}"
    );
    assert_eq!(b.ap.mode, 4, "HOLD after END");
}

#[test]
fn move_fails_on_denied_reposition() {
    let mut b = Bench::new();
    b.ap.armed = true;
    b.feed(b.ap.heartbeat());
    b.ap.results
        .push((MavCmd::MAV_CMD_DO_REPOSITION, MavResult::MAV_RESULT_DENIED));
    b.start(1, "move", to(Enu::new(10.0, 0.0, 0.0)));
    b.failed(1, "DENIED");
}

#[test]
fn move_fails_on_a_foreign_mode_change_when_the_config_says_repair() {
    let mut b = Bench::with(repair_config());
    b.start(1, "move", to(Enu::new(10.0, 0.0, 0.0)));
    b.feed(b.ap.heartbeat()); // GUIDED seen
    assert!(b.report(1).is_none());
    b.ap.mode = 0; // someone switched to MANUAL
    b.feed(b.ap.heartbeat());
    b.failed(1, "foreign mode change");
}

#[test]
fn an_error_statustext_fails_the_running_action() {
    let mut b = Bench::new();
    b.start(1, "move", to(Enu::new(10.0, 0.0, 0.0)));
    let mut text = [0u8; 50];
    text[..19].copy_from_slice(b"no map available!!!");
    b.feed(MavMessage::STATUSTEXT(STATUSTEXT_DATA {
        severity: MavSeverity::MAV_SEVERITY_ERROR,
        text: text.into(),
        id: 0,
        chunk_seq: 0,
    }));
    b.failed(1, "no map available");
}

#[test]
fn command_without_ack_is_retried_with_confirmation_then_fails() {
    let mut b = Bench::new();
    b.ap.answer_commands = false;
    b.start(1, "recharge", vec![]);
    for _ in 0..5 {
        b.tick(1000);
    }
    let confirmations: Vec<u8> =
        b.ap.seen
            .iter()
            .filter_map(|m| match m {
                MavMessage::COMMAND_LONG(c) => Some(c.confirmation),
                _ => None,
            })
            .collect();
    assert_eq!(confirmations, vec![0, 1, 2, 3]);
    b.failed(1, "no COMMAND_ACK");
}

#[test]
fn survey_uploads_a_lawnmower_runs_auto_and_ends_on_the_last_item_reached() {
    let mut b = Bench::new();
    b.start(
        3,
        "survey",
        vec![("area", Arg::location("Z1", Enu::new(50.0, 50.0, 0.0)))],
    );
    // 40 x 30 m at 10 m spacing: 4 rows of 2 points, plus item 0 for home.
    assert_eq!(b.ap.mission.len(), 9);
    let first = &b.ap.mission[1];
    let (lat, lon, _) = b.d.config().home.to_global(Enu::new(30.0, 35.0, 0.0));
    assert_eq!(
        (first.x, first.y),
        ((lat * 1e7).round() as i32, (lon * 1e7).round() as i32)
    );
    assert!(b.ap.seen.iter().any(|m| matches!(m, MavMessage::COMMAND_LONG(c) if c.command == MavCmd::MAV_CMD_DO_SET_MISSION_CURRENT && c.param1 == 1.0)));
    assert_eq!(b.ap.mode, 10, "AUTO");
    b.feed(MavMessage::MISSION_ITEM_REACHED(
        MISSION_ITEM_REACHED_DATA { seq: 7 },
    ));
    assert!(b.report(3).is_none());
    b.feed(MavMessage::MISSION_ITEM_REACHED(
        MISSION_ITEM_REACHED_DATA { seq: 8 },
    ));
    assert_eq!(b.report(3).expect("report").status, ReportStatus::Nominal);
}

/// STORAGE_INFORMATION of a 3 MiB card with `used` MiB used.
fn storage(used: f32) -> MavMessage {
    MavMessage::STORAGE_INFORMATION(STORAGE_INFORMATION_DATA {
        total_capacity: 3.0,
        used_capacity: used,
        available_capacity: 3.0 - used,
        storage_count: 1,
        storage_id: 1,
        ..Default::default()
    })
}

#[test]
fn take_picture_nominal_failed_on_capture_result_and_on_timeout() {
    let mut b = Bench::new();
    b.start(4, "take_picture", vec![]);
    // The capture triggers a STORAGE_INFORMATION request; the report waits for it, to carry the level.
    assert!(b.ap.seen.iter().any(|m| matches!(m, MavMessage::COMMAND_LONG(c) if c.command == MavCmd::MAV_CMD_REQUEST_MESSAGE && c.param1 == 261.0)));
    assert!(b.report(4).is_none());
    b.feed(storage(2.0));
    let r = b.report(4).expect("report");
    assert_eq!(r.status, ReportStatus::Nominal);
    assert!(r
        .resources
        .iter()
        .any(|l| l.resource == "storage" && (l.level - 1.0).abs() < 1e-9));

    b.ap.capture = Some(false);
    b.start(5, "take_picture", vec![]);
    b.feed(storage(2.0));
    b.failed(5, "capture_result 0");

    let mut b = Bench::new();
    b.ap.capture = None;
    b.start(6, "take_picture", vec![]);
    b.tick(5000);
    assert!(b.report(6).is_none());
    b.tick(5001);
    b.failed(6, "within");
}

#[test]
fn sample_runs_its_servo_sequence() {
    let mut b = Bench::new();
    b.start(7, "sample", vec![]);
    let servo: Vec<(f32, f32)> =
        b.ap.seen
            .iter()
            .filter_map(|m| match m {
                MavMessage::COMMAND_LONG(c) if c.command == MavCmd::MAV_CMD_DO_SET_SERVO => {
                    Some((c.param1, c.param2))
                }
                _ => None,
            })
            .collect();
    assert_eq!(servo, vec![(9.0, 1900.0)]);
    b.tick(1999);
    assert!(b.report(7).is_none());
    b.tick(1);
    assert!(b.report(7).is_none(), "second step holds");
    b.tick(999);
    assert!(b.report(7).is_none());
    b.tick(1);
    assert_eq!(b.report(7).expect("report").status, ReportStatus::Nominal);
    let n = b.ap.seen.iter().filter(|m| matches!(m, MavMessage::COMMAND_LONG(c) if c.command == MavCmd::MAV_CMD_DO_SET_SERVO)).count();
    assert_eq!(n, 2);
}

#[test]
fn return_home_sets_rtl_and_ends_at_home() {
    let mut b = Bench::new();
    b.ap.armed = true;
    b.feed(b.ap.heartbeat());
    b.start(8, "return_home", vec![]);
    assert_eq!(b.ap.mode, 11, "RTL");
    let cfg = config();
    b.feed(position(&cfg, Enu::new(20.0, 0.0, 0.0)));
    assert!(b.report(8).is_none());
    b.feed(position(&cfg, Enu::new(1.0, 1.0, 0.0)));
    assert_eq!(b.report(8).expect("report").status, ReportStatus::Nominal);
}

#[test]
fn recharge_holds_until_the_battery_level_and_reports_it() {
    let mut b = Bench::new();
    b.start(9, "recharge", vec![("level", Arg::Number(80.0))]);
    assert_eq!(b.ap.mode, 4, "HOLD");
    let battery = |pct| {
        MavMessage::BATTERY_STATUS(BATTERY_STATUS_DATA {
            battery_remaining: pct,
            ..Default::default()
        })
    };
    b.feed(battery(70));
    assert!(b.report(9).is_none());
    b.feed(battery(81));
    let r = b.report(9).expect("report");
    assert_eq!(r.status, ReportStatus::Nominal);
    assert_eq!(r.resources[0].resource, "battery");
    assert_eq!(r.resources[0].level, 81.0);
}

#[test]
fn download_polls_storage_until_emptied_and_capacity_changes_are_reported() {
    let mut b = Bench::new();
    let storage = |used: f32, total: f32| {
        MavMessage::STORAGE_INFORMATION(STORAGE_INFORMATION_DATA {
            total_capacity: total,
            used_capacity: used,
            available_capacity: total - used,
            ..Default::default()
        })
    };
    b.feed(storage(300.0, 1000.0));
    b.start(10, "download", vec![]);
    assert!(b
        .ap
        .seen
        .iter()
        .any(|m| matches!(m, MavMessage::COMMAND_LONG(c) if c.command == MavCmd::MAV_CMD_USER_1)));
    b.tick(1000);
    let polls = b.ap.seen.iter().filter(|m| matches!(m, MavMessage::COMMAND_LONG(c) if c.command == MavCmd::MAV_CMD_REQUEST_MESSAGE)).count();
    assert!(polls >= 2, "polled {polls} times");
    b.feed(storage(100.0, 800.0));
    assert!(b.report(10).is_none());
    assert!(b.events.iter().any(
        |e| matches!(e, VehicleEvent::Capacity(c) if c.resource == "storage" && c.delta == -200.0)
    ));
    b.feed(storage(0.0, 800.0));
    let r = b.report(10).expect("report");
    assert_eq!(r.status, ReportStatus::Nominal);
    assert!(r
        .resources
        .iter()
        .any(|l| l.resource == "storage" && l.level == 800.0));
}

#[test]
fn link_loss_by_heartbeat_timeout_then_recovery() {
    let mut b = Bench::new();
    b.tick(3000);
    assert!(!b
        .events
        .iter()
        .any(|e| matches!(e, VehicleEvent::Link(LinkStatus::Lost))));
    b.tick(1);
    assert!(b
        .events
        .iter()
        .any(|e| matches!(e, VehicleEvent::Link(LinkStatus::Lost))));
    b.feed(b.ap.heartbeat());
    assert!(matches!(
        b.events.last(),
        Some(VehicleEvent::Link(LinkStatus::Recovered))
    ));
}

#[test]
fn unknown_task_and_bad_arguments_are_refused_at_start() {
    let mut d = Driver::new(config());
    let e = d
        .start(
            ActionStart {
                id: 1,
                task: "fly".into(),
                args: vec![],
            },
            0,
        )
        .unwrap_err();
    assert!(e.to_string().contains("no binding for task `fly`"));
    let e = d
        .start(
            ActionStart {
                id: 1,
                task: "move".into(),
                args: vec![],
            },
            0,
        )
        .unwrap_err();
    assert!(e.to_string().contains("location argument `to`"), "{e}");
}

/// GLOBAL_POSITION_INT at `at`, moving east at `speed` m/s, at vehicle time `ms`.
fn moving(cfg: &VehicleConfig, at: Enu, speed: f64, ms: u32) -> MavMessage {
    let MavMessage::GLOBAL_POSITION_INT(mut p) = position(cfg, at) else {
        unreachable!()
    };
    p.vy = (speed * 100.0) as i16;
    p.time_boot_ms = ms;
    MavMessage::GLOBAL_POSITION_INT(p)
}

fn commands(ap: &Autopilot) -> Vec<(MavCmd, f32, f32)> {
    ap.seen
        .iter()
        .filter_map(|m| match m {
            MavMessage::COMMAND_LONG(c) => Some((c.command, c.param1, c.param2)),
            MavMessage::COMMAND_INT(c) => Some((c.command, c.param1, c.param2)),
            _ => None,
        })
        .collect()
}

#[test]
fn ardupilot_gets_the_move_speed_by_do_change_speed_once_in_guided() {
    let mut b = Bench::new();
    b.start(1, "slow_move", to(Enu::new(30.0, 0.0, 0.0)));
    // ArduPilot fails DO_REPOSITION with a speed from GUIDED's Stop submode: no speed in it, then
    // DO_CHANGE_SPEED (ground speed) after its ACK.
    let cmds = commands(&b.ap);
    assert_eq!(
        cmds,
        vec![
            (MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, 1.0, 0.0),
            (MavCmd::MAV_CMD_DO_REPOSITION, -1.0, 1.0),
            (MavCmd::MAV_CMD_DO_CHANGE_SPEED, 1.0, 0.45),
        ]
    );
    // A move without a speed of its own sends none.
    let mut b = Bench::new();
    b.start(2, "move", to(Enu::new(30.0, 0.0, 0.0)));
    assert!(!commands(&b.ap)
        .iter()
        .any(|c| c.0 == MavCmd::MAV_CMD_DO_CHANGE_SPEED));
}

#[test]
fn px4_gets_the_move_speed_in_do_reposition() {
    let mut b = Bench::with(px4_config());
    b.start(1, "slow_move", to(Enu::new(30.0, 0.0, 0.0)));
    let cmds = commands(&b.ap);
    assert!(
        cmds.contains(&(MavCmd::MAV_CMD_DO_REPOSITION, 0.45, 1.0)),
        "{cmds:?}"
    );
    assert!(!cmds.iter().any(|c| c.0 == MavCmd::MAV_CMD_DO_CHANGE_SPEED));
}

#[test]
fn a_refused_speed_does_not_fail_the_move() {
    let mut b = Bench::new();
    b.ap.results.push((
        MavCmd::MAV_CMD_DO_CHANGE_SPEED,
        MavResult::MAV_RESULT_FAILED,
    ));
    let dest = Enu::new(30.0, 0.0, 0.0);
    b.start(1, "slow_move", to(dest));
    assert!(
        b.report(1).is_none(),
        "the move goes on at the autopilot's speed"
    );
    let cfg = config();
    b.feed(position(&cfg, dest));
    assert_eq!(b.report(1).expect("report").status, ReportStatus::Nominal);
}

#[test]
fn a_picture_ends_on_camera_feedback_as_ardupilot_confirms_it() {
    let mut b = Bench::new();
    b.ap.feedback = true;
    b.start(4, "take_picture", vec![]);
    // At once: no storage answer is waited for (ArduPilot sends none).
    let r = b.report(4).expect("report on CAMERA_FEEDBACK");
    assert_eq!(r.status, ReportStatus::Nominal);
    // A second picture is not confirmed by the first one's feedback, sent again late.
    b.ap.capture = None;
    b.ap.answer_commands = true;
    b.ap.feedback = false;
    b.start(5, "take_picture", vec![]);
    b.feed(MavMessage::CAMERA_FEEDBACK(CAMERA_FEEDBACK_DATA {
        img_idx: 1,
        completed_captures: 1,
        ..Default::default()
    }));
    b.feed(storage(1.0));
    assert!(
        b.report(5).is_none(),
        "an old feedback is not this picture's"
    );
    b.feed(MavMessage::CAMERA_FEEDBACK(CAMERA_FEEDBACK_DATA {
        img_idx: 2,
        completed_captures: 2,
        ..Default::default()
    }));
    assert_eq!(b.report(5).expect("report").status, ReportStatus::Nominal);
}

#[test]
fn a_failed_move_is_reported_once_still_with_the_observed_state() {
    let cfg = config();
    let mut b = Bench::with(repair_config());
    b.start(1, "move", to(Enu::new(30.0, 0.0, 0.0)));
    b.feed(b.ap.heartbeat()); // GUIDED seen
    b.feed(moving(&cfg, Enu::new(10.0, 0.0, 0.0), 0.5, 2_000));
    b.ap.mode = 4; // a foreign HOLD: the rover brakes
    b.feed(b.ap.heartbeat());
    assert!(b.report(1).is_none(), "still moving: the report waits");
    b.feed(moving(&cfg, Enu::new(10.3, 0.0, 0.0), 0.1, 3_000));
    let r = b.report(1).expect("report once still");
    reports::assert_failed(&r, "foreign mode change");
    assert!(
        r.state
            .contains(&("STATUS".to_string(), StateValue::Symbol("STILL".into()))),
        "{:?}",
        r.state
    );
    assert!(
        matches!(r.state[0], (ref v, StateValue::Position(p)) if v == "position" && (p.east - 10.3).abs() < 0.1)
    );
}

#[test]
fn a_failed_move_still_moving_after_the_settle_time_says_so() {
    let cfg = config();
    let mut b = Bench::with(repair_config());
    b.start(1, "move", to(Enu::new(30.0, 0.0, 0.0)));
    b.feed(b.ap.heartbeat());
    b.feed(moving(&cfg, Enu::new(10.0, 0.0, 0.0), 0.5, 2_000));
    b.ap.mode = 0; // someone drives it by hand
    b.feed(b.ap.heartbeat());
    b.feed(moving(&cfg, Enu::new(12.0, 0.0, 0.0), 0.5, 6_000));
    assert!(b.report(1).is_none());
    b.feed(moving(&cfg, Enu::new(13.0, 0.0, 0.0), 0.5, 7_001));
    let r = b.report(1).expect("report after settle_ms");
    assert!(
        r.state
            .contains(&("STATUS".to_string(), StateValue::Symbol("MOVING".into()))),
        "{:?}",
        r.state
    );
}

#[test]
fn an_interrupted_move_reports_no_moving_value() {
    // A preempted move ended as its task says (its end effects hold): only where it stopped is reported.
    let cfg = config();
    let mut b = Bench::new();
    b.start(1, "move", to(Enu::new(30.0, 0.0, 0.0)));
    b.feed(moving(&cfg, Enu::new(10.0, 0.0, 0.0), 0.5, 2_000));
    b.d.stop(1, b.now).expect("running");
    b.settle();
    let r = b.report(1).expect("report at once");
    assert_eq!(r.status, ReportStatus::Interrupted);
    assert!(!r.state.iter().any(|(v, _)| v == "STATUS"), "{:?}", r.state);
}

fn system_time(ms: u32) -> MavMessage {
    MavMessage::SYSTEM_TIME(SYSTEM_TIME_DATA {
        time_unix_usec: 0,
        time_boot_ms: ms,
    })
}

fn statustext(severity: MavSeverity, text: &str) -> MavMessage {
    let mut t = [0u8; 50];
    t[..text.len()].copy_from_slice(text.as_bytes());
    MavMessage::STATUSTEXT(STATUSTEXT_DATA {
        severity,
        text: t.into(),
        id: 0,
        chunk_seq: 0,
    })
}

#[test]
fn readiness_waits_for_a_fix_and_a_home_then_retries_arm_with_a_backoff_until_accepted() {
    let cfg = config();
    let mut b = Bench::new();
    let arms = |ap: &Autopilot| {
        commands(ap)
            .iter()
            .filter(|c| c.0 == MavCmd::MAV_CMD_COMPONENT_ARM_DISARM)
            .count()
    };
    let home_requests = |ap: &Autopilot| {
        commands(ap)
            .iter()
            .filter(|c| c.0 == MavCmd::MAV_CMD_REQUEST_MESSAGE && c.1 == 242.0)
            .count()
    };
    b.feed(system_time(1_000));
    b.d.begin_ready(b.now);
    b.settle();
    assert_eq!(arms(&b.ap), 0, "no ARM before a position fix");
    assert_eq!(home_requests(&b.ap), 1, "HOME_POSITION asked for");
    // lat = lon = 0: no fix yet.
    b.feed(MavMessage::GLOBAL_POSITION_INT(GLOBAL_POSITION_INT_DATA {
        time_boot_ms: 2_000,
        ..Default::default()
    }));
    assert_eq!(arms(&b.ap), 0);
    assert_eq!(home_requests(&b.ap), 2, "asked again a second later");
    b.ap.results.push((
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
        MavResult::MAV_RESULT_FAILED,
    ));
    b.ap.results.push((
        MavCmd::MAV_CMD_COMPONENT_ARM_DISARM,
        MavResult::MAV_RESULT_FAILED,
    ));
    // A position, but no home: ArduPilot would refuse GUIDED ("Flight mode change failed").
    b.feed(moving(&cfg, Enu::new(0.0, 0.0, 0.0), 0.0, 2_500));
    assert_eq!(arms(&b.ap), 0, "no ARM before a home");
    let (lat, lon, _) = cfg.home.to_global(Enu::default());
    b.feed(MavMessage::HOME_POSITION(HOME_POSITION_DATA {
        latitude: (lat * 1e7) as i32,
        longitude: (lon * 1e7) as i32,
        ..Default::default()
    }));
    b.feed(statustext(
        MavSeverity::MAV_SEVERITY_CRITICAL,
        "PreArm: EKF3 waiting for GPS config data",
    ));
    assert_eq!(arms(&b.ap), 1, "armed as soon as the home is known");
    b.feed(system_time(3_400));
    assert_eq!(arms(&b.ap), 1, "backing off 1 s");
    b.feed(system_time(3_500));
    assert_eq!(arms(&b.ap), 2);
    b.feed(system_time(5_400));
    assert_eq!(arms(&b.ap), 2, "backing off 2 s");
    b.feed(system_time(5_500));
    assert_eq!(arms(&b.ap), 3);
    // Armed, but ArduPilot's EKF still holds a constant position: GUIDED would be refused, not ready.
    let ekf = |flags: EkfStatusFlags| {
        MavMessage::EKF_STATUS_REPORT(EKF_STATUS_REPORT_DATA {
            flags,
            ..Default::default()
        })
    };
    b.feed(ekf(
        EkfStatusFlags::EKF_PRED_POS_HORIZ_ABS | EkfStatusFlags::EKF_CONST_POS_MODE
    ));
    b.feed(b.ap.heartbeat());
    assert!(!b.d.readiness().expect("waiting").report().ready);
    b.feed(system_time(7_000));
    b.feed(ekf(
        EkfStatusFlags::EKF_POS_HORIZ_ABS | EkfStatusFlags::EKF_VELOCITY_HORIZ
    ));
    let r = b.d.readiness().expect("waiting").report().clone();
    assert!(r.ready, "{r:?}");
    assert_eq!(r.arm_attempts, 3);
    assert_eq!(r.fix_after_ms, Some(1_500));
    assert_eq!(r.navigation_after_ms, Some(6_000));
    assert!(r.refusals.iter().any(|t| t.contains("EKF3")), "{r:?}");
    assert!(b.ap.armed);
}

/// Issue 30: a foreign HOLD mid-move hands the vehicle to the operator. The move ends interrupted where the
/// vehicle is, with no command; nothing that commands the vehicle goes out while paused (a minute of
/// ticks and telemetry); GUIDED again, armed, resumes, with the position for the plan.
#[test]
fn a_foreign_hold_pauses_with_no_command_until_guided_is_restored() {
    let cfg = config();
    let mut b = Bench::new();
    b.start(1, "move", to(Enu::new(30.0, 0.0, 0.0)));
    b.feed(b.ap.heartbeat()); // GUIDED seen, armed by the companion
    b.feed(moving(&cfg, Enu::new(10.0, 0.0, 0.0), 0.5, 2_000));
    b.ap.mode = 4; // the operator's HOLD
    let seen_before = b.ap.seen.len();
    b.feed(b.ap.heartbeat());
    assert!(b.d.is_paused());
    let r = b.report(1).expect("the move ends at once");
    assert_eq!(r.status, ReportStatus::Interrupted);
    assert!(
        r.reason.as_deref().is_some_and(|w| w.contains("HOLD")),
        "{r:?}"
    );
    assert!(
        matches!(r.state[0], (_, StateValue::Position(p)) if (p.east - 10.0).abs() < 0.1),
        "{:?}",
        r.state
    );
    assert!(b.events.iter().any(|e| matches!(
        e,
        VehicleEvent::Authority(mavtempo_vehicle::authority::AuthorityEvent::Paused { why })
            if why.contains("HOLD")
    )));
    for k in 0..60u32 {
        b.tick(1_000);
        b.feed(moving(
            &cfg,
            Enu::new(10.2, 0.0, 0.0),
            0.0,
            3_000 + k * 1_000,
        ));
        b.feed(b.ap.heartbeat());
    }
    assert_eq!(
        b.ap.seen.len(),
        seen_before,
        "no command while paused: {:?}",
        &b.ap.seen[seen_before..]
    );
    // Starting an action while paused is refused.
    let refused = b.try_start(2, "move", to(Enu::new(0.0, 0.0, 0.0)));
    assert_eq!(refused, Err(mavtempo_vehicle::VehicleError::Yielded));
    b.ap.mode = 15; // handed back
    b.feed(b.ap.heartbeat());
    assert!(!b.d.is_paused());
    let resumed = b.events.iter().find_map(|e| match e {
        VehicleEvent::Authority(mavtempo_vehicle::authority::AuthorityEvent::Resumed {
            position,
            ..
        }) => Some(*position),
        _ => None,
    });
    let at = resumed.expect("resumed").expect("with the position");
    assert!((at.east - 10.2).abs() < 0.1, "{at:?}");
    // The companion commands again.
    b.start(2, "move", to(Enu::new(30.0, 0.0, 0.0)));
    assert!(b.ap.seen.len() > seen_before);
}

/// `MAV_CMD_DO_PAUSE_CONTINUE` to 191 from a ground station: p1 = 0 stops the move (HOLD) and pauses,
/// p1 = 1 resumes; each answered with a COMMAND_ACK to the ground station.
#[test]
fn pause_continue_to_the_companion_pauses_and_resumes() {
    let cfg = config();
    let mut b = Bench::new();
    b.start(1, "move", to(Enu::new(30.0, 0.0, 0.0)));
    b.feed(b.ap.heartbeat());
    b.feed(moving(&cfg, Enu::new(5.0, 0.0, 0.0), 0.5, 2_000));
    let gcs = MavHeader {
        system_id: 255,
        component_id: 190,
        sequence: 0,
    };
    let pause_continue = |p1: f32| {
        MavMessage::COMMAND_LONG(COMMAND_LONG_DATA {
            command: MavCmd::MAV_CMD_DO_PAUSE_CONTINUE,
            param1: p1,
            target_system: 1,
            target_component: 191,
            ..Default::default()
        })
    };
    b.d.handle(gcs, &pause_continue(0.0), b.now);
    let out = b.d.take_outgoing();
    assert!(out.iter().any(|m| matches!(m, MavMessage::COMMAND_ACK(a)
        if a.command == MavCmd::MAV_CMD_DO_PAUSE_CONTINUE && a.result == MavResult::MAV_RESULT_ACCEPTED && a.target_system == 255)));
    assert!(
        out.iter().any(|m| matches!(m, MavMessage::COMMAND_LONG(c)
            if c.command == MavCmd::MAV_CMD_DO_SET_MODE && c.param2 == 4.0)),
        "the pause asked stops the vehicle: {out:?}"
    );
    b.ap.respond(out);
    b.settle();
    assert!(b.d.is_paused());
    assert_eq!(
        b.report(1).expect("ended").status,
        ReportStatus::Interrupted
    );
    b.d.handle(gcs, &pause_continue(1.0), b.now);
    assert!(!b.d.is_paused());
}

/// `[authority] arm = "operator"`: readiness never sends ARM and waits for the vehicle armed by someone
/// else; a move on a disarmed vehicle is refused rather than armed.
#[test]
fn with_operator_arming_the_companion_never_arms() {
    let cfg = operator_config();
    let mut b = Bench::with(cfg.clone());
    b.feed(MavMessage::GLOBAL_POSITION_INT(GLOBAL_POSITION_INT_DATA {
        lat: 435_616_000,
        lon: 14_847_000,
        ..Default::default()
    }));
    b.feed(MavMessage::HOME_POSITION(HOME_POSITION_DATA {
        latitude: 435_616_000,
        longitude: 14_847_000,
        ..Default::default()
    }));
    b.d.begin_ready(b.now);
    for _ in 0..30 {
        b.tick(1_000);
        b.feed(b.ap.heartbeat());
    }
    let arms = |b: &Bench| {
        b.ap.seen
            .iter()
            .filter(|m| matches!(m, MavMessage::COMMAND_LONG(c) if c.command == MavCmd::MAV_CMD_COMPONENT_ARM_DISARM))
            .count()
    };
    assert_eq!(arms(&b), 0);
    let r = b.d.readiness().expect("waiting");
    assert!(!r.report().ready);
    let why = r.report().why_not(30.0);
    assert!(why.contains("operator"), "{why} {:?}", r.phase());
    let err = b.try_start(1, "move", to(Enu::new(10.0, 0.0, 0.0)));
    assert!(
        err.as_ref()
            .is_err_and(|e| e.to_string().contains("operator")),
        "{err:?}"
    );
    b.ap.armed = true; // the operator arms
    b.tick(1_000);
    b.feed(b.ap.heartbeat());
    assert!(b.d.readiness().expect("waiting").report().ready);
    assert_eq!(arms(&b), 0);
}
