//! What a complete replanning (seed 1 §3.6) leaves in the mission report: its attempts, how each ended,
//! the goals kept and rejected. Data only: [`super::replan`] fills it.

use serde::{Deserialize, Serialize};

pub use super::outcome::AttemptEnd;
use super::outcome::{AbortReason, FateReason};
use mavtempo_temporal::model::Time;

/// How a complete replanning ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ReplanOutcome {
    /// A new plan was adopted.
    NewPlan,
    /// No goal was left to plan for.
    NoGoals,
    /// No problem could be extracted.
    Error,
}

impl std::fmt::Display for ReplanOutcome {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ReplanOutcome::NewPlan => "new plan",
            ReplanOutcome::NoGoals => "no goal left",
            ReplanOutcome::Error => "error",
        })
    }
}

/// One attempt of a complete replanning.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct AttemptRecord {
    pub attempt: u32,
    /// The goals it planned for.
    pub goals: Vec<String>,
    pub steps: u64,
    pub end: AttemptEnd,
    /// Why a plan it found was not adopted (it needs a banned action; found after T_end).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub not_adopted: Option<String>,
}

/// A goal rejected by a complete replanning (§3.6), and why.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReplanRejection {
    pub goal: String,
    #[serde(serialize_with = "super::outcome::text")]
    pub reason: FateReason,
}

/// One complete replanning, as the `--report` JSON keeps it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReplanRecord {
    /// Mission time when it started and ended, ms since origin.
    pub time_ms: Time,
    pub end_ms: Time,
    /// What aborted execution.
    #[serde(serialize_with = "super::outcome::text")]
    pub abort: AbortReason,
    pub attempts: Vec<AttemptRecord>,
    /// Planning steps of the whole replanning: its attempts and the single-goal searches.
    pub steps: u64,
    pub outcome: ReplanOutcome,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The goals of the new plan.
    pub kept: Vec<String>,
    pub rejected: Vec<ReplanRejection>,
}
