//! The `[autopilot] profile = "ardupilot"` behaviours over a real socket, on the manual clock: arming
//! refused until the autopilot is ready, no position before the GPS fix, ArduPilot's camera (or none),
//! GUIDED's submodes and speeds, WP_SPEED by default.
#![allow(deprecated)]

use std::time::Duration;

use crate::support::*;
use mavlink::dialects::ardupilotmega::*;

const ARDUPILOT: &str = "[autopilot]\nprofile = \"ardupilot\"\n";
/// The ArduPilot profile with the boot delays off, for tests about something else.
const ARDUPILOT_READY: &str =
    "[autopilot]\nprofile = \"ardupilot\"\nready_after_s = 0.0\ngps_fix_after_s = 0.0\n";
/// Home of `scenarios/ardupilot-rover.toml`.
const AP_HOME: (f64, f64) = (43.5616, 1.4847);

/// Steps to sim time `t_s` (from wherever the clock is).
async fn step_to(sim: &sitl::SimHandle, t_s: f64) {
    let now = sim.now_ms();
    let to = (t_s * 1000.0) as u64;
    assert!(to >= now, "already at {now} ms");
    sim.step(Duration::from_millis(to - now))
        .await
        .expect("step");
}

/// An arming attempt: its result and the STATUSTEXTs sent with it.
async fn try_arm(gcs: &mut Gcs, force: bool) -> (MavResult, Vec<(MavSeverity, String)>) {
    let p2 = if force { 21196.0 } else { 0.0 };
    let r = gcs
        .command(MavCmd::MAV_CMD_COMPONENT_ARM_DISARM, &[1.0, p2])
        .await;
    (r, Gcs::texts_with_severity(&gcs.sync().await))
}

fn critical(text: &str) -> (MavSeverity, String) {
    (MavSeverity::MAV_SEVERITY_CRITICAL, text.to_string())
}

async fn request(gcs: &mut Gcs, id: u32) -> (MavResult, Vec<MavMessage>) {
    let r = gcs.request_message(id).await;
    (r, gcs.sync().await)
}

/// The last GLOBAL_POSITION_INT among `msgs`.
fn last_position(msgs: &[MavMessage]) -> GLOBAL_POSITION_INT_DATA {
    msgs.iter()
        .rev()
        .find_map(|m| match m {
            MavMessage::GLOBAL_POSITION_INT(p) => Some(p.clone()),
            _ => None,
        })
        .expect("a GLOBAL_POSITION_INT")
}

async fn change_speed(gcs: &mut Gcs, speed_type: f32, speed: f32) -> MavResult {
    gcs.command(MavCmd::MAV_CMD_DO_CHANGE_SPEED, &[speed_type, speed, -1.0])
        .await
}

/// DO_CHANGE_SPEED of `speed_type` to 2 m/s, answered `expected`.
async fn change_speed_is(gcs: &mut Gcs, speed_type: f32, expected: MavResult) {
    let r = change_speed(gcs, speed_type, 2.0).await;
    assert_eq!(r, expected, "speed type {speed_type}");
}

/// DO_REPOSITION with the change-mode flag to metres north/east of `home`, at `speed` (-1: default).
async fn reposition(gcs: &mut Gcs, home: (f64, f64), north: f64, speed: f32) -> MavResult {
    let wp = waypoint(home, north, 0.0);
    gcs.command_int(
        MavCmd::MAV_CMD_DO_REPOSITION,
        [speed, 1.0, 0.0, 0.0],
        wp.x,
        wp.y,
        0.0,
    )
    .await
    .0
}

/// A sim in `scenario`, armed and sent `north` metres north of home at `speed` (-1: default) by an
/// accepted DO_REPOSITION (GUIDED).
async fn guided_north(scenario: &str, north: f64, speed: f32) -> (sitl::SimHandle, Gcs) {
    let (sim, mut gcs) = start(scenario).await;
    let armed = gcs.arm().await;
    assert_eq!(armed, MavResult::MAV_RESULT_ACCEPTED, "{scenario:?}");
    let r = reposition(&mut gcs, HOME, north, speed).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED, "{scenario:?}");
    (sim, gcs)
}

