//! Goal files (.plan, .waypoints) and vehicle configs: good ones parse, malformed ones give clear errors.

use mavtempo_vehicle::config::VehicleConfig;
use mavtempo_vehicle::geo::Home;
use mavtempo_vehicle::goal_files::{parse_plan, parse_waypoints};
use mavtempo_vehicle::goals::{items_to_goals, KnownLocations, SyntacticDecider};
use mavtempo_vehicle::{Enu, GoalKind, GoalVerdict};

const PLAN: &str = r#"{
  "fileType": "Plan", "version": 1, "groundStation": "QGroundControl",
  "mission": { "version": 2, "firmwareType": 3, "vehicleType": 10, "cruiseSpeed": 2, "hoverSpeed": 5,
    "plannedHomePosition": [43.5616, 1.4847, 150],
    "items": [
      {"type": "SimpleItem", "command": 31011, "frame": 2, "params": [3, 0, 600, 0, 120, 0, 0], "autoContinue": true, "doJumpId": 1},
      {"type": "SimpleItem", "command": 2000, "frame": 3, "params": [0, 0, 1, 0, 43.5617, 1.4848, 0], "autoContinue": true, "doJumpId": 2},
      {"type": "SimpleItem", "command": 16, "frame": 3, "params": [0, 0, 0, null, 43.5620, 1.4850, 0], "autoContinue": true, "doJumpId": 3}
    ]},
  "geoFence": {"circles": [], "polygons": [], "version": 2}, "rallyPoints": {"points": [], "version": 2}
}"#;

#[test]
fn plan_maps_to_goals_with_attributes_and_locations() {
    let f = parse_plan(PLAN, "g.plan").expect("valid plan");
    let home = f.home.expect("planned home");
    assert_eq!(
        home,
        Home {
            lat: 43.5616,
            lon: 1.4847,
            alt: 150.0
        }
    );
    assert_eq!(f.items.len(), 3);
    let mut known = KnownLocations::new(home);
    let l7 = home.to_local(43.5617, 1.4848, 150.0);
    known
        .objects
        .push(("L7".into(), Enu::new(l7.east + 0.5, l7.north, 0.0)));
    let goals = items_to_goals(&f.items, &known, 6).requests();
    assert_eq!(goals.len(), 2);
    assert_eq!(goals[0].name, "g6");
    assert_eq!(goals[0].kind, GoalKind::PictureOf);
    assert_eq!(goals[0].proposition, "picture_of(L7)");
    assert_eq!(
        (
            goals[0].priority,
            goals[0].start_window_s,
            goals[0].d_achiev_s
        ),
        (3, (0.0, 600.0), 120.0)
    );
    let loc = goals[1].location.as_ref().expect("position");
    assert!(loc.new, "no known object there: a new location");
    assert_eq!(loc.name, "g7_loc");
    assert_eq!(goals[1].proposition, "at(g7_loc)");
    assert_eq!(
        goals[1].priority, 1,
        "attributes apply to the next item only"
    );
}

#[test]
fn malformed_plans_name_the_json_place() {
    let err = parse_plan(
        "{\"fileType\": \"Plan\",\n \"mission\": [1, 2,}",
        "bad.plan",
    )
    .unwrap_err();
    assert!(err.place.starts_with("bad.plan:2:"), "{err}");
    let bad_param = PLAN.replace("[0, 0, 1, 0, 43.5617", "[0, \"x\", 1, 0, 43.5617");
    let err = parse_plan(&bad_param, "p.plan").unwrap_err();
    assert_eq!(
        err.to_string(),
        "p.plan: mission.items[1].params[1]: expected a number or null"
    );
    let six = PLAN.replace(
        "[0, 0, 0, null, 43.5620, 1.4850, 0]",
        "[0, 0, 0, 43.5620, 1.4850, 0]",
    );
    let err = parse_plan(&six, "p.plan").unwrap_err();
    assert_eq!(
        err.to_string(),
        "p.plan: mission.items[2].params: expected an array of 7 numbers"
    );
    let err = parse_plan(&PLAN.replace("\"Plan\"", "\"Fence\""), "p.plan").unwrap_err();
    assert!(
        err.to_string().contains("fileType: expected \"Plan\""),
        "{err}"
    );
    let complex = PLAN.replace(
        "\"type\": \"SimpleItem\", \"command\": 16",
        "\"type\": \"ComplexItem\", \"command\": 16",
    );
    // A complex item without the items QGroundControl generates for it is skipped with its place, not
    // refused whole.
    let f = parse_plan(&complex, "p.plan").expect("parses");
    assert_eq!(f.skipped.len(), 1);
    assert!(
        f.skipped[0].to_string().contains("mission.items[2]"),
        "{:?}",
        f.skipped
    );
}

