//! The world model shared by the planner, the executive and the ground-station side: plain data, no search.
//!
//! Seed 1 §2.2 (IxTeT): the world is a set of *attributes*. Logical attributes ([`LogicalAttr`]) are
//! multi-valued, possibly parametrised state variables (`robot_at()`, `picture(?l)`), piecewise constant over
//! time, changed by `event`s and asserted by `hold`s. Resource attributes ([`ResourceAttr`]) are unary or
//! reservoirs, borrowed (`use`), consumed or produced. Tasks ([`Task`]) are lifted action templates.
//! A [`Problem`] gives objects, the initial scenario Φ_0 (initial values and predicted exogenous changes),
//! resource levels and availability profiles, a horizon and the goals Φ_g = Φ_ge ∪ Φ_gi ([`Goal`]).
//!
//! Time is integer milliseconds ([`Time`]) relative to the problem's origin (its start). Numeric variables
//! are `f64`; a numeric variable tied to timepoints (`?duration = et - st`) is measured in **seconds**.
//! Names are kept everywhere for printing; every reference is an index newtype ([`AttrId`], [`TaskId`] ...)
//! and [`Domain`] / [`Problem`] offer name → index lookups.

mod attr;
mod display;
mod domain;
mod geo;
mod goal;
mod ids;
mod interval;
mod problem;
mod task;
mod types;

pub use attr::{LogicalAttr, ResourceAttr, ResourceKind, Value, LEVEL_TOLERANCE};
pub use display::interval_string;
pub use domain::Domain;
pub use geo::{GeoPoint, Position};
pub use goal::{Goal, GoalOrigin};
pub use ids::{AttrId, GoalId, NumVarId, ObjectId, ResourceId, SymVarId, TaskId, TpId, TypeId};
pub use interval::{show_bounds, Bound, Interval, NumInterval, TimeInterval};
pub use problem::{
    combinations, DefaultFact, Fact, LegLimits, Legs, Problem, ResourceSetup, TimedFact,
};
pub use task::{
    Binding, Event, Hold, NumConstraint, NumTerm, NumVar, Preemption, ResourceUsage, SymVar, Task,
    TemporalConstraint, Term, UsageKind,
};
pub use types::{Object, Type, TypeKind};

/// A date or a duration in integer milliseconds: the temporal network's one time type. Dates are relative to
/// the problem's origin (its start, timepoint 0).
pub use crate::stn::Time;

/// Milliseconds per second: numeric variables bound to durations are in seconds.
pub const MS_PER_S: Time = 1_000;