/// Steps `secs` in 100 ms slices; the highest ground speed seen and the last snapshot.
async fn drive(sim: &sitl::SimHandle, secs: u64) -> (f64, sitl::Snapshot) {
    let mut top: f64 = 0.0;
    for _ in 0..secs * 10 {
        sim.step(Duration::from_millis(100)).await.expect("step");
        top = top.max(sim.snapshot().speed_mps);
    }
    (top, sim.snapshot())
}

/// Drives `secs` of sim time (as [`drive`]) and checks the top speed on the way was `expected`; `what`
/// names the case in the failure. The last snapshot.
async fn drive_at(sim: &sitl::SimHandle, secs: u64, expected: f64, what: &str) -> sitl::Snapshot {
    let (top, s) = drive(sim, secs).await;
    assert!(
        (top - expected).abs() < 1e-6,
        "{what} top speed {top}, not {expected}"
    );
    s
}

#[tokio::test]
async fn arming_is_refused_until_ready_with_ardupilot_reasons() {
    let (sim, mut gcs) = start(ARDUPILOT).await;
    step_to(&sim, 1.0).await;
    let (r, t) = try_arm(&mut gcs, false).await;
    assert_eq!(r, MavResult::MAV_RESULT_FAILED);
    assert_eq!(t, vec![critical("Arm: System not initialised")]);
    step_to(&sim, 12.0).await;
    let (r, t) = try_arm(&mut gcs, false).await;
    assert_eq!(r, MavResult::MAV_RESULT_FAILED);
    assert_eq!(t, vec![critical("Arm: Accels inconsistent")]);
    step_to(&sim, 19.0).await;
    let (r, t) = try_arm(&mut gcs, false).await;
    assert_eq!(r, MavResult::MAV_RESULT_FAILED);
    assert_eq!(t, vec![critical("Arm: Gyros inconsistent")]);
    assert!(!sim.snapshot().armed);
    step_to(&sim, 20.0).await;
    let (r, t) = try_arm(&mut gcs, false).await;
    assert_eq!((r, t), (MavResult::MAV_RESULT_ACCEPTED, vec![]));
    assert!(sim.snapshot().armed);

    // A reboot starts the wait again.
    sim.inject(sitl::Fault::Reboot { silent_s: 1.0 })
        .expect("inject");
    step_to(&sim, 22.0).await;
    gcs.sync().await;
    assert!(!sim.snapshot().armed);
    let (r, t) = try_arm(&mut gcs, false).await;
    assert_eq!(r, MavResult::MAV_RESULT_FAILED);
    assert_eq!(t, vec![critical("Arm: System not initialised")]);
}

#[tokio::test]
async fn forced_arming_skips_the_readiness_checks_and_a_low_battery_adds_its_reason() {
    let (sim, mut gcs) = start(&format!("{ARDUPILOT}[battery]\ninitial_pct = 10.0\n")).await;
    step_to(&sim, 15.0).await;
    let (r, t) = try_arm(&mut gcs, false).await;
    assert_eq!(r, MavResult::MAV_RESULT_FAILED);
    // ArduPilot runs every group of checks once initialised: both reasons come.
    assert_eq!(
        t,
        vec![
            critical("Arm: Accels inconsistent"),
            critical("Arm: Battery 1 below minimum arming capacity")
        ]
    );
    let (r, t) = try_arm(&mut gcs, true).await;
    assert_eq!((r, t), (MavResult::MAV_RESULT_ACCEPTED, vec![]));
    assert!(sim.snapshot().armed);
}

#[tokio::test]
async fn the_default_profile_is_ready_at_boot() {
    let (sim, mut gcs) = start("").await;
    let (r, _) = try_arm(&mut gcs, false).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    sim.step(Duration::from_secs(1)).await.expect("step");
    let p = last_position(&gcs.sync().await);
    assert_eq!(p.lat, geodesy::deg_to_e7(HOME.0));
}