const WAYPOINTS: &str = "QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t43.5616\t1.4847\t150\t1\n1\t0\t3\t16\t0\t0\t0\t0\t43.5620\t1.4850\t0\t1\n2\t0\t3\t20\t0\t0\t0\t0\t0\t0\t0\t1\n";

#[test]
fn waypoints_row_zero_is_home_and_others_are_goals() {
    let f = parse_waypoints(WAYPOINTS, "w.waypoints").expect("valid");
    assert_eq!(
        f.home,
        Some(Home {
            lat: 43.5616,
            lon: 1.4847,
            alt: 150.0
        })
    );
    let goals = items_to_goals(&f.items, &KnownLocations::new(f.home.expect("home")), 1).requests();
    assert_eq!(
        goals.iter().map(|g| g.kind).collect::<Vec<_>>(),
        vec![GoalKind::BeAt, GoalKind::ReturnHome]
    );
    assert_eq!(goals[1].proposition, "at(home)");
}

#[test]
fn malformed_waypoints_give_line_and_column() {
    let err = parse_waypoints("QGC WPX\n", "w.waypoints").unwrap_err();
    assert!(
        err.to_string()
            .starts_with("w.waypoints:1:1: expected the header"),
        "{err}"
    );
    let bad = WAYPOINTS.replace("43.5620", "43.56x0");
    let err = parse_waypoints(&bad, "w.waypoints").unwrap_err();
    assert_eq!(
        err.to_string(),
        "w.waypoints:3:18: LAT: `43.56x0` is not a number"
    );
    let short = "QGC WPL 110\n1\t0\t3\t16\t0\t0\n";
    let err = parse_waypoints(short, "w.waypoints").unwrap_err();
    assert_eq!(
        err.to_string(),
        "w.waypoints:2:1: expected 12 tab-separated fields, found 6"
    );
    let frame = WAYPOINTS.replace("1\t0\t3\t16", "1\t0\t300\t16");
    let err = parse_waypoints(&frame, "w.waypoints").unwrap_err();
    assert!(
        err.to_string().starts_with("w.waypoints:3:5: FRAME"),
        "{err}"
    );
}

#[test]
fn items_that_cannot_be_goals_are_skipped_with_the_item() {
    let f =
        parse_waypoints(&WAYPOINTS.replace("1\t0\t3\t16", "1\t0\t3\t183"), "w").expect("parses");
    let list = items_to_goals(
        &f.items,
        &KnownLocations::new(Home {
            lat: 0.0,
            lon: 0.0,
            alt: 0.0,
        }),
        1,
    );
    assert_eq!(list.skipped.len(), 1);
    let err = &list.skipped[0];
    assert_eq!(err.seq, 0);
    assert!(err.reason.contains("183 is not a goal"), "{err}");
    assert_eq!(list.goals.len(), f.items.len() - 1);
}

#[test]
fn syntactic_decider_rejects_a_window_ending_before_reachable() {
    let f = parse_plan(
        &PLAN.replace("[3, 0, 600, 0, 120", "[3, 0, 60, 0, 120"),
        "p",
    )
    .expect("valid");
    let goals = items_to_goals(&f.items, &KnownLocations::new(f.home.expect("home")), 1).requests();
    assert_eq!(
        SyntacticDecider::verdict(&goals[0]),
        GoalVerdict::Rejected("window ends before reachable".into())
    );
    assert_eq!(SyntacticDecider::verdict(&goals[1]), GoalVerdict::Accepted);
}

fn shipped(name: &str) -> String {
    std::fs::read_to_string(format!("{}/{name}", repo!("config"))).expect("shipped config")
}

/// The test configuration with one binding of every kind.
fn all_bindings() -> String {
    std::fs::read_to_string(repo!("tests/fixtures/vehicle/bindings.toml")).expect("fixture")
}

#[test]
fn shipped_configs_parse_and_px4_modes_follow_px4_numbering() {
    for name in [
        "demo-rover.toml",
        "sitl-rover.toml",
        "ardupilot-rover.toml",
        "px4-rover.toml",
        "sitl-auv.toml",
    ] {
        VehicleConfig::parse(&shipped(name), name).unwrap_or_else(|e| panic!("{e}"));
    }
    let px4 = VehicleConfig::parse(&shipped("px4-rover.toml"), "px4").expect("parses");
    assert_eq!(px4.modes.auto.custom_mode(), (4 << 16) | (4 << 24));
    assert_eq!(px4.modes.auto.set_mode_params(), (4.0, 4.0));
    let ap = VehicleConfig::parse(&shipped("ardupilot-rover.toml"), "ap").expect("parses");
    assert_eq!(ap.link.address, "tcpout:127.0.0.1:5760");
    assert_eq!(ap.modes.guided.custom_mode(), 15);
}

