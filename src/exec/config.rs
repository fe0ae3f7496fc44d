//! The executive's parameters (seed 1 §3.2, §3.6): the timestep ts, the share μ of it given to plan repair,
//! and the slack d kept at the end of a complete replanning.

use serde::Deserialize;

use crate::dispatch::PolicyKind;
use crate::model::Time;

#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExecConfig {
    /// ts: the maximum duration of a cycle, ms (seed 1 §4: 1.3 s; §5: 2 s).
    #[serde(default = "default_ts")]
    pub timestep_ms: Time,
    /// μ: the share of ts allotted to plan repair (seed 1: 0.6).
    #[serde(default = "default_mu")]
    pub repair_share: f64,
    /// d: slack saved at the end of complete replanning for the cycle's initialisation, ms.
    #[serde(default = "default_slack")]
    pub replan_slack_ms: Time,
    /// Deterministic runs (tests, demo): plan repair and replanning budgets in planning steps instead of
    /// wall-clock time (μ·ts of steps per cycle).
    #[serde(default)]
    pub repair_max_steps: Option<u64>,
    /// When starts are dispatched: `earliest` (IxTeT-eXeC), `latest`, `goal-driven` (seed 2).
    #[serde(default)]
    pub dispatch: PolicyKind,
    /// k: an action instance failing the same way this many times in a row is banned and the goals that
    /// depend on it are rejected (src/exec/failures.rs).
    #[serde(default = "default_same_failures")]
    pub same_failure_limit: u32,
    /// Plan repairs plus complete replannings allowed within any minute of mission time; past it a goal is
    /// rejected with the count as the reason.
    #[serde(default = "default_changes_per_min")]
    pub max_plan_changes_per_min: u32,
}

fn default_ts() -> Time {
    2_000
}
fn default_mu() -> f64 {
    0.6
}
fn default_slack() -> Time {
    2_000
}
fn default_same_failures() -> u32 {
    3
}
fn default_changes_per_min() -> u32 {
    12
}

impl Default for ExecConfig {
    fn default() -> Self {
        ExecConfig {
            timestep_ms: default_ts(),
            repair_share: default_mu(),
            replan_slack_ms: default_slack(),
            repair_max_steps: None,
            dispatch: PolicyKind::default(),
            same_failure_limit: default_same_failures(),
            max_plan_changes_per_min: default_changes_per_min(),
        }
    }
}

/// A bad `[exec]` table.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ConfigError {
    #[error("exec.timestep_ms must be positive, got {0}")]
    Timestep(Time),
    #[error("exec.repair_share must be in ]0, 1], got {0}")]
    Share(f64),
    #[error("exec.replan_slack_ms must be >= 0, got {0}")]
    Slack(Time),
    #[error("exec.{0} must be at least 1")]
    Positive(&'static str),
}

impl ExecConfig {
    pub fn validate(&self) -> Result<(), ConfigError> {
        if self.timestep_ms <= 0 {
            return Err(ConfigError::Timestep(self.timestep_ms));
        }
        if !(self.repair_share > 0.0 && self.repair_share <= 1.0) {
            return Err(ConfigError::Share(self.repair_share));
        }
        if self.replan_slack_ms < 0 {
            return Err(ConfigError::Slack(self.replan_slack_ms));
        }
        if self.same_failure_limit == 0 {
            return Err(ConfigError::Positive("same_failure_limit"));
        }
        if self.max_plan_changes_per_min == 0 {
            return Err(ConfigError::Positive("max_plan_changes_per_min"));
        }
        Ok(())
    }

    /// μ·ts: the plan repair budget of one cycle, ms.
    pub fn repair_budget_ms(&self) -> Time {
        (self.timestep_ms as f64 * self.repair_share) as Time
    }
}