#[tokio::test]
async fn position_reads_zero_until_the_gps_fix() {
    let scenario = format!(
        "{ARDUPILOT}[home]\nlat = {}\nlon = {}\n",
        AP_HOME.0, AP_HOME.1
    );
    let (sim, mut gcs) = start(&scenario).await;
    step_to(&sim, 5.0).await;
    let seen = gcs.sync().await;
    let p = last_position(&seen);
    assert_eq!((p.lat, p.lon), (0, 0));
    let gps = seen
        .iter()
        .rev()
        .find_map(|m| match m {
            MavMessage::GPS_RAW_INT(g) => Some(g.clone()),
            _ => None,
        })
        .expect("GPS_RAW_INT");
    assert_eq!(gps.fix_type, GpsFixType::GPS_FIX_TYPE_NO_FIX);
    assert_eq!((gps.lat, gps.lon), (0, 0));
    // No home yet: the request is accepted and nothing comes.
    let (r, seen) = request(&mut gcs, 242).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    assert!(!seen
        .iter()
        .any(|m| matches!(m, MavMessage::HOME_POSITION(_))));
    // Without a position, armed (forced), GUIDED cannot be entered; RTL not even disarmed.
    assert_eq!(gcs.set_mode(11).await, MavResult::MAV_RESULT_FAILED);
    assert_eq!(
        try_arm(&mut gcs, true).await.0,
        MavResult::MAV_RESULT_ACCEPTED
    );
    assert_eq!(gcs.set_mode(15).await, MavResult::MAV_RESULT_FAILED);
    assert!(Gcs::texts_with_severity(&gcs.sync().await)
        .iter()
        .any(|(_, t)| t == "Flight mode change failed"));
    assert_eq!(sim.snapshot().mode, "MANUAL");

    step_to(&sim, 10.0).await;
    let p = last_position(&gcs.sync().await);
    assert_eq!(
        (p.lat, p.lon),
        (geodesy::deg_to_e7(AP_HOME.0), geodesy::deg_to_e7(AP_HOME.1))
    );
    let (r, seen) = request(&mut gcs, 242).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    assert!(seen.iter().any(|m| matches!(m, MavMessage::HOME_POSITION(h)
        if h.latitude == geodesy::deg_to_e7(AP_HOME.0))));
    assert_eq!(gcs.set_mode(15).await, MavResult::MAV_RESULT_ACCEPTED);
}

