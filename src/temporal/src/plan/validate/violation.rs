//! What the checker can find wrong with a plan: one typed, human-readable violation per fault.

use thiserror::Error;

use crate::model::Time;

/// One fault of a plan. Names are the plan's (`a3 (move)`, `g2`, `a3.st`); times are ms after the origin.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Violation {
    /// The solution does not fit the domain/problem (unknown task, wrong arity, dangling index ...).
    #[error("malformed plan: {0}")]
    Malformed(String),
    /// The plan's temporal network has no solution.
    #[error("inconsistent temporal network: negative cycle through {cycle}")]
    InconsistentNetwork { cycle: String },
    /// A reported window admits times the network forbids.
    #[error(
        "timepoint {tp}: reported window {reported} is not within the network's bounds {computed}"
    )]
    WindowOutsideNetwork {
        tp: String,
        reported: String,
        computed: String,
    },
    /// The reported windows, taken together with the network, admit no schedule.
    #[error("the reported timepoint windows are jointly inconsistent with the network (cycle through {cycle})")]
    InconsistentWindows { cycle: String },
    /// An action timepoint after the problem's horizon.
    #[error("timepoint {tp} at {time} ms is after the horizon {horizon} ms")]
    AfterHorizon {
        tp: String,
        time: Time,
        horizon: Time,
    },
    /// A temporal constraint of the task template is violated by the schedule (a duration ...).
    #[error("{action}: {to} − {from} = {value} ms violates the task's constraint {interval}")]
    TaskConstraint {
        action: String,
        from: String,
        to: String,
        value: Time,
        interval: String,
    },
    /// A binding constraint (task template or plan ≠) cannot be satisfied.
    #[error("{action}: binding constraint violated: {reason}")]
    Binding { action: String, reason: String },
    /// A numeric constraint cannot be satisfied within the reported bounds at the schedule.
    #[error("{action}: numeric constraint unsatisfiable: {reason}")]
    Numeric {
        action: String,
        reason: NumericFault,
    },
    /// An event's `from` value is not the attribute's value just before it.
    #[error("{action}: event on {instance} at {time} ms requires the value {expected} but it is {actual}")]
    EventFrom {
        action: String,
        instance: String,
        time: Time,
        expected: String,
        actual: String,
    },
    /// Two changes of one attribute instance at the same instant (their order is undefined).
    #[error("{instance}: simultaneous changes at {time} ms by {first} and {second}")]
    SimultaneousEvents {
        instance: String,
        time: Time,
        first: String,
        second: String,
    },
    /// A hold of an action does not hold over its interval.
    #[error("{action}: hold {lapse}")]
    HoldBroken { action: String, lapse: Lapse },
    /// A causal link's value does not persist over its protected interval.
    #[error("causal link {link}: {lapse}")]
    LinkBroken { link: String, lapse: Lapse },
    /// A causal link does not match its establisher or consumer.
    #[error("causal link {link}: {reason}")]
    LinkMismatch { link: String, reason: LinkFault },
    /// A goal marked achieved whose proposition does not hold over its window.
    #[error("goal {goal}: {lapse}")]
    GoalBroken { goal: String, lapse: Lapse },
    /// st^g − origin outside I^g (a missed deadline or a too-early start).
    #[error("goal {goal}: start at {start} ms is outside its window I^g = {window}")]
    GoalWindow {
        goal: String,
        start: Time,
        window: String,
    },
    /// et^g − st^g outside I^d.
    #[error("goal {goal}: duration {duration} ms is outside I^d = {interval}")]
    GoalDuration {
        goal: String,
        duration: Time,
        interval: String,
    },
    /// A goal marked achieved without timepoints or without a supporting causal link.
    #[error("goal {goal}: marked achieved but {reason}")]
    GoalUnsupported { goal: String, reason: String },
    /// A reservoir's worst-case level drops below zero.
    #[error("resource {resource}: worst-case level {level} < 0 at {time} ms (after {culprit})")]
    ResourceBelowZero {
        resource: String,
        time: Time,
        level: f64,
        culprit: String,
    },
    /// A reservoir's worst-case level exceeds the capacity available then.
    #[error("resource {resource}: worst-case level {level} > capacity {capacity} at {time} ms (after {culprit})")]
    ResourceOverCapacity {
        resource: String,
        time: Time,
        level: f64,
        capacity: f64,
        culprit: String,
    },
    /// Two uses of a unary resource overlap.
    #[error("unary resource {resource}: {first} and {second} overlap at {time} ms")]
    UnaryOverlap {
        resource: String,
        first: String,
        second: String,
        time: Time,
    },
    /// A use of a unary resource while its availability profile says it is unavailable.
    #[error(
        "unary resource {resource}: {action} uses it at {time} ms while its capacity is {capacity}"
    )]
    ResourceUnavailable {
        resource: String,
        action: String,
        time: Time,
        capacity: f64,
    },
}

