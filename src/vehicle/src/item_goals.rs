//! Mission items → goal requests (docs/goal-items.md). A list as ground stations write it is taken item by
//! item: what the companion can use becomes goals, every other item is skipped with a warning naming it
//! (never the whole list refused). Camera actions after a waypoint (IMAGE_START_CAPTURE 2000 without a
//! position, DO_DIGICAM_CONTROL 203) make that waypoint a picture goal; a camera trigger distance
//! (DO_SET_CAM_TRIGG_DIST 206, as QGroundControl's surveys and Mission Planner write it) makes a picture
//! goal every trigger distance along the waypoints it covers, in their order.

use std::ops::Range;

use mavlink::dialects::ardupilotmega::{MavCmd, MavMissionResult};

use super::goals::{KnownLocations, GOAL_ATTRIBUTES_CMD, SAMPLE_GOAL_CMD, SURVEY_GOAL_CMD};
use super::items::MissionItem;
use super::types::{GoalKind, GoalRequest};
use super::wire_float::widen;

/// Pictures one trigger distance may ask for; past it the rest of the leg is skipped with a warning.
pub const MAX_TRIGGER_PICTURES: usize = 200;

/// Why an uploaded item is not (part of) a goal; maps to the MISSION_ACK error a whole-list refusal would give.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("item {seq}: {reason}")]
pub struct ItemError {
    pub seq: usize,
    pub reason: String,
    pub ack: MavMissionResult,
}

/// One goal of a list and the items it came from (its attributes, its item, the camera actions after it).
#[derive(Debug, Clone, PartialEq)]
pub struct ListedGoal {
    pub request: GoalRequest,
    pub items: Range<usize>,
    /// Its rank among the goals of the same items (the pictures of one trigger distance).
    pub ordinal: usize,
}

/// The goals of a list and the items skipped, each with why.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct GoalList {
    pub goals: Vec<ListedGoal>,
    pub skipped: Vec<ItemError>,
}

impl GoalList {
    pub fn requests(&self) -> Vec<GoalRequest> {
        self.goals.iter().map(|g| g.request.clone()).collect()
    }
}

#[derive(Debug, Clone, Copy)]
struct Attributes {
    priority: u32,
    window: (f64, f64),
    duration: (f64, f64),
    d_achiev: f64,
}

impl Default for Attributes {
    fn default() -> Self {
        Self {
            priority: 1,
            window: (0.0, f64::INFINITY),
            duration: (0.0, f64::INFINITY),
            d_achiev: 0.0,
        }
    }
}

/// A parameter that must be a finite number ≥ 0 (NaN, infinities and negatives are refused).
fn non_negative(v: f64, what: &str) -> Result<f64, String> {
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("{what} must be a finite number >= 0, got {v}"))
    }
}

fn attributes(item: &MissionItem) -> Result<Attributes, (String, MavMissionResult)> {
    let [p1, p2, p3, p4] = item.params.map(f64::from);
    let bad = |r: String, ack| (r, ack);
    let priority = non_negative(p1, "priority (param1)")
        .map_err(|r| bad(r, MavMissionResult::MAV_MISSION_INVALID_PARAM1))?;
    let start = non_negative(p2, "window start (param2, s)")
        .map_err(|r| bad(r, MavMissionResult::MAV_MISSION_INVALID_PARAM2))?;
    let end = non_negative(p3, "window end (param3, s; 0: none)")
        .map_err(|r| bad(r, MavMissionResult::MAV_MISSION_INVALID_PARAM3))?;
    let dmin = non_negative(p4, "minimum duration (param4, s)")
        .map_err(|r| bad(r, MavMissionResult::MAV_MISSION_INVALID_PARAM4))?;
    let dmax = non_negative(item.y, "maximum duration (y, s; 0: none)")
        .map_err(|r| bad(r, MavMissionResult::MAV_MISSION_INVALID_PARAM6_Y))?;
    let achiev = non_negative(item.x, "d_achiev (x, s)")
        .map_err(|r| bad(r, MavMissionResult::MAV_MISSION_INVALID_PARAM5_X))?;
    Ok(Attributes {
        priority: priority as u32,
        window: (start, if end > 0.0 { end } else { f64::INFINITY }),
        duration: (dmin, if dmax > 0.0 { dmax } else { f64::INFINITY }),
        d_achiev: achiev,
    })
}