#[tokio::test]
async fn the_ardupilot_camera_sends_camera_feedback_and_no_image_captured() {
    let (sim, mut gcs) = start(&format!(
        "{ARDUPILOT}[camera]\nsize_min_mib = 3.0\nsize_max_mib = 3.0\n"
    ))
    .await;
    step_to(&sim, 11.0).await;
    gcs.sync().await;
    let seen = shoot(&sim, &mut gcs, Duration::from_secs(2)).await;
    assert!(
        !seen
            .iter()
            .any(|m| matches!(m, MavMessage::CAMERA_IMAGE_CAPTURED(_))),
        "CAMERA_IMAGE_CAPTURED from AP_Camera"
    );
    let fb: Vec<_> = seen
        .iter()
        .filter_map(|m| match m {
            MavMessage::CAMERA_FEEDBACK(f) => Some(f.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(fb.len(), 1, "{fb:?}");
    assert_eq!((fb[0].img_idx, fb[0].completed_captures), (1, 1));
    assert_eq!(fb[0].flags, CameraFeedbackFlags::CAMERA_FEEDBACK_PHOTO);
    assert_eq!(fb[0].lat, geodesy::deg_to_e7(HOME.0));
    // Stamped with GPS time at the capture's end (t = 12 s: 1 s capture from 11 s).
    assert_eq!(fb[0].time_usec, 1_767_225_600_000_000 + 12_000_000);
    // The picture used storage, and the storage is still answered.
    assert_eq!(sim.snapshot().storage_used_mib, 3.0);
    let (r, seen) = request(&mut gcs, 261).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    assert!(seen
        .iter()
        .any(|m| matches!(m, MavMessage::STORAGE_INFORMATION(s) if s.used_capacity == 3.0)));

    // A failed picture: no feedback at all (AP_Camera hears only its feedback pin).
    sim.inject(sitl::Fault::PictureFails { count: 1 })
        .expect("inject");
    let seen = shoot(&sim, &mut gcs, Duration::from_secs(2)).await;
    assert!(!seen.iter().any(|m| matches!(
        m,
        MavMessage::CAMERA_FEEDBACK(_) | MavMessage::CAMERA_IMAGE_CAPTURED(_)
    )));
    assert_eq!(sim.snapshot().pictures_failed, 1);
    // CAMERA_CAPTURE_STATUS as AP_Camera: idle, two pictures triggered, no capacity.
    let (r, seen) = request(&mut gcs, 262).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    let st = seen
        .iter()
        .find_map(|m| match m {
            MavMessage::CAMERA_CAPTURE_STATUS(s) => Some(s.clone()),
            _ => None,
        })
        .expect("CAMERA_CAPTURE_STATUS");
    assert_eq!((st.image_status, st.image_count), (0, 2));
    assert!(st.available_capacity.is_nan());
    // The last feedback again, on request.
    let (r, seen) = request(&mut gcs, 180).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    assert!(seen
        .iter()
        .any(|m| matches!(m, MavMessage::CAMERA_FEEDBACK(f) if f.img_idx == 1)));
    // AP_Camera's refusals: several pictures at no interval, a negative camera id, camera 2.
    for (p, want) in [
        ([0.0, 0.0, 3.0], MavResult::MAV_RESULT_FAILED),
        ([-1.0, 0.0, 1.0], MavResult::MAV_RESULT_UNSUPPORTED),
        ([2.0, 0.0, 1.0], MavResult::MAV_RESULT_FAILED),
    ] {
        assert_eq!(gcs.image_start_capture(p).await, want, "{p:?}");
    }
}

#[tokio::test]
async fn a_hung_picture_sends_no_feedback_either() {
    let (sim, mut gcs) = start(ARDUPILOT_READY).await;
    sim.inject(sitl::Fault::PictureHangs { count: 1 })
        .expect("inject");
    let seen = shoot(&sim, &mut gcs, Duration::from_secs(3)).await;
    assert!(!seen
        .iter()
        .any(|m| matches!(m, MavMessage::CAMERA_FEEDBACK(_))));
    assert_eq!(sim.snapshot().storage_used_mib, 0.0);
}

#[tokio::test]
async fn without_a_camera_image_start_capture_fails() {
    let (sim, mut gcs) = start(&format!("{ARDUPILOT_READY}camera = \"none\"\n")).await;
    let r = gcs.image_start_capture([0.0, 0.0, 1.0]).await;
    assert_eq!(r, MavResult::MAV_RESULT_FAILED);
    // DO_DIGICAM_CONTROL is accepted whatever the camera (AP_Camera::control), and shoots nothing.
    assert_eq!(
        gcs.command(
            MavCmd::MAV_CMD_DO_DIGICAM_CONTROL,
            &[0.0, 0.0, 0.0, 0.0, 1.0]
        )
        .await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    let (r, seen) = request(&mut gcs, 262).await;
    assert_eq!(r, MavResult::MAV_RESULT_ACCEPTED);
    assert!(!seen
        .iter()
        .any(|m| matches!(m, MavMessage::CAMERA_CAPTURE_STATUS(_))));
    sim.step(Duration::from_secs(3)).await.expect("step");
    let s = sim.snapshot();
    assert_eq!((s.pictures_ok, s.pictures_failed), (0, 0));
}

#[tokio::test]
async fn storage_information_can_be_refused_as_ardupilot_itself_does() {
    let (_sim, mut gcs) = start(&format!("{ARDUPILOT}storage_information = false\n")).await;
    let (r, seen) = request(&mut gcs, 261).await;
    assert_eq!(r, MavResult::MAV_RESULT_FAILED);
    assert!(!seen
        .iter()
        .any(|m| matches!(m, MavMessage::STORAGE_INFORMATION(_))));
}

#[tokio::test]
async fn reposition_with_a_speed_from_guided_stop_fails_and_change_speed_needs_a_destination() {
    let (sim, mut gcs) = start(ARDUPILOT_READY).await;
    assert_eq!(gcs.arm().await, MavResult::MAV_RESULT_ACCEPTED);
    // From MANUAL: GUIDED is entered (Stop submode), then the speed fails: no destination.
    assert_eq!(
        reposition(&mut gcs, HOME, 100.0, 2.0).await,
        MavResult::MAV_RESULT_FAILED
    );
    assert_eq!(sim.snapshot().mode, "GUIDED");
    let (_, s) = drive(&sim, 3).await;
    assert!(s.distance_m < 0.01, "moved without a destination: {s:?}");
    // In Stop there is no speed to change; climb and descent speeds are never for a rover.
    change_speed_is(&mut gcs, 1.0, MavResult::MAV_RESULT_FAILED).await;
    change_speed_is(&mut gcs, 2.0, MavResult::MAV_RESULT_DENIED).await;
    // A destination at the default speed, then the speed: the WP submode takes it.
    assert_eq!(
        reposition(&mut gcs, HOME, 100.0, -1.0).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    change_speed_is(&mut gcs, 1.0, MavResult::MAV_RESULT_ACCEPTED).await;
    change_speed_is(&mut gcs, 3.0, MavResult::MAV_RESULT_DENIED).await;
    let s = drive_at(&sim, 20, 2.0, "").await;
    assert!(s.north_m > 30.0, "{s:?}");
    // Now in WP, a speed in DO_REPOSITION is taken, and it lasts for later destinations.
    assert_eq!(
        reposition(&mut gcs, HOME, 200.0, 3.0).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    drive_at(&sim, 10, 3.0, "").await;
    assert_eq!(
        reposition(&mut gcs, HOME, 300.0, -1.0).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    drive_at(&sim, 10, 3.0, "").await;
    // Entering GUIDED again goes back to WP_SPEED.
    assert_eq!(gcs.set_mode(4).await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(gcs.set_mode(15).await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(
        reposition(&mut gcs, HOME, 500.0, -1.0).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    drive_at(&sim, 15, 5.0, "").await;
    // MANUAL has no speed to change.
    assert_eq!(gcs.set_mode(0).await, MavResult::MAV_RESULT_ACCEPTED);
    change_speed_is(&mut gcs, 1.0, MavResult::MAV_RESULT_FAILED).await;
}

/// The sequence the companion moves to: DO_REPOSITION with p1 = -1, then DO_CHANGE_SPEED.
#[tokio::test]
async fn reposition_then_change_speed_works_in_every_profile() {
    for scenario in ["", ARDUPILOT_READY] {
        let (sim, mut gcs) = guided_north(scenario, 100.0, -1.0).await;
        assert_eq!(
            change_speed(&mut gcs, 1.0, 2.5).await,
            MavResult::MAV_RESULT_ACCEPTED,
            "{scenario:?}"
        );
        let s = drive_at(&sim, 15, 2.5, &format!("{scenario:?}:")).await;
        assert!(s.north_m > 25.0, "{scenario:?}: {s:?}");
    }
}

/// The default profile keeps its old rule (the companion on main sends its speed in DO_REPOSITION
/// from MANUAL): accepted, and the target goes at that speed.
#[tokio::test]
async fn the_default_profile_takes_a_reposition_speed_from_any_state() {
    let (sim, _gcs) = guided_north("", 100.0, 2.0).await;
    drive_at(&sim, 10, 2.0, "").await;
}

/// With no speed command the rover drives at WP_SPEED (5 m/s), in GUIDED and in AUTO, whatever
/// the profile.
#[tokio::test]
async fn wp_speed_is_the_default_speed() {
    for scenario in ["", ARDUPILOT_READY] {
        let (sim, _gcs) = guided_north(scenario, 150.0, -1.0).await;
        drive_at(&sim, 15, 5.0, &format!("{scenario:?}: GUIDED")).await;

        let (sim, mut gcs) = start(scenario).await;
        start_auto(
            &mut gcs,
            &[waypoint(HOME, 0.0, 0.0), waypoint(HOME, 150.0, 0.0)],
        )
        .await;
        drive_at(&sim, 15, 5.0, &format!("{scenario:?}: AUTO")).await;
    }
}

#[tokio::test]
async fn change_speed_in_auto_sets_the_mission_speed() {
    let (sim, mut gcs) = start(ARDUPILOT_READY).await;
    start_auto(
        &mut gcs,
        &[waypoint(HOME, 0.0, 0.0), waypoint(HOME, 300.0, 0.0)],
    )
    .await;
    drive_at(&sim, 8, 5.0, "").await;
    assert_eq!(
        change_speed(&mut gcs, 0.0, 1.5).await,
        MavResult::MAV_RESULT_ACCEPTED
    );
    drive(&sim, 3).await;
    drive_at(&sim, 5, 1.5, "").await;
    // Entering AUTO again initialises the navigation at WP_SPEED.
    assert_eq!(gcs.set_mode(4).await, MavResult::MAV_RESULT_ACCEPTED);
    assert_eq!(gcs.set_mode(10).await, MavResult::MAV_RESULT_ACCEPTED);
    drive(&sim, 3).await;
    drive_at(&sim, 5, 5.0, "").await;
}

#[tokio::test]
async fn ardupilot_denies_a_reposition_to_zero_zero() {
    let (_sim, mut gcs) = start(ARDUPILOT_READY).await;
    let (r, _) = gcs
        .command_int(
            MavCmd::MAV_CMD_DO_REPOSITION,
            [-1.0, 1.0, 0.0, 0.0],
            0,
            0,
            0.0,
        )
        .await;
    assert_eq!(r, MavResult::MAV_RESULT_DENIED);
}

#[tokio::test]
async fn the_shipped_ardupilot_rover_scenario_is_the_profile_at_its_home() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/ardupilot-rover.toml");
    let scenario = sitl::Scenario::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        scenario.autopilot.behaviour(),
        sitl::Profile::Ardupilot.behaviour()
    );
    let mut cfg = sitl::SimConfig::for_tests();
    cfg.scenario = scenario;
    assert_eq!(
        cfg.home_point(),
        sitl::GeoPoint {
            lat: AP_HOME.0,
            lon: AP_HOME.1
        }
    );
    // A different configured home is an error, not a silent choice.
    cfg.home = sitl::GeoPoint {
        lat: 10.0,
        lon: 10.0,
    };
    assert!(cfg.validate().is_err());
}

/// A mission's camera items go through AP_Camera too: IMAGE_START_CAPTURE shoots (CAMERA_FEEDBACK),
/// DO_DIGICAM_CONTROL only with its shooting command (param5) at 1.
#[tokio::test]
async fn mission_camera_items_follow_ap_camera() {
    let (sim, mut gcs) = start(ARDUPILOT_READY).await;
    let digicam = |shoot: i32| MISSION_ITEM_INT_DATA {
        x: shoot,
        ..item(MavCmd::MAV_CMD_DO_DIGICAM_CONTROL, [0.0; 4])
    };
    start_auto(
        &mut gcs,
        &[
            waypoint(HOME, 0.0, 0.0),
            waypoint(HOME, 5.0, 0.0),
            item(MavCmd::MAV_CMD_IMAGE_START_CAPTURE, [0.0, 0.0, 1.0, 0.0]),
            MISSION_ITEM_INT_DATA {
                param1: 10.0,
                ..waypoint(HOME, 10.0, 0.0)
            },
            digicam(0),
            digicam(1),
            waypoint(HOME, 20.0, 0.0),
        ],
    )
    .await;
    let s = run_until(&sim, 120, |s| s.mission_complete).await;
    let feedbacks: Vec<u16> = gcs
        .sync()
        .await
        .iter()
        .filter_map(|m| match m {
            MavMessage::CAMERA_FEEDBACK(f) => Some(f.img_idx),
            _ => None,
        })
        .collect();
    assert_eq!(feedbacks, vec![1, 2], "{s:?}");
    assert_eq!(s.pictures_ok, 2);
}