/// Why an action's numeric variables have no values (names are the task's, `?dist`).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NumericFault {
    #[error("{var} has an empty domain: declared ∩ reported = [{lo}, {hi}]")]
    EmptyDomain { var: String, lo: f64, hi: f64 },
    #[error("{var} = distance({from}, {to}): a location without coordinates")]
    NoCoordinates {
        var: String,
        from: String,
        to: String,
    },
    #[error("unknown numeric variable #{0}")]
    UnknownVariable(u32),
    /// The value the schedule or the instantiation fixes (`what`: the scheduled duration, the distance).
    #[error("{var} = {value} ({what}) is outside its bounds [{lo}, {hi}]")]
    OutOfBounds {
        var: String,
        value: f64,
        what: &'static str,
        lo: f64,
        hi: f64,
    },
    #[error("{constraint} has no solution within the bounds {domains}")]
    NoSolution { constraint: String, domains: String },
}

/// How a causal link disagrees with its establisher or consumer (`role`: which of them).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LinkFault {
    #[error("its proposition {instance} = {value} differs from its {role}'s {role_instance} = {role_value}")]
    Proposition {
        instance: String,
        value: String,
        role: &'static str,
        role_instance: String,
        role_value: String,
    },
    #[error("its interval bound {tp} is not its {role}'s timepoint")]
    NotAtBound { tp: String, role: &'static str },
    #[error("it starts at {start} ms, not at the exogenous change's {change} ms")]
    NotAtExogenousChange { start: Time, change: Time },
    #[error("unknown establisher")]
    UnknownEstablisher,
    #[error("unknown consumer")]
    UnknownConsumer,
    #[error("its interval bound {tp} is not the end of the {what} it supports")]
    NotAtSupportedEnd { tp: String, what: &'static str },
    /// Footnote 3 of seed 1: the establisher may not start after what it supports.
    #[error("its establisher at {from} ms comes after the start of the {what} it supports at {start} ms")]
    EstablisherAfter {
        from: Time,
        what: &'static str,
        start: Time,
    },
}

/// A proposition that does not persist: `instance = value` over `[from, to]` fails at `time`.
#[derive(Debug, Clone, PartialEq)]
pub struct Lapse {
    /// `AT_ROBOT()`.
    pub instance: String,
    pub value: String,
    pub from: Time,
    pub to: Time,
    /// The first time it fails, and the value then.
    pub time: Time,
    pub actual: String,
}

impl std::fmt::Display for Lapse {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} = {} over [{}, {}] ms is broken at {} ms (value {})",
            self.instance, self.value, self.from, self.to, self.time, self.actual
        )
    }
}

/// A rejected plan: every violation found.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("plan rejected with {} violation(s): {}", violations.len(), summary(violations))]
pub struct Rejected {
    pub violations: Vec<Violation>,
}

fn summary(v: &[Violation]) -> String {
    v.iter()
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join("; ")
}