/// Frames whose altitude is above home (terrain frames taken as above home: a companion has no terrain model).
fn altitude_above_home(frame: u8) -> bool {
    // GLOBAL_RELATIVE_ALT (3) and its _INT twin (6), GLOBAL_TERRAIN_ALT (10) and its _INT twin (11).
    matches!(frame, 3 | 6 | 10 | 11)
}

/// A position item's latitude, longitude and altitude above mean sea level, or why it has none.
/// `home_alt` turns the relative altitudes ground stations write (frame 3 and kin) into AMSL: taken as
/// AMSL, a relative 0 m put uploaded places 150 m under a rover's home and sized their moves 4–8× too long.
fn position(
    item: &MissionItem,
    home_alt: f64,
) -> Result<(f64, f64, f64), (String, MavMissionResult)> {
    let cmd = item.command;
    if !item.has_position() {
        return Err((
            format!("command {cmd} needs a position in a global frame (x = lat, y = lon)"),
            MavMissionResult::MAV_MISSION_INVALID_PARAM5_X,
        ));
    }
    let alt = widen(item.z)
        + if altitude_above_home(item.frame) {
            home_alt
        } else {
            0.0
        };
    if !(-90.0..=90.0).contains(&item.x) || !(-180.0..=180.0).contains(&item.y) || !alt.is_finite()
    {
        return Err((
            format!(
                "position ({}, {}, {alt}) is not a latitude/longitude/altitude",
                item.x, item.y
            ),
            MavMissionResult::MAV_MISSION_INVALID_PARAM5_X,
        ));
    }
    Ok((item.x, item.y, alt))
}

const WAYPOINT: u16 = MavCmd::MAV_CMD_NAV_WAYPOINT as u16;
const LOITER_TIME: u16 = MavCmd::MAV_CMD_NAV_LOITER_TIME as u16;
const RTL: u16 = MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH as u16;
const IMAGE_START_CAPTURE: u16 = MavCmd::MAV_CMD_IMAGE_START_CAPTURE as u16;
const DIGICAM_CONTROL: u16 = MavCmd::MAV_CMD_DO_DIGICAM_CONTROL as u16;
const CAM_TRIGG_DIST: u16 = MavCmd::MAV_CMD_DO_SET_CAM_TRIGG_DIST as u16;

/// A camera trigger distance in force: where it started and the waypoints it covers so far.
struct Trigger {
    first_item: usize,
    distance_m: f64,
    path: Vec<(f64, f64, f64)>,
    attrs: Attributes,
}

struct Mapper<'a> {
    known: &'a KnownLocations,
    first_number: u32,
    list: GoalList,
    /// The goal the last waypoint made (a camera action after it makes it a picture).
    last_waypoint: Option<usize>,
    /// The position of the last waypoint, goal or not.
    last_position: Option<(f64, f64, f64)>,
    trigger: Option<Trigger>,
}

