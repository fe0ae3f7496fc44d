//! The executive's parameters (seed 1 §3.2, §3.6): the timestep ts, the share μ of it given to plan repair,
//! and the slack d kept at the end of a complete replanning.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::dispatch::PolicyKind;
use mavtempo_temporal::model::Time;
use mavtempo_vehicle::config::{ConfigError as VehicleConfigError, VehicleConfig};

/// A key left out takes its value from [`ExecConfig::default`], the one place the defaults are written.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExecConfig {
    /// ts: the maximum duration of a cycle, ms (seed 1 §4: 1.3 s; §5: 2 s).
    pub timestep_ms: Time,
    /// μ: the share of ts allotted to plan repair (seed 1: 0.6).
    pub repair_share: f64,
    /// d: slack saved at the end of complete replanning for the cycle's initialisation, ms.
    pub replan_slack_ms: Time,
    /// Deterministic runs (tests, demo): plan repair and replanning budgets in planning steps instead of
    /// mission time (μ·n steps per cycle; a replanning attempt at most 40·n steps).
    pub repair_max_steps: Option<u64>,
    /// Hard cap on the plan repair steps of one cycle, whatever the clock does: the μ·ts deadline is in
    /// mission time, which does not move while a stepped simulator or a manual clock waits for the cycle.
    pub repair_cycle_max_steps: u64,
    /// Planning steps one plan repair may take over all its cycles (its tree restarted or not) before it
    /// is given up: execution is aborted and a complete replanning follows. A repair that never converges
    /// would otherwise go on for the rest of the mission.
    pub repair_episode_max_steps: u64,
    /// Hard cap on the planning steps of the first complete replanning attempt (§3.6), for the same reason:
    /// past it the attempt ends as if the time limit l were reached. Each further attempt (one goal fewer)
    /// gets half the steps of the one before, down to a sixteenth: a whole replanning stays within about
    /// twice this (plus a sixteenth per further goal dropped), and so does its memory.
    pub replan_max_steps: u64,
    /// Wall-time bound of one cycle's plan repair or goal insertion, ms, whatever a step costs (a stepped
    /// simulator's clock does not move while the executive plans, and a step's cost grows with the plan).
    pub cycle_max_wall_ms: u64,
    /// Wall-time bound of a whole complete replanning (its single-goal searches and attempts, each attempt
    /// at most half of what is left), ms: past it the replanning ends as if its step budget were spent.
    pub replan_max_wall_ms: u64,
    /// Memory bound of a replanning attempt: its search stops once its plan holds this many actions (a
    /// branch that adds action after action costs more with each step and never ends on its own).
    pub plan_max_actions: usize,
    /// Cycles of plan repair (μ·ts, or μ·n steps, each) a new goal's insertion into the plan may take; past
    /// them the goal is rejected and the plan stays as it was (src/executive/src/exec/goal_insertion.rs).
    pub goal_insertion_cycles: u32,
    /// When starts are dispatched: `goal-driven` (seed 2, the default), `earliest` (IxTeT-eXeC), `latest`.
    pub dispatch: PolicyKind,
    /// k: an action instance failing the same way this many times in a row is banned and the goals that
    /// depend on it are rejected (src/executive/src/exec/failures.rs).
    pub same_failure_limit: u32,
    /// Plan repairs plus complete replannings allowed within any minute of mission time; past it a goal is
    /// rejected with the count as the reason.
    pub max_plan_changes_per_min: u32,
    /// `[exec.reserve]`: per resource, the largest fault (drop) the mission must absorb, e.g. `BATTERY =
    /// 20.0`. A plan that may leave less is said so (a warning in the trace) when it is adopted.
    pub reserve: std::collections::BTreeMap<String, f64>,
}

impl Default for ExecConfig {
    fn default() -> Self {
        ExecConfig {
            timestep_ms: 2_000,
            repair_share: 0.6,
            replan_slack_ms: 2_000,
            repair_max_steps: None,
            // A planning step costs tens of µs on a rover plan: 20,000 steps are about μ·ts at the default ts.
            repair_cycle_max_steps: 20_000,
            repair_episode_max_steps: 20_000,
            // An attempt's steps: generous for missions of a few dozen goals, bounded for a stepped simulator.
            replan_max_steps: 100_000,
            cycle_max_wall_ms: 2_000,
            replan_max_wall_ms: 20_000,
            // Ten times the largest shipped mission's plan.
            plan_max_actions: 500,
            goal_insertion_cycles: 3,
            dispatch: PolicyKind::default(),
            same_failure_limit: 3,
            max_plan_changes_per_min: 12,
            reserve: std::collections::BTreeMap::new(),
        }
    }
}

