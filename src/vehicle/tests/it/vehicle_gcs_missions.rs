//! Missions as ground stations write them (issue 30 item 4): a QGroundControl `.plan` with a survey and
//! camera actions, and a Mission Planner `.waypoints` with DO_DIGICAM_CONTROL and a camera trigger
//! distance, give the picture goals expected, in order, and a warning naming each other item.

use mavtempo_vehicle::goal_files::load;
use mavtempo_vehicle::goals::{items_to_goals, KnownLocations};
use mavtempo_vehicle::GoalKind;

fn fixture(name: &str) -> std::path::PathBuf {
    std::path::Path::new(repo!("tests/fixtures/vehicle")).join(name)
}

/// A goal's kind and where it is (metres east, north of home, rounded).
type Spot = (GoalKind, Option<(i64, i64)>);

/// Each goal of the file and the warnings naming what was skipped.
fn goals(name: &str) -> (Vec<Spot>, Vec<String>) {
    let f = load(&fixture(name)).expect("loads");
    let list = items_to_goals(&f.items, &KnownLocations::new(f.home.expect("home")), 1);
    let goals = list
        .goals
        .iter()
        .map(|g| {
            (
                g.request.kind,
                g.request
                    .location
                    .as_ref()
                    .map(|l| (l.at.east.round() as i64, l.at.north.round() as i64)),
            )
        })
        .collect();
    let warnings = f
        .skipped
        .iter()
        .map(|e| e.to_string())
        .chain(list.skipped.iter().map(|e| e.to_string()))
        .collect();
    (goals, warnings)
}

#[test]
fn a_qgc_plan_with_a_survey_and_camera_actions_gives_pictures_along_the_transects() {
    let (goals, warnings) = goals("survey.plan");
    let pic = |e, n| (GoalKind::PictureOf, Some((e, n)));
    assert_eq!(
        goals,
        [
            // The waypoint with IMAGE_START_CAPTURE after it.
            pic(10, 5),
            // The survey's transects, a picture every 9 m (its trigger distance) in their order.
            pic(0, 20),
            pic(9, 20),
            pic(18, 20),
            pic(27, 20),
            pic(30, 26),
            pic(25, 30),
            pic(16, 30),
            pic(7, 30),
            (GoalKind::ReturnHome, None),
        ]
    );
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(
        warnings[0].contains("mission.items[4]") && warnings[0].contains("StructureScan"),
        "{warnings:?}"
    );
    assert!(
        warnings[1].starts_with("item 2: command 178 is not a goal"),
        "{warnings:?}"
    );
}

#[test]
fn a_mission_planner_file_with_digicam_and_trigger_distance_gives_pictures() {
    let (goals, warnings) = goals("camera.waypoints");
    let pic = |e, n| (GoalKind::PictureOf, Some((e, n)));
    assert_eq!(goals, [pic(10, 5), pic(0, 20), pic(5, 20), pic(10, 20)]);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].starts_with("item 6: command 178 is not a goal"),
        "{warnings:?}"
    );
}
