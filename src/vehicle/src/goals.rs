//! Goal lists from a ground station: mission items → goal requests (the mapping the README documents), and the
//! accept/reject decision, which belongs to the executive (seed 1 §3.3's constraint test) and reaches it as a
//! [`GoalBatch`] to answer; [`SyntacticDecider`] is the stand-in when no executive decides.

use mavlink::dialects::ardupilotmega::MavMissionResult;
use num_traits::ToPrimitive;

use super::geo::Home;
use super::types::{Enu, GoalLocation, GoalRequest, GoalVerdict};

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

    pub(crate) fn resolve(&self, goal_name: &str, lat: f64, lon: f64, alt: f64) -> GoalLocation {
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

pub use super::item_goals::{items_to_goals, GoalList, ItemError, ListedGoal};

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

/// One goal of an upload, watched after its verdict: its later fate (achieved, rejected by a replanning,
/// cancelled) is told to the goal intake, which keeps the list a ground station reads back true.
#[derive(Debug, Clone)]
pub struct GoalWatch {
    tx: tokio::sync::mpsc::UnboundedSender<(usize, GoalVerdict)>,
    index: usize,
}

impl GoalWatch {
    /// Tells the goal intake (ignored if it went away).
    pub fn tell(&self, verdict: GoalVerdict) {
        let _ = self.tx.send((self.index, verdict));
    }
}

impl GoalBatch {
    /// A watch on goal `i` for its fate after the verdict; `None` for a batch nobody waits on.
    pub fn watch(&self, i: usize) -> Option<GoalWatch> {
        self.later.as_ref().map(|tx| GoalWatch {
            tx: tx.clone(),
            index: i,
        })
    }
}

/// Goals a ground station withdraws (by name), and why in its words; the executive answers with the names
/// it withdrew (those it still held or was inserting).
#[derive(Debug)]
pub struct GoalCancel {
    pub names: Vec<String>,
    pub reason: String,
    pub reply: Option<tokio::sync::oneshot::Sender<Vec<String>>>,
}

impl GoalCancel {
    pub fn new(
        names: Vec<String>,
        reason: String,
    ) -> (Self, tokio::sync::oneshot::Receiver<Vec<String>>) {
        let (tx, rx) = tokio::sync::oneshot::channel();
        (
            Self {
                names,
                reason,
                reply: Some(tx),
            },
            rx,
        )
    }

    /// Answers with the names withdrawn.
    pub fn answer(mut self, withdrawn: Vec<String>) {
        if let Some(tx) = self.reply.take() {
            let _ = tx.send(withdrawn);
        }
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
        GoalVerdict::Achieved => format!("{} achieved: {}", goal.name, goal.proposition),
        GoalVerdict::Cancelled(reason) => format!("{} cancelled: {reason}", goal.name),
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
        && matches!(
            verdict,
            "accepted:" | "rejected:" | "achieved:" | "cancelled:"
        )
}

/// How many final verdicts a large upload's summary line (`100 goals (g1-g100): 75 x accepted; 25 x
/// rejected: …`) carries: every count but the goals still "received, verdict to follow".
pub fn summary_finals(text: &str) -> Option<usize> {
    let (head, rest) = text.split_once(" goals (g")?;
    head.parse::<usize>().ok()?;
    let (_, counts) = rest.split_once("): ")?;
    Some(
        counts
            .split("; ")
            .filter(|c| !c.ends_with("received, verdict to follow"))
            .filter_map(|c| c.split_once(" x ")?.0.parse::<usize>().ok())
            .sum(),
    )
}

/// The MAVLink value of a MISSION_ACK result (for messages and logs).
pub fn ack_code(r: MavMissionResult) -> u8 {
    r.to_u8().unwrap_or(u8::MAX)
}
