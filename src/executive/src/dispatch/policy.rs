//! Dispatch policies: when, within its start window `[lb, ub]`, an action is started.
//!
//! Each policy gives the start timepoint an execution time `t_exec`. [`DispatchPolicy::decide`] is the tick
//! form of seed 1 §3.5 and seed 2's Algorithm 1 (executed in the current cycle when `t_exec` falls before the
//! end of the cycle `[now, now + ts]`, at `max(now, t_exec)`), derived from `t_exec`; the benchmarks'
//! dispatcher uses it. The executive itself wakes at `t_exec` and executes then (src/executive/src/exec/act.rs,
//! docs/departures.md). Whether the timepoint is executable (Definition 2: its
//! predecessors executed, `now ∈ [lb, ub]`) is the executive's question, asked before this one.
//!
//! - `earliest`: IxTeT-eXeC's rule for start timepoints, `t_exec = lb`.
//! - `latest`: every start deferred to its latest start minus one timestep, `t_exec = ub − ts` (the margin of
//!   seed 1's late-preemptive ends), never below `lb`; never started while `ub` is infinite.
//! - `goal-driven`: seed 2's Algorithm 1 ([`GoalDriven::decide`]), the goal support answered by Algorithm 2
//!   or by the incremental marking of Algorithms 3–8 ([`SupportForm`]).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use mavtempo_temporal::stn::{Time, INF};

/// The window `[lb, ub]` of a start timepoint (relative to the origin; `ub >= INF` is unbounded).
#[derive(Copy, Clone, Eq, PartialEq, Debug, Serialize)]
pub struct StartWindow {
    pub lb: Time,
    pub ub: Time,
}

impl StartWindow {
    fn finite_ub(self) -> Option<Time> {
        (self.ub < INF).then_some(self.ub)
    }
}

/// The current cycle: it started at `now` and ends at `end` (`now + ts`, the tick's upper bound).
#[derive(Copy, Clone, Eq, PartialEq, Debug, Serialize)]
pub struct Tick {
    pub now: Time,
    pub end: Time,
}

impl Tick {
    pub fn new(now: Time, ts: Time) -> Self {
        Tick {
            now,
            end: now.saturating_add(ts),
        }
    }

    pub fn ts(self) -> Time {
        self.end - self.now
    }
}

/// What to do with a start timepoint this cycle.
#[derive(Copy, Clone, Eq, PartialEq, Debug, Serialize)]
pub enum Decision {
    /// Start the action at `at` (within this cycle).
    Dispatch { at: Time },
    /// Not this cycle; `t_exec` is when it would be (`None`: never, as things stand).
    Defer { t_exec: Option<Time> },
}

impl Decision {
    pub fn is_dispatch(self) -> bool {
        matches!(self, Decision::Dispatch { .. })
    }
}

/// A dispatch policy. `supports_external_goal` is only asked for when [`Self::needs_goal_support`].
pub trait DispatchPolicy: Send + Sync + fmt::Debug {
    fn name(&self) -> &'static str;

    /// Whether [`Self::decide`] looks at `supports_external_goal` (so the caller can skip computing it).
    fn needs_goal_support(&self) -> bool {
        false
    }

    /// The execution time of a start timepoint with this window (`None`: never).
    fn t_exec(&self, window: StartWindow, ts: Time, supports_external_goal: bool) -> Option<Time>;

    /// The decision for this cycle (seed 1 §3.5: executed when `t_exec` falls before the end of the cycle).
    fn decide(&self, window: StartWindow, tick: Tick, supports_external_goal: bool) -> Decision {
        match self.t_exec(window, tick.ts(), supports_external_goal) {
            Some(t) if t <= tick.end => Decision::Dispatch {
                at: t.max(tick.now),
            },
            t_exec => Decision::Defer { t_exec },
        }
    }
}

/// IxTeT-eXeC's default: start as soon as possible.
#[derive(Copy, Clone, Debug, Default)]
pub struct Earliest;

impl DispatchPolicy for Earliest {
    fn name(&self) -> &'static str {
        "earliest"
    }

    fn t_exec(&self, window: StartWindow, _ts: Time, _: bool) -> Option<Time> {
        Some(window.lb)
    }
}

/// Everything deferred to its latest start minus one timestep.
#[derive(Copy, Clone, Debug, Default)]
pub struct Latest;

