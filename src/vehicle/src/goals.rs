//! Goal lists from a ground station: mission items → goal requests (the mapping the README documents), and the
//! accept/reject decision, which belongs to the executive (seed 1 §3.3's constraint test) and reaches it as a
//! [`GoalBatch`] to answer; [`SyntacticDecider`] is the stand-in when no executive decides.

use mavlink::dialects::ardupilotmega::{MavCmd, MavMissionResult};
use num_traits::ToPrimitive;

use super::geo::Home;
use super::items::MissionItem;
use super::types::{Enu, GoalKind, GoalLocation, GoalRequest, GoalVerdict};

/// `MAV_CMD_USER_2`: attributes of the goal item that follows (priority, window, duration, d_achiev).
/// (`MAV_CMD_USER_1` is left to the simulator's downlink command.)
pub const GOAL_ATTRIBUTES_CMD: u16 = 31011;
/// `MAV_CMD_SPATIAL_USER_1`: take a sample at the item's position.
pub const SAMPLE_GOAL_CMD: u16 = 31005;
/// `MAV_CMD_SPATIAL_USER_2`: survey the item's position.
pub const SURVEY_GOAL_CMD: u16 = 31006;

/// Objects of the problem that have a position, so an uploaded position can be recognised as one of them.
#[derive(Debug, Clone)]
pub struct KnownLocations {
    pub home: Home,
    pub objects: Vec<(String, Enu)>,
    /// An uploaded position within this distance of an object names that object.
    pub match_radius_m: f64,
}

impl KnownLocations {
    pub fn new(home: Home) -> Self {
        Self {
            home,
            objects: Vec::new(),
            match_radius_m: 2.0,
        }
    }

    fn resolve(&self, goal_name: &str, lat: f64, lon: f64, alt: f64) -> GoalLocation {
        let at = self.home.to_local(lat, lon, alt);
        let known = self
            .objects
            .iter()
            .map(|(n, p)| (n, p.horizontal_distance(&at)))
            .filter(|(_, d)| *d <= self.match_radius_m)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match known {
            Some((name, _)) => GoalLocation {
                name: name.clone(),
                new: false,
                at,
                lat,
                lon,
            },
            None => GoalLocation {
                name: format!("{goal_name}_loc"),
                new: true,
                at,
                lat,
                lon,
            },
        }
    }
}