impl Mapper<'_> {
    fn skip(&mut self, seq: usize, reason: String, ack: MavMissionResult) {
        self.list.skipped.push(ItemError { seq, reason, ack });
    }

    fn push(
        &mut self,
        kind: GoalKind,
        at: Option<(f64, f64, f64)>,
        attrs: Attributes,
        items: Range<usize>,
        ordinal: usize,
    ) {
        let name = format!("g{}", self.first_number as usize + self.list.goals.len());
        let location = at.map(|(lat, lon, alt)| self.known.resolve(&name, lat, lon, alt));
        let object = location
            .as_ref()
            .map_or("home".to_string(), |l| l.name.clone());
        self.list.goals.push(ListedGoal {
            request: GoalRequest {
                proposition: format!("{}({object})", kind.predicate()),
                name,
                kind,
                location,
                priority: attrs.priority,
                start_window_s: attrs.window,
                duration_s: attrs.duration,
                d_achiev_s: attrs.d_achiev,
            },
            items,
            ordinal,
        });
    }

    /// Makes the goal of the last waypoint a picture goal there, its items extended to `seq`.
    fn picture_at_last_waypoint(&mut self, seq: usize) -> bool {
        let Some(i) = self.last_waypoint else {
            return false;
        };
        let g = &mut self.list.goals[i];
        if g.request.kind != GoalKind::PictureOf {
            g.request.kind = GoalKind::PictureOf;
            let object = g.request.location.as_ref().map_or("home", |l| &l.name);
            g.request.proposition = format!("{}({object})", GoalKind::PictureOf.predicate());
        }
        g.items.end = seq + 1;
        true
    }

    /// The trigger in force ends at item `last`: a picture every trigger distance along its waypoints.
    fn end_trigger(&mut self, last: usize) {
        let Some(t) = self.trigger.take() else {
            return;
        };
        let home = self.known.home;
        let local: Vec<_> = t
            .path
            .iter()
            .map(|&(lat, lon, alt)| home.to_local(lat, lon, alt))
            .collect();
        let mut points = Vec::new();
        // Distance still to go to the next picture; the first picture is at the trigger's first waypoint.
        let mut to_next = 0.0;
        for w in local.windows(2) {
            let (a, b) = (w[0], w[1]);
            let leg = a.horizontal_distance(&b);
            let mut along = to_next;
            while along <= leg + 1e-9 {
                let f = if leg > 0.0 { along / leg } else { 0.0 };
                points.push(super::types::Enu::new(
                    a.east + f * (b.east - a.east),
                    a.north + f * (b.north - a.north),
                    a.up + f * (b.up - a.up),
                ));
                along += t.distance_m;
            }
            to_next = along - leg;
        }
        if local.len() == 1 {
            points.push(local[0]);
        }
        if points.len() > MAX_TRIGGER_PICTURES {
            let n = points.len();
            points.truncate(MAX_TRIGGER_PICTURES);
            self.skip(
                t.first_item,
                format!(
                    "a trigger distance of {} m asks for {n} pictures; the first {MAX_TRIGGER_PICTURES} are kept",
                    t.distance_m
                ),
                MavMissionResult::MAV_MISSION_NO_SPACE,
            );
        }
        for (k, p) in points.into_iter().enumerate() {
            let at = home.to_global(p);
            self.push(
                GoalKind::PictureOf,
                Some(at),
                t.attrs,
                t.first_item..last + 1,
                k,
            );
        }
    }

    fn item(&mut self, seq: usize, item: &MissionItem, attrs: Option<(usize, Attributes)>) {
        let first = attrs.map_or(seq, |(s, _)| s);
        let attrs = attrs.map(|(_, a)| a).unwrap_or_default();
        let cmd = item.command;
        let kind = match cmd {
            WAYPOINT | LOITER_TIME => GoalKind::BeAt,
            IMAGE_START_CAPTURE if item.has_position() => GoalKind::PictureOf,
            IMAGE_START_CAPTURE | DIGICAM_CONTROL => {
                if self.trigger.is_some() {
                    // A capture during a trigger distance: one more picture where the vehicle last was.
                    if let Some(at) = self.last_position {
                        self.push(GoalKind::PictureOf, Some(at), attrs, first..seq + 1, 0);
                        return;
                    }
                }
                if !self.picture_at_last_waypoint(seq) {
                    self.skip(
                        seq,
                        format!(
                            "camera command {cmd} has no waypoint before it to take the picture at"
                        ),
                        MavMissionResult::MAV_MISSION_INVALID_SEQUENCE,
                    );
                }
                return;
            }
            CAM_TRIGG_DIST => {
                let d = f64::from(item.params[0]);
                if !(d.is_finite() && d >= 0.0) {
                    self.skip(
                        seq,
                        format!("camera trigger distance (param1) must be a finite number >= 0 m, got {d}"),
                        MavMissionResult::MAV_MISSION_INVALID_PARAM1,
                    );
                    return;
                }
                self.end_trigger(seq);
                if d > 0.0 {
                    let path = self.last_position.into_iter().collect();
                    let first_item = first.min(self.last_waypoint_item(seq));
                    // The waypoint the trigger starts at is its first picture, not a goal of its own (it is
                    // the last goal made).
                    if self.last_waypoint.take().is_some() {
                        self.list.goals.pop();
                    }
                    self.trigger = Some(Trigger {
                        first_item,
                        distance_m: d,
                        path,
                        attrs,
                    });
                }
                return;
            }
            SAMPLE_GOAL_CMD => GoalKind::SampleAt,
            SURVEY_GOAL_CMD => GoalKind::SurveyOf,
            RTL => GoalKind::ReturnHome,
            other => {
                self.skip(
                    seq,
                    format!("command {other} is not a goal: skipped"),
                    MavMissionResult::MAV_MISSION_UNSUPPORTED,
                );
                return;
            }
        };
        if kind == GoalKind::ReturnHome {
            self.end_trigger(seq.saturating_sub(1));
            self.last_waypoint = None;
            self.push(kind, None, attrs, first..seq + 1, 0);
            return;
        }
        let at = match position(item, self.known.home.alt) {
            Ok(at) => at,
            Err((reason, ack)) => {
                self.skip(seq, reason, ack);
                return;
            }
        };
        let mut attrs = attrs;
        if cmd == LOITER_TIME && attrs.duration.0 == 0.0 {
            // Loiter time = how long the position must hold, unless attributes said otherwise.
            match non_negative(widen(item.params[0]), "loiter time (param1, s)") {
                Ok(t) => attrs.duration.0 = t,
                Err(reason) => {
                    self.skip(seq, reason, MavMissionResult::MAV_MISSION_INVALID_PARAM1);
                    return;
                }
            }
        }
        self.last_position = Some(at);
        if let Some(t) = &mut self.trigger {
            if kind == GoalKind::BeAt {
                // A waypoint under a trigger distance is a leg of the pictures, not a goal of its own.
                t.path.push(at);
                return;
            }
        }
        self.last_waypoint = (kind == GoalKind::BeAt).then_some(self.list.goals.len());
        self.push(kind, Some(at), attrs, first..seq + 1, 0);
    }

    /// The first item of the last waypoint's goal (where a trigger starting there begins), else `seq`.
    fn last_waypoint_item(&self, seq: usize) -> usize {
        self.last_waypoint
            .and_then(|i| self.list.goals.get(i))
            .map_or(seq, |g| g.items.start)
    }
}