impl DispatchPolicy for Latest {
    fn name(&self) -> &'static str {
        "latest"
    }

    fn t_exec(&self, window: StartWindow, ts: Time, _: bool) -> Option<Time> {
        window
            .finite_ub()
            .map(|ub| ub.saturating_sub(ts).max(window.lb))
    }
}

/// Seed 2's goal-driven dispatching: proactive for actions that support an external goal, deferred
/// otherwise.
#[derive(Copy, Clone, Debug, Default)]
pub struct GoalDriven;

impl DispatchPolicy for GoalDriven {
    fn name(&self) -> &'static str {
        "goal-driven"
    }

    fn needs_goal_support(&self) -> bool {
        true
    }

    /// Algorithm 1 as an execution time: an action supporting an external goal at `lb`; any other when its
    /// start upper bound falls within the current tick `[now, now + ts]`, i.e. from `ub − ts` on (never
    /// before `lb`, never while `ub` is infinite).
    fn t_exec(&self, window: StartWindow, ts: Time, supports_external_goal: bool) -> Option<Time> {
        if supports_external_goal {
            Some(window.lb)
        } else {
            window
                .finite_ub()
                .map(|ub| ub.saturating_sub(ts).max(window.lb))
        }
    }

    /// Algorithm 1 (DispatchToken) on the current tick: dispatch if the token supports an external goal;
    /// otherwise only when its start upper bound is at most the upper bound of the tick. Dispatched tokens
    /// start at the beginning of the tick, or when their start window opens within it.
    fn decide(&self, window: StartWindow, tick: Tick, supports_external_goal: bool) -> Decision {
        let due = if supports_external_goal {
            window.lb <= tick.end
        } else {
            window.ub < INF && window.ub <= tick.end
        };
        if due {
            Decision::Dispatch {
                at: window.lb.max(tick.now),
            }
        } else {
            Decision::Defer {
                t_exec: self.t_exec(window, tick.ts(), supports_external_goal),
            }
        }
    }
}

/// How the goal-driven policy learns whether an action supports an external goal.
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SupportForm {
    /// Algorithm 2 at each decision.
    Search,
    /// Algorithms 3–8: a lookup in `List_goals` kept during planning (the paper's preferred form).
    Marking,
}

/// A policy as named in config files and on the command line: `earliest | latest | goal-driven`
/// (`goal-driven` uses the marking; `goal-driven:search` / `goal-driven:marking` choose the form).
#[derive(Copy, Clone, Eq, PartialEq, Hash, Debug, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum PolicyKind {
    Earliest,
    Latest,
    GoalDriven(SupportForm),
}

#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("unknown dispatch policy {0:?}: expected earliest, latest, goal-driven, goal-driven:search or goal-driven:marking")]
pub struct UnknownPolicy(pub String);

impl FromStr for PolicyKind {
    type Err = UnknownPolicy;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim() {
            "earliest" => Ok(PolicyKind::Earliest),
            "latest" => Ok(PolicyKind::Latest),
            "goal-driven" | "goal-driven:marking" => {
                Ok(PolicyKind::GoalDriven(SupportForm::Marking))
            }
            "goal-driven:search" => Ok(PolicyKind::GoalDriven(SupportForm::Search)),
            other => Err(UnknownPolicy(other.to_string())),
        }
    }
}

impl TryFrom<String> for PolicyKind {
    type Error = UnknownPolicy;

    fn try_from(s: String) -> Result<Self, Self::Error> {
        s.parse()
    }
}

impl From<PolicyKind> for String {
    fn from(k: PolicyKind) -> String {
        k.to_string()
    }
}

impl fmt::Display for PolicyKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            PolicyKind::Earliest => "earliest",
            PolicyKind::Latest => "latest",
            PolicyKind::GoalDriven(SupportForm::Marking) => "goal-driven:marking",
            PolicyKind::GoalDriven(SupportForm::Search) => "goal-driven:search",
        })
    }
}

impl Default for PolicyKind {
    /// The product's behaviour: seed 2's goal-driven dispatch, its support kept by the incremental marking
    /// (`earliest`, IxTeT-eXeC's own rule, and `latest` remain options).
    fn default() -> Self {
        PolicyKind::GoalDriven(SupportForm::Marking)
    }
}