/// Why an uploaded item cannot be a goal; maps to the MISSION_ACK error.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("item {seq}: {reason}")]
pub struct ItemError {
    pub seq: usize,
    pub reason: String,
    pub ack: MavMissionResult,
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

/// Maps an uploaded item list to goal requests, naming them `g<first_number>`, `g<first_number+1>`, ...
pub fn items_to_goals(
    items: &[MissionItem],
    known: &KnownLocations,
    first_number: u32,
) -> Result<Vec<GoalRequest>, ItemError> {
    let mut goals = Vec::new();
    let mut pending: Option<Attributes> = None;
    for (seq, item) in items.iter().enumerate() {
        let err = |reason: String, ack| ItemError { seq, reason, ack };
        if item.command == GOAL_ATTRIBUTES_CMD {
            let [p1, p2, p3, p4] = item.params.map(f64::from);
            if !(p1.is_finite() && p1 >= 0.0) {
                return Err(err(
                    format!("priority (param1) must be a number >= 0, got {p1}"),
                    MavMissionResult::MAV_MISSION_INVALID_PARAM1,
                ));
            }
            pending = Some(Attributes {
                priority: p1 as u32,
                window: (p2.max(0.0), if p3 > 0.0 { p3 } else { f64::INFINITY }),
                duration: (
                    p4.max(0.0),
                    if item.y > 0.0 { item.y } else { f64::INFINITY },
                ),
                d_achiev: item.x.max(0.0),
            });
            continue;
        }
        let name = format!("g{}", first_number as usize + goals.len());
        let mut attrs = pending.take().unwrap_or_default();
        let cmd = item.command;
        let kind = match cmd {
            c if c == MavCmd::MAV_CMD_NAV_WAYPOINT as u16 => GoalKind::BeAt,
            c if c == MavCmd::MAV_CMD_NAV_LOITER_TIME as u16 => {
                // Loiter time = how long the position must hold, unless attributes said otherwise.
                if attrs.duration.0 == 0.0 {
                    attrs.duration.0 = super::wire_float::widen(item.params[0]).max(0.0);
                }
                GoalKind::BeAt
            }
            c if c == MavCmd::MAV_CMD_IMAGE_START_CAPTURE as u16 => GoalKind::PictureOf,
            SAMPLE_GOAL_CMD => GoalKind::SampleAt,
            SURVEY_GOAL_CMD => GoalKind::SurveyOf,
            c if c == MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH as u16 => GoalKind::ReturnHome,
            other => {
                return Err(err(
                    format!("command {other} is not a goal (see README: goal items)"),
                    MavMissionResult::MAV_MISSION_UNSUPPORTED,
                ))
            }
        };
        let needs_position = cmd != MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH as u16;
        let location = if needs_position {
            if !item.has_position() {
                return Err(err(
                    format!("command {cmd} needs a position in a global frame (x = lat, y = lon)"),
                    MavMissionResult::MAV_MISSION_INVALID_PARAM5_X,
                ));
            }
            if !(-90.0..=90.0).contains(&item.x) || !(-180.0..=180.0).contains(&item.y) {
                return Err(err(
                    format!(
                        "position ({}, {}) is not a latitude/longitude",
                        item.x, item.y
                    ),
                    MavMissionResult::MAV_MISSION_INVALID_PARAM5_X,
                ));
            }
            Some(known.resolve(&name, item.x, item.y, super::wire_float::widen(item.z)))
        } else {
            None
        };
        let object = location
            .as_ref()
            .map_or("home".to_string(), |l| l.name.clone());
        goals.push(GoalRequest {
            proposition: format!("{}({object})", kind.predicate()),
            name,
            kind,
            location,
            priority: attrs.priority,
            start_window_s: attrs.window,
            duration_s: attrs.duration,
            d_achiev_s: attrs.d_achiev,
        });
    }
    if pending.is_some() {
        return Err(ItemError {
            seq: items.len().saturating_sub(1),
            reason: "goal attributes (MAV_CMD_USER_2) with no goal item after them".into(),
            ack: MavMissionResult::MAV_MISSION_INVALID,
        });
    }
    Ok(goals)
}

/// Decides which goals of an upload are accepted.
pub trait GoalDecider: Send {
    fn decide(&mut self, goals: &[GoalRequest]) -> Vec<GoalVerdict>;
}

/// The default decider: rejects what is inconsistent on its face; the executive's constraint test replaces it.
#[derive(Debug, Default, Clone, Copy)]
pub struct SyntacticDecider;

impl SyntacticDecider {
    pub fn verdict(g: &GoalRequest) -> GoalVerdict {
        let (ws, we) = g.start_window_s;
        let (dmin, dmax) = g.duration_s;
        if we < ws {
            GoalVerdict::Rejected("window ends before it starts".into())
        } else if we < g.d_achiev_s {
            GoalVerdict::Rejected("window ends before reachable".into())
        } else if dmax < dmin {
            GoalVerdict::Rejected("max duration below min duration".into())
        } else {
            GoalVerdict::Accepted
        }
    }
}

impl GoalDecider for SyntacticDecider {
    fn decide(&mut self, goals: &[GoalRequest]) -> Vec<GoalVerdict> {
        goals.iter().map(Self::verdict).collect()
    }
}

/// The verdicts that follow an upload's answer: `(index of the goal in the upload, final verdict)`.
pub type LaterVerdicts = tokio::sync::mpsc::UnboundedReceiver<(usize, GoalVerdict)>;

/// A goal list handed to the executive. The upload is answered once ([`GoalBatch::answer`] or
/// [`GoalBatch::answer_now`]: the MISSION_ACK and a STATUSTEXT per goal); a goal still being inserted into the
/// plan then is answered [`GoalVerdict::Inserting`] and its final verdict ([`GoalBatch::decide`]) follows on
/// its own.
#[derive(Debug)]
pub struct GoalBatch {
    pub goals: Vec<GoalRequest>,
    reply: Option<tokio::sync::oneshot::Sender<Vec<GoalVerdict>>>,
    later: Option<tokio::sync::mpsc::UnboundedSender<(usize, GoalVerdict)>>,
    verdicts: Vec<Option<GoalVerdict>>,
    answered: bool,
}

impl GoalBatch {
    pub fn new(
        goals: Vec<GoalRequest>,
    ) -> (Self, tokio::sync::oneshot::Receiver<Vec<GoalVerdict>>) {
        let (batch, rx, _) = Self::with_later(goals);
        (batch, rx)
    }

