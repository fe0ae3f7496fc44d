//! The vocabulary shared by the executive and a vehicle: action instances to start (seed 1 §2.1
//! `START a p_a i_a`), reports on their completion, and the other messages of §3.3.
//! Everything is in vehicle terms (local ENU metres from the problem's home, task names as text) so the
//! executive converts its model types to and from these without the vehicle depending on the model.

use std::fmt;

/// `i_a` (seed 1 §3.5): the identifier the vehicle knows an action instance by, chosen by the executive.
pub type VehicleActionId = u64;

/// A point in the local East-North-Up frame of the problem's home, in metres.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Enu {
    pub east: f64,
    pub north: f64,
    pub up: f64,
}

impl Enu {
    pub fn new(east: f64, north: f64, up: f64) -> Self {
        Self { east, north, up }
    }

    /// Horizontal distance (the rover and the surface vehicle ignore depth differences for arrival).
    pub fn horizontal_distance(&self, other: &Enu) -> f64 {
        (self.east - other.east).hypot(self.north - other.north)
    }
}

/// One grounded parameter of `p_a`.
#[derive(Debug, Clone, PartialEq)]
pub enum Arg {
    /// A location object of the problem, with its coordinates relative to home.
    Location {
        name: String,
        east: f64,
        north: f64,
        up: f64,
    },
    /// Any other symbolic object (camera, sampler, ...).
    Symbol(String),
    Number(f64),
}

impl Arg {
    pub fn location(name: &str, at: Enu) -> Self {
        Arg::Location {
            name: name.to_string(),
            east: at.east,
            north: at.north,
            up: at.up,
        }
    }

    pub fn as_enu(&self) -> Option<Enu> {
        match self {
            Arg::Location {
                east, north, up, ..
            } => Some(Enu::new(*east, *north, *up)),
            _ => None,
        }
    }

    pub fn as_number(&self) -> Option<f64> {
        match self {
            Arg::Number(n) => Some(*n),
            _ => None,
        }
    }
}

/// `START a p_a i_a`: the task name `a` (as in the domain), its parameters by name, and `i_a`.
#[derive(Debug, Clone, PartialEq)]
pub struct ActionStart {
    pub id: VehicleActionId,
    pub task: String,
    pub args: Vec<(String, Arg)>,
}

impl ActionStart {
    pub fn arg(&self, name: &str) -> Option<&Arg> {
        self.args.iter().find(|(n, _)| n == name).map(|(_, a)| a)
    }
}

/// The ending status of an action (seed 1 §2.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum ReportStatus {
    Nominal,
    Interrupted,
    Failed,
}

impl fmt::Display for ReportStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ReportStatus::Nominal => "nominal",
            ReportStatus::Interrupted => "interrupted",
            ReportStatus::Failed => "failed",
        })
    }
}

/// The global level of a resource (not the share used by one action: seed 1 §2.1 footnote 1).
#[derive(Debug, Clone, PartialEq)]
pub struct ResourceLevel {
    pub resource: String,
    pub level: f64,
}

/// The value of a state variable relevant to an action, returned when the report is not nominal.
#[derive(Debug, Clone, PartialEq)]
pub enum StateValue {
    /// A position; the executive maps it to a known location or creates a new location object.
    Position(Enu),
    Symbol(String),
    Number(f64),
}

/// The report sent upon an action's completion.
#[derive(Debug, Clone, PartialEq)]
pub struct ActionReport {
    pub id: VehicleActionId,
    pub status: ReportStatus,
    /// Vehicle time of the completion, in ms.
    pub time_ms: u64,
    /// Final levels of the resources the action uses.
    pub resources: Vec<ResourceLevel>,
    /// Final values of the action's state variables, empty when nominal.
    pub state: Vec<(String, StateValue)>,
    /// Why the action failed or was interrupted, for the trace.
    pub reason: Option<String>,
}

/// Link status changes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinkStatus {
    /// First heartbeat of the autopilot: its system id is adopted.
    Up { system_id: u8 },
    /// No heartbeat within the timeout, or the transport closed.
    Lost,
    /// Heartbeats again after a loss.
    Recovered,
    /// The autopilot restarted (its clock went back): the running actions were commanded again.
    Restarted,
}