/// Maps an uploaded item list to goal requests, named `g<first_number>`, `g<first_number+1>`, ...; items
/// that are no goal are skipped, each with why.
pub fn items_to_goals(
    items: &[MissionItem],
    known: &KnownLocations,
    first_number: u32,
) -> GoalList {
    let mut m = Mapper {
        known,
        first_number,
        list: GoalList::default(),
        last_waypoint: None,
        last_position: None,
        trigger: None,
    };
    let mut pending: Option<(usize, Attributes)> = None;
    // Invalid attributes at this item: the goal after them is not taken without them.
    let mut invalid: Option<usize> = None;
    for (seq, item) in items.iter().enumerate() {
        if item.command == GOAL_ATTRIBUTES_CMD {
            if let Some((s, _)) = pending {
                m.skip(
                    s,
                    "goal attributes (MAV_CMD_USER_2) followed by more attributes: skipped".into(),
                    MavMissionResult::MAV_MISSION_INVALID,
                );
            }
            match attributes(item) {
                Ok(a) => pending = Some((seq, a)),
                Err((reason, ack)) => {
                    m.skip(seq, format!("{reason}: the goal after it is skipped"), ack);
                    pending = None;
                    invalid = Some(seq);
                }
            }
            continue;
        }
        if let Some(s) = invalid.take() {
            m.skip(
                seq,
                format!("its attributes (item {s}) are invalid: skipped"),
                MavMissionResult::MAV_MISSION_INVALID,
            );
            continue;
        }
        m.item(seq, item, pending.take());
    }
    if let Some((s, _)) = pending {
        m.skip(
            s,
            "goal attributes (MAV_CMD_USER_2) with no goal item after them".into(),
            MavMissionResult::MAV_MISSION_INVALID,
        );
    }
    m.end_trigger(items.len().saturating_sub(1));
    // Names in list order (a trigger's pictures come after the goals that followed them otherwise).
    for (i, g) in m.list.goals.iter_mut().enumerate() {
        rename(&mut g.request, format!("g{}", first_number as usize + i));
    }
    m.list.skipped.sort_by_key(|e| e.seq);
    m.list
}