#[test]
fn malformed_configs_name_the_key() {
    let base = all_bindings();
    // The error of the fixture with `from` replaced by `to`.
    let err = |from: &str, to: &str| {
        VehicleConfig::parse(&base.replace(from, to), "c.toml")
            .unwrap_err()
            .to_string()
    };
    let e = err(
        "acceptance_radius_m = 3.0\n\n[actions.survey]",
        "acceptance_radius_m = 3.0\nradius = 2\n\n[actions.survey]",
    );
    assert!(e.contains("unknown field `radius`"), "{e}");
    assert!(e.starts_with("c.toml:34:1: error: "), "{e}");
    let e = err("kind = \"sample\"", "kind = \"dance\"");
    assert!(e.contains("dance"), "{e}");
    let e = err("spacing_m = 10.0", "spacing_m = 0.0");
    assert!(
        e.starts_with("c.toml:")
            && e.contains(": error: actions.survey.spacing_m: must be > 0\n    spacing_m = 0.0\n"),
        "{e}"
    );
    let e = err("[link]\n", "[link]\nsigning_key = \"abc\"\n");
    assert!(
        e.starts_with("c.toml:7:15: error: link.signing_key: expected 64 hex digits"),
        "{e}"
    );
    let e = err("hold = 4\n", "");
    assert!(e.contains("missing field `hold`"), "{e}");
}

#[test]
fn shutdown_mode_and_goal_sysids_are_read_and_checked() {
    use mavtempo_vehicle::safe_stop::OnShutdown;
    let base = all_bindings();
    let parse = |from: &str, to: &str| VehicleConfig::parse(&base.replacen(from, to, 1), "c.toml");
    let cfg = VehicleConfig::parse(&base, "c.toml").expect("parses");
    assert_eq!(cfg.modes.on_shutdown, OnShutdown::Hold, "HOLD by default");
    assert_eq!(
        cfg.link.goal_sysids, None,
        "goals from any system by default"
    );
    let cfg = parse("[modes]", "[modes]\non_shutdown = \"rtl\"").expect("rtl");
    assert_eq!(cfg.modes.on_shutdown, OnShutdown::Rtl);
    let cfg = parse("[modes]", "[modes]\non_shutdown = \"none\"").expect("none");
    assert_eq!(cfg.modes.on_shutdown, OnShutdown::None);
    let err = parse("[modes]", "[modes]\non_shutdown = \"land\"").unwrap_err();
    assert!(
        err.to_string().contains("land") && err.to_string().contains("hold"),
        "{err}"
    );
    let cfg = parse("[link]\n", "[link]\ngoal_sysids = [255, 250]\n").expect("list");
    assert_eq!(cfg.link.goal_sysids, Some(vec![255, 250]));
    for bad in ["[]", "[0, 255]"] {
        let err = parse("[link]\n", &format!("[link]\ngoal_sysids = {bad}\n")).unwrap_err();
        assert!(
            err.to_string()
                .starts_with("c.toml:7:15: error: link.goal_sysids: system ids 1 to 255"),
            "{bad}: {err}"
        );
    }
    assert!(parse("[link]\n", "[link]\ngoal_sysids = [256]\n").is_err());
}

#[test]
fn goal_files_refuse_non_finite_numbers_absurd_homes_and_bad_bytes() {
    let err = parse_plan(
        &PLAN.replace("[43.5616, 1.4847, 150]", "[214.0, 1.4847, 150]"),
        "g.plan",
    )
    .unwrap_err();
    assert!(
        err.to_string()
            .starts_with("g.plan: mission.plannedHomePosition: home: latitude"),
        "{err}"
    );
    for bad in ["nan", "inf", "-inf", "1e999"] {
        let text = WAYPOINTS.replace("43.5620", bad);
        assert_ne!(text, WAYPOINTS);
        let err = parse_waypoints(&text, "w.waypoints").unwrap_err();
        assert!(err.to_string().contains("is not a number"), "{bad}: {err}");
    }
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("g.waypoints");
    std::fs::write(
        &path,
        b"QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t4\xe93\t1\t0\t1\n",
    )
    .expect("write");
    let err = mavtempo_vehicle::goal_files::load(&path).unwrap_err();
    assert!(
        err.to_string().starts_with(&format!(
            "{}:2:19: invalid UTF-8 (byte 0xe9)",
            path.display()
        )),
        "{err}"
    );
}