/// An exogenous alteration of a resource capacity (seed 1 §3.3), e.g. a partial loss of storage.
#[derive(Debug, Clone, PartialEq)]
pub struct CapacityChange {
    pub resource: String,
    pub capacity: f64,
    /// New capacity minus the previous one (q of the paper, signed).
    pub delta: f64,
}

/// A location named by a goal: a known object, or coordinates that become a new location object.
#[derive(Debug, Clone, PartialEq)]
pub struct GoalLocation {
    pub name: String,
    /// True when no known object lies at these coordinates: the executive creates the object.
    pub new: bool,
    pub at: Enu,
    pub lat: f64,
    pub lon: f64,
}

/// What a goal asks for: the kind of the uploaded item it comes from. The config's `[mapping.goals]` says
/// which attribute of the domain each kind becomes, under the names [`GoalKind::key`] gives.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Deserialize, serde::Serialize,
)]
pub enum GoalKind {
    /// Be at a position (waypoint and loiter items).
    #[serde(rename = "waypoint")]
    BeAt,
    #[serde(rename = "picture")]
    PictureOf,
    #[serde(rename = "sample")]
    SampleAt,
    #[serde(rename = "survey")]
    SurveyOf,
    /// Be back home (return-to-launch items): the mapping's home object.
    #[serde(rename = "return_home")]
    ReturnHome,
}

impl GoalKind {
    pub const ALL: [GoalKind; 5] = [
        GoalKind::BeAt,
        GoalKind::PictureOf,
        GoalKind::SampleAt,
        GoalKind::SurveyOf,
        GoalKind::ReturnHome,
    ];

    /// The proposition's name in texts to ground stations (`g7 accepted: picture_of(L7)`).
    pub fn predicate(&self) -> &'static str {
        match self {
            GoalKind::BeAt => "at",
            GoalKind::PictureOf => "picture_of",
            GoalKind::SampleAt => "sampled",
            GoalKind::SurveyOf => "surveyed",
            GoalKind::ReturnHome => "at",
        }
    }

    /// Its key in the config's `[mapping.goals]`.
    pub fn key(&self) -> &'static str {
        match self {
            GoalKind::BeAt => "waypoint",
            GoalKind::PictureOf => "picture",
            GoalKind::SampleAt => "sample",
            GoalKind::SurveyOf => "survey",
            GoalKind::ReturnHome => "return_home",
        }
    }
}

/// A goal request (seed 1 §3.3): priority, duration interval I^d, start window I^g, d_achiev.
/// Times are seconds relative to the plan's origin.
#[derive(Debug, Clone, PartialEq)]
pub struct GoalRequest {
    pub name: String,
    pub kind: GoalKind,
    /// The goal proposition as text, e.g. `picture_of(L7)`.
    pub proposition: String,
    pub location: Option<GoalLocation>,
    pub priority: u32,
    /// I^g: window for the goal's start timepoint, seconds after origin.
    pub start_window_s: (f64, f64),
    /// I^d: how long the proposition must hold, seconds.
    pub duration_s: (f64, f64),
    /// Estimated minimal achievement duration.
    pub d_achiev_s: f64,
}

/// The decision about one goal of an upload.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GoalVerdict {
    Accepted,
    Rejected(String),
    /// Passed the acceptance test; its bounded insertion into the plan (plan repair) is still going on when
    /// the upload is answered: `Accepted` or `Rejected` follows.
    Inserting,
    /// An accepted goal was achieved (told later, so the goal list a ground station reads back is true).
    Achieved,
    /// An accepted or waiting goal was withdrawn by its ground station (MISSION_CLEAR_ALL, or a new list
    /// without it): why.
    Cancelled(String),
}

impl GoalVerdict {
    /// Whether this is the goal's last word (not [`GoalVerdict::Inserting`]).
    pub fn is_final(&self) -> bool {
        !matches!(self, GoalVerdict::Inserting)
    }
}