    /// A batch whose final verdicts after the answer come out of the [`LaterVerdicts`] receiver.
    pub fn with_later(
        goals: Vec<GoalRequest>,
    ) -> (
        Self,
        tokio::sync::oneshot::Receiver<Vec<GoalVerdict>>,
        LaterVerdicts,
    ) {
        let (tx, rx) = tokio::sync::oneshot::channel();
        let (later_tx, later_rx) = tokio::sync::mpsc::unbounded_channel();
        let verdicts = vec![None; goals.len()];
        (
            Self {
                goals,
                reply: Some(tx),
                later: Some(later_tx),
                verdicts,
                answered: false,
            },
            rx,
            later_rx,
        )
    }

    /// A batch nobody waits on (the mock vehicle's scripted goal requests).
    pub fn detached(goals: Vec<GoalRequest>) -> Self {
        let verdicts = vec![None; goals.len()];
        Self {
            goals,
            reply: None,
            later: None,
            verdicts,
            answered: false,
        }
    }

    /// Sends all the verdicts back to the goal intake at once (ignored if the ground station went away).
    pub fn answer(mut self, verdicts: Vec<GoalVerdict>) {
        self.verdicts = verdicts.into_iter().map(Some).collect();
        self.answer_now();
    }

    /// Goal `i`'s verdict: kept for the answer, or, once the upload is answered, sent after it.
    pub fn decide(&mut self, i: usize, verdict: GoalVerdict) {
        let Some(slot) = self.verdicts.get_mut(i) else {
            return;
        };
        *slot = Some(verdict.clone());
        if self.answered && verdict.is_final() {
            if let Some(tx) = &self.later {
                let _ = tx.send((i, verdict));
            }
        }
    }

    /// Answers the upload with the verdicts known so far: [`GoalVerdict::Inserting`] for the others.
    pub fn answer_now(&mut self) {
        if self.answered {
            return;
        }
        self.answered = true;
        let verdicts = self
            .verdicts
            .iter()
            .map(|v| v.clone().unwrap_or(GoalVerdict::Inserting))
            .collect();
        if let Some(tx) = self.reply.take() {
            let _ = tx.send(verdicts);
        }
    }

    /// Answered, and every goal has its final verdict.
    pub fn settled(&self) -> bool {
        self.answered
            && self
                .verdicts
                .iter()
                .all(|v| v.as_ref().is_some_and(GoalVerdict::is_final))
    }
}

/// The STATUSTEXT line for one verdict.
pub fn verdict_text(goal: &GoalRequest, verdict: &GoalVerdict) -> String {
    match verdict {
        GoalVerdict::Accepted => format!("{} accepted: {}", goal.name, goal.proposition),
        GoalVerdict::Rejected(reason) => format!("{} rejected: {reason}", goal.name),
        GoalVerdict::Inserting => {
            format!("{} received: {}; {INSERTING}", goal.name, goal.proposition)
        }
    }
}

/// How a [`GoalVerdict::Inserting`] text ends: the ground station waits for the final verdict.
pub const INSERTING: &str = "inserting it into the plan, verdict to follow";

/// Whether a STATUSTEXT is a goal's final verdict (`g<n> accepted: …` or `g<n> rejected: …`).
pub fn is_final_verdict_text(text: &str) -> bool {
    let mut words = text.splitn(3, ' ');
    let name = words.next().unwrap_or("");
    let verdict = words.next().unwrap_or("");
    name.len() > 1
        && name.starts_with('g')
        && name[1..].bytes().all(|b| b.is_ascii_digit())
        && (verdict == "accepted:" || verdict == "rejected:")
}

/// The MAVLink value of a MISSION_ACK result (for messages and logs).
pub fn ack_code(r: MavMissionResult) -> u8 {
    r.to_u8().unwrap_or(u8::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each goal item command becomes its kind, the key the config's `[mapping.goals]` maps.
    #[test]
    fn item_commands_become_goal_kinds() {
        let home = Home {
            lat: 43.5,
            lon: 1.4,
            alt: 0.0,
        };
        let at = |cmd: u16| {
            let mut it = MissionItem::waypoint(43.5001, 1.4001, 0.0);
            it.command = cmd;
            it
        };
        let items = vec![
            at(MavCmd::MAV_CMD_NAV_WAYPOINT as u16),
            at(MavCmd::MAV_CMD_IMAGE_START_CAPTURE as u16),
            at(SAMPLE_GOAL_CMD),
            at(SURVEY_GOAL_CMD),
            at(MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH as u16),
        ];
        let goals = items_to_goals(&items, &KnownLocations::new(home), 1).expect("goals");
        let kinds: Vec<(&str, bool)> = goals
            .iter()
            .map(|g| (g.kind.key(), g.location.is_some()))
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
        assert_eq!(goals[3].proposition, "surveyed(g4_loc)");
    }
}