impl PolicyKind {
    pub fn policy(self) -> Box<dyn DispatchPolicy> {
        match self {
            PolicyKind::Earliest => Box::new(Earliest),
            PolicyKind::Latest => Box::new(Latest),
            PolicyKind::GoalDriven(_) => Box::new(GoalDriven),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TS: Time = 1_000;

    fn w(lb: Time, ub: Time) -> StartWindow {
        StartWindow { lb, ub }
    }

    fn dispatch(at: Time) -> Decision {
        Decision::Dispatch { at }
    }

    fn defer(t_exec: Option<Time>) -> Decision {
        Decision::Defer { t_exec }
    }

    /// Each case: the start's window, the tick, whether it supports an external goal, the decision expected.
    fn check(p: &dyn DispatchPolicy, cases: &[(StartWindow, Tick, bool, Decision)]) {
        for &(window, tick, supports, expected) in cases {
            assert_eq!(
                p.decide(window, tick, supports),
                expected,
                "{p:?}: window {window:?}, {tick:?}, supports an external goal: {supports}"
            );
        }
    }

    #[test]
    fn earliest_starts_at_lb() {
        let tick = Tick::new(10_000, TS);
        check(
            &Earliest,
            &[
                (w(5_000, 60_000), tick, false, dispatch(10_000)),
                (w(10_500, INF), tick, false, dispatch(10_500)),
                (w(11_001, INF), tick, true, defer(Some(11_001))),
            ],
        );
    }

    #[test]
    fn latest_waits_for_ub_minus_ts_and_never_starts_an_unbounded_window() {
        let at = |now| Tick::new(now, TS);
        check(
            &Latest,
            &[
                (w(0, 60_000), at(57_999), true, defer(Some(59_000))),
                (w(0, 60_000), at(58_500), false, dispatch(59_000)),
                // A window narrower than ts starts at lb.
                (w(59_500, 60_000), at(59_000), false, dispatch(59_500)),
                (w(0, INF), at(1 << 40), false, defer(None)),
            ],
        );
    }

    #[test]
    fn goal_driven_is_proactive_only_for_external_goal_support() {
        let tick = Tick::new(10_000, TS);
        check(
            &GoalDriven,
            &[
                (w(0, 60_000), tick, true, dispatch(10_000)),
                (w(0, 60_000), tick, false, defer(Some(59_000))),
                // Alg. 1's second branch: start ub within the current tick → dispatched in this tick.
                (w(0, 10_800), tick, false, dispatch(10_000)),
                (w(0, 11_000), tick, false, dispatch(10_000)),
                (w(0, 11_001), tick, false, defer(Some(10_001))),
                (w(0, INF), Tick::new(1 << 40, TS), false, defer(None)),
                // Proactive, but not before its window opens.
                (w(20_000, 60_000), tick, true, defer(Some(20_000))),
                (w(10_500, 60_000), tick, true, dispatch(10_500)),
            ],
        );
    }

    /// Algorithm 1 on ticks and its execution time agree: for a start whose window is open (the executive
    /// only asks about executable timepoints, Definition 2: `lb <= now`), the token is dispatched in the tick
    /// exactly when `t_exec <= now` — the executive's rule, which wakes up at `t_exec`.
    #[test]
    fn algorithm_1_agrees_with_its_execution_time() {
        for lb in (0..6).map(|i| i * 700) {
            for ub in [lb, lb + 300, lb + 1_000, lb + 5_000, INF] {
                for now in (0..12).map(|i| i * 450).filter(|&n| n >= lb) {
                    for s in [false, true] {
                        let tick = Tick::new(now, TS);
                        let te = GoalDriven.t_exec(w(lb, ub), TS, s);
                        assert_eq!(
                            GoalDriven.decide(w(lb, ub), tick, s).is_dispatch(),
                            te.is_some_and(|t| t <= now),
                            "lb {lb} ub {ub} now {now} supports {s}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn policy_names_parse_and_round_trip() {
        for s in [
            "earliest",
            "latest",
            "goal-driven:search",
            "goal-driven:marking",
        ] {
            let k: PolicyKind = s.parse().unwrap();
            assert_eq!(k.to_string(), s);
        }
        assert_eq!(
            "goal-driven".parse::<PolicyKind>(),
            Ok(PolicyKind::GoalDriven(SupportForm::Marking))
        );
        let err = "eager".parse::<PolicyKind>().unwrap_err();
        assert!(err.to_string().contains("eager"), "{err}");
        #[derive(Deserialize)]
        struct Cfg {
            dispatch: PolicyKind,
        }
        let cfg: Cfg = toml::from_str("dispatch = \"latest\"").unwrap();
        assert_eq!(cfg.dispatch, PolicyKind::Latest);
        assert!(toml::from_str::<Cfg>("dispatch = \"soon\"").is_err());
    }
}