/// Names a goal `name`, and its new place `<name>_loc`.
pub fn rename(request: &mut GoalRequest, name: String) {
    if let Some(l) = request.location.as_mut().filter(|l| l.new) {
        l.name = format!("{name}_loc");
        let pred = request.kind.predicate();
        request.proposition = format!("{pred}({})", l.name);
    }
    request.name = name;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geo::Home;

    fn home() -> Home {
        Home {
            lat: 43.5,
            lon: 1.4,
            alt: 0.0,
        }
    }

    fn at(cmd: u16) -> MissionItem {
        let mut it = MissionItem::waypoint(43.5001, 1.4001, 0.0);
        it.command = cmd;
        it
    }

    /// Each goal item command becomes its kind, the key the config's `[mapping.goals]` maps.
    #[test]
    fn item_commands_become_goal_kinds() {
        let items = vec![
            at(WAYPOINT),
            at(IMAGE_START_CAPTURE),
            at(SAMPLE_GOAL_CMD),
            at(SURVEY_GOAL_CMD),
            at(RTL),
        ];
        let list = items_to_goals(&items, &KnownLocations::new(home()), 1);
        assert!(list.skipped.is_empty(), "{:?}", list.skipped);
        let kinds: Vec<(&str, bool)> = list
            .goals
            .iter()
            .map(|g| (g.request.kind.key(), g.request.location.is_some()))
            .collect();
        assert_eq!(
            kinds,
            vec![
                ("waypoint", true),
                ("picture", true),
                ("sample", true),
                ("survey", true),
                ("return_home", false),
            ]
        );
        assert_eq!(list.goals[3].request.proposition, "surveyed(g4_loc)");
    }

    #[test]
    fn relative_altitudes_are_above_home_and_global_ones_above_sea_level() {
        let h = Home {
            alt: 150.0,
            ..home()
        };
        let mut amsl = MissionItem::waypoint(43.5003, 1.4, 150.0);
        amsl.frame = 0; // MAV_FRAME_GLOBAL: altitude above mean sea level
        let items = vec![MissionItem::waypoint(43.5003, 1.4, 0.0), amsl];
        let list = items_to_goals(&items, &KnownLocations::new(h), 1);
        assert_eq!(list.goals.len(), 2, "{:?}", list.skipped);
        for g in &list.goals {
            let at = g.request.location.as_ref().expect("a place").at;
            // 0 m above a home 150 m above sea level, and 150 m above sea level: both on the ground.
            assert!(at.up.abs() < 0.5, "{}: up {}", g.request.name, at.up);
            assert!((at.north - 33.4).abs() < 0.5, "north {}", at.north);
        }
    }

    fn camera(cmd: u16, p1: f32) -> MissionItem {
        let mut it = MissionItem::new(
            MavCmd::MAV_CMD_NAV_WAYPOINT,
            mavlink::dialects::ardupilotmega::MavFrame::MAV_FRAME_MISSION,
        );
        it.command = cmd;
        it.params[0] = p1;
        it
    }

    #[test]
    fn a_camera_action_after_a_waypoint_makes_it_a_picture_goal_and_others_are_skipped_by_name() {
        let items = vec![
            MissionItem::waypoint(43.5001, 1.4001, 0.0),
            camera(IMAGE_START_CAPTURE, 0.0),
            camera(178, 2.0), // DO_CHANGE_SPEED
            MissionItem::waypoint(43.5002, 1.4001, 0.0),
            camera(DIGICAM_CONTROL, 0.0),
        ];
        let list = items_to_goals(&items, &KnownLocations::new(home()), 6);
        let props: Vec<_> = list
            .goals
            .iter()
            .map(|g| g.request.proposition.clone())
            .collect();
        assert_eq!(props, ["picture_of(g6_loc)", "picture_of(g7_loc)"]);
        assert_eq!(list.goals[0].items, 0..2);
        assert_eq!(list.skipped.len(), 1);
        assert_eq!(list.skipped[0].seq, 2);
        assert!(
            list.skipped[0].reason.contains("command 178"),
            "{:?}",
            list.skipped
        );
    }

    #[test]
    fn a_trigger_distance_makes_pictures_along_the_legs_in_order() {
        let h = home();
        let p = |e: f64, n: f64| {
            let (lat, lon, _) = h.to_global(crate::types::Enu::new(e, n, 0.0));
            MissionItem::waypoint(lat, lon, 0.0)
        };
        let items = vec![
            p(0.0, 10.0),
            camera(CAM_TRIGG_DIST, 10.0),
            p(30.0, 10.0),
            p(30.0, 20.0),
            camera(CAM_TRIGG_DIST, 0.0),
        ];
        let list = items_to_goals(&items, &KnownLocations::new(h), 1);
        assert!(list.skipped.is_empty(), "{:?}", list.skipped);
        let spots: Vec<(i64, i64)> = list
            .goals
            .iter()
            .map(|g| {
                let l = g.request.location.as_ref().expect("a place");
                (l.at.east.round() as i64, l.at.north.round() as i64)
            })
            .collect();
        assert_eq!(spots, [(0, 10), (10, 10), (20, 10), (30, 10), (30, 20)]);
        assert!(list
            .goals
            .iter()
            .all(|g| g.request.kind == GoalKind::PictureOf));
    }

    #[test]
    fn non_finite_or_negative_parameters_are_refused() {
        let mut attrs = camera(GOAL_ATTRIBUTES_CMD, 1.0);
        attrs.params[1] = f32::NAN;
        let mut loiter = at(LOITER_TIME);
        loiter.params[0] = -5.0;
        let mut inf_end = camera(GOAL_ATTRIBUTES_CMD, 1.0);
        inf_end.params[2] = f32::INFINITY;
        let items = vec![
            attrs,
            at(WAYPOINT),
            loiter,
            inf_end,
            at(WAYPOINT),
            at(WAYPOINT),
        ];
        let list = items_to_goals(&items, &KnownLocations::new(home()), 1);
        let seqs: Vec<usize> = list.skipped.iter().map(|e| e.seq).collect();
        assert_eq!(seqs, [0, 1, 2, 3, 4], "{:?}", list.skipped);
        assert_eq!(list.goals.len(), 1);
        assert!(
            list.skipped[0].reason.contains("window start"),
            "{:?}",
            list.skipped
        );
    }
}