/// A bad `[exec]` table.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ExecConfigError {
    #[error("exec.timestep_ms must be in ]0, 3600000] (an hour), got {0}")]
    Timestep(Time),
    #[error("exec.repair_share must be in ]0, 1], got {0}")]
    Share(f64),
    #[error("exec.replan_slack_ms must be in [0, 3600000] (an hour), got {0}")]
    Slack(Time),
    #[error("exec.{0} must be at least 1")]
    Positive(&'static str),
    #[error("exec.{0} must be positive")]
    StepCap(&'static str),
    #[error("exec.reserve: each resource's fault size must be a finite number ≥ 0, got {0}")]
    Reserve(f64),
}

const HOUR_MS: Time = 3_600_000;

impl ExecConfigError {
    /// The key of `[exec]` the error is about.
    pub fn key(&self) -> &'static str {
        match self {
            ExecConfigError::Timestep(_) => "timestep_ms",
            ExecConfigError::Share(_) => "repair_share",
            ExecConfigError::Slack(_) => "replan_slack_ms",
            ExecConfigError::Positive(k) | ExecConfigError::StepCap(k) => k,
            ExecConfigError::Reserve(_) => "reserve",
        }
    }
}

impl ExecConfig {
    pub fn validate(&self) -> Result<(), ExecConfigError> {
        // An hour at most: a cycle or a slack past it is a typo, and huge values overflow time sums.
        if self.timestep_ms <= 0 || self.timestep_ms > HOUR_MS {
            return Err(ExecConfigError::Timestep(self.timestep_ms));
        }
        if !(self.repair_share > 0.0 && self.repair_share <= 1.0) {
            return Err(ExecConfigError::Share(self.repair_share));
        }
        if !(0..=HOUR_MS).contains(&self.replan_slack_ms) {
            return Err(ExecConfigError::Slack(self.replan_slack_ms));
        }
        if let Some((_, &v)) = self
            .reserve
            .iter()
            .find(|(_, v)| !(v.is_finite() && **v >= 0.0))
        {
            return Err(ExecConfigError::Reserve(v));
        }
        let counts = [
            ("same_failure_limit", self.same_failure_limit),
            ("goal_insertion_cycles", self.goal_insertion_cycles),
            ("max_plan_changes_per_min", self.max_plan_changes_per_min),
        ];
        if let Some((key, _)) = counts.into_iter().find(|&(_, n)| n == 0) {
            return Err(ExecConfigError::Positive(key));
        }
        let step_caps = [
            ("repair_cycle_max_steps", self.repair_cycle_max_steps),
            ("repair_episode_max_steps", self.repair_episode_max_steps),
            ("replan_max_steps", self.replan_max_steps),
            ("cycle_max_wall_ms", self.cycle_max_wall_ms),
            ("replan_max_wall_ms", self.replan_max_wall_ms),
            ("plan_max_actions", self.plan_max_actions as u64),
        ];
        if let Some((key, _)) = step_caps.into_iter().find(|&(_, n)| n == 0) {
            return Err(ExecConfigError::StepCap(key));
        }
        Ok(())
    }

    /// μ·ts: the plan repair budget of one cycle, ms.
    pub fn repair_budget_ms(&self) -> Time {
        (self.timestep_ms as f64 * self.repair_share) as Time
    }
}

/// What a vehicle configuration file is to the executive: its vehicle part and its `[exec]` table.
#[derive(Debug, Clone)]
pub struct MissionConfig {
    pub vehicle: VehicleConfig,
    pub exec: ExecConfig,
}

/// The keys of a configuration file the executive reads; the vehicle layer reads (and checks) the rest.
#[derive(Deserialize)]
struct ExecSection {
    exec: Option<ExecConfig>,
}

impl MissionConfig {
    pub fn load(path: &Path) -> Result<Self, VehicleConfigError> {
        let text = srctext::read(path)?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses and validates the whole file, the `[exec]` table too; `origin` names the source in errors.
    pub fn parse(text: &str, origin: &str) -> Result<Self, VehicleConfigError> {
        let vehicle = VehicleConfig::parse(text, origin)?;
        let exec = ExecConfig::parse_section(text, origin)?;
        Ok(MissionConfig { vehicle, exec })
    }
}

impl ExecConfig {
    /// The `[exec]` table of a configuration's text (the defaults when there is none), validated; errors at
    /// the table's lines.
    pub fn parse_section(text: &str, origin: &str) -> Result<Self, VehicleConfigError> {
        let at = |e| VehicleConfigError::At(Box::new(e));
        let section: ExecSection = srctext::toml_file::parse(origin, text).map_err(at)?;
        let exec = section.exec.unwrap_or_default();
        exec.validate().map_err(|e| {
            // The executive's messages name their key already.
            let key = format!("exec.{}", e.key());
            at(srctext::toml_file::at_key(
                origin,
                text,
                &key,
                e.to_string(),
            ))
        })?;
        Ok(exec)
    }

