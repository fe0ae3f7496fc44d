//! Goals (seed 1 §3.3 "Goal request", footnote 5; seed 2's Φ_g = Φ_ge ∪ Φ_gi).

use serde::Serialize;

use super::{AttrId, ObjectId, Time, TimeInterval, Value};

/// Who wants the goal (seed 2): an operator (external, Φ_ge, dispatched proactively) or the mission itself
/// (internal, Φ_gi, e.g. "back at the surface by 20:00", deferred).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum GoalOrigin {
    External,
    Internal,
}

/// A goal: the grounded proposition `hold(attr(args): value, (st^g, et^g))` with its constraints.
/// Instantaneous goals have `duration = [0, 0]`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Goal {
    /// `g1` ... (unique within a problem).
    pub name: String,
    pub kind: GoalOrigin,
    /// Higher is more important; complete replanning rejects the lowest first.
    pub priority: i64,
    pub attr: AttrId,
    pub args: Vec<ObjectId>,
    pub value: Value,
    /// I^g: the window of `st^g − origin`.
    pub start_window: TimeInterval,
    /// I^d: the window of `et^g − st^g`.
    pub duration: TimeInterval,
    /// d_achiev: an estimate of the minimal time needed to achieve it (`st^g − origin ≥ t + d_achiev`).
    pub achieve: Time,
}

impl Goal {
    /// True for `duration = [0, 0]`: the value must hold at one instant.
    pub fn is_instantaneous(&self) -> bool {
        self.duration.min_ms() == Some(0) && self.duration.max_ms() == Some(0)
    }
}