    /// `base` with the keys the configuration's `[exec]` table writes (validated as
    /// [`Self::parse_section`] does): how `demo` and `soak` keep their own defaults (seed 1's ts and μ,
    /// deterministic step budgets) and still honour a configuration's `[exec]`.
    pub fn over(base: &ExecConfig, text: &str, origin: &str) -> Result<Self, VehicleConfigError> {
        #[derive(Deserialize)]
        struct Raw {
            exec: Option<toml::Table>,
        }
        Self::parse_section(text, origin)?;
        let at = |e| VehicleConfigError::At(Box::new(e));
        let raw: Raw = srctext::toml_file::parse(origin, text).map_err(at)?;
        let Some(written) = raw.exec else {
            return Ok(base.clone());
        };
        let merge = || -> Result<ExecConfig, String> {
            let mut table = toml::Table::try_from(base).map_err(|e| e.to_string())?;
            table.extend(written);
            let cfg: ExecConfig = table.try_into().map_err(|e| e.to_string())?;
            cfg.validate()
                .map_err(|e| format!("exec.{}: {e}", e.key()))?;
            Ok(cfg)
        };
        merge().map_err(|reason| at(srctext::toml_file::at_key(origin, text, "exec", reason)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_exec_table_is_written_over_a_commands_own_defaults() {
        let base = ExecConfig {
            timestep_ms: 1_300,
            repair_max_steps: Some(300),
            ..ExecConfig::default()
        };
        let none = ExecConfig::over(&base, "[link]\naddress = \"x\"\n", "t").expect("no table");
        assert_eq!(none, base);
        let cfg = ExecConfig::over(&base, "[exec]\ntimestep_ms = 900\n", "t").expect("over");
        assert_eq!(cfg.timestep_ms, 900);
        assert_eq!(
            cfg.repair_max_steps,
            Some(300),
            "the base's own default kept"
        );
        assert!(ExecConfig::over(&base, "[exec]\nrepair_share = 2.0\n", "t").is_err());
    }

    #[test]
    fn step_caps_have_defaults_and_must_be_positive() {
        let cfg: ExecConfig = toml::from_str("timestep_ms = 1300").expect("parses");
        assert_eq!(cfg.repair_cycle_max_steps, 20_000);
        assert_eq!(cfg.replan_max_steps, 100_000);
        assert_eq!(cfg.validate(), Ok(()));
        let cfg: ExecConfig =
            toml::from_str("replan_max_steps = 0\nrepair_cycle_max_steps = 5").expect("parses");
        assert_eq!(cfg.repair_cycle_max_steps, 5);
        assert_eq!(
            cfg.validate(),
            Err(ExecConfigError::StepCap("replan_max_steps"))
        );
    }

    #[test]
    fn goal_insertion_cycles_default_to_3_and_must_be_positive() {
        let cfg: ExecConfig = toml::from_str("").expect("parses");
        assert_eq!(cfg.goal_insertion_cycles, 3);
        let cfg: ExecConfig = toml::from_str("goal_insertion_cycles = 0").expect("parses");
        assert_eq!(
            cfg.validate(),
            Err(ExecConfigError::Positive("goal_insertion_cycles"))
        );
    }

    #[test]
    fn each_count_and_step_cap_at_zero_is_refused_under_its_own_key() {
        let cases = [
            (
                "same_failure_limit",
                ExecConfigError::Positive("same_failure_limit"),
            ),
            (
                "goal_insertion_cycles",
                ExecConfigError::Positive("goal_insertion_cycles"),
            ),
            (
                "max_plan_changes_per_min",
                ExecConfigError::Positive("max_plan_changes_per_min"),
            ),
            (
                "repair_cycle_max_steps",
                ExecConfigError::StepCap("repair_cycle_max_steps"),
            ),
            (
                "repair_episode_max_steps",
                ExecConfigError::StepCap("repair_episode_max_steps"),
            ),
            (
                "replan_max_steps",
                ExecConfigError::StepCap("replan_max_steps"),
            ),
        ];
        for (key, expected) in cases {
            let cfg: ExecConfig = toml::from_str(&format!("{key} = 0")).expect("parses");
            assert_eq!(cfg.validate(), Err(expected), "{key} = 0");
        }
    }
}
