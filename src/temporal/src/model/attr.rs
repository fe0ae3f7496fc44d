//! Attributes (seed 1 §2.2): logical attributes (state variables) and resource attributes.

use serde::Serialize;

use super::{ObjectId, TypeId};

/// A ground value of a logical attribute: an object, or IxTeT's `+oo` ("unknown / in transit", as in
/// `event(AT_ROBOT_X(): (?xi, +oo), st)`), which only holds between a start and an end event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub enum Value {
    Obj(ObjectId),
    Unknown,
}

/// A logical attribute: a multi-valued function of time, `name(?p1: T1, ...): V`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LogicalAttr {
    pub name: String,
    /// Parameter names (for printing) and types, in order.
    pub params: Vec<(String, TypeId)>,
    /// The type of its values (`+oo` is always allowed besides).
    pub value_type: TypeId,
    /// Where it is declared in its domain file (1-based), for messages about it; `None` when built in code.
    pub line: Option<usize>,
}

impl LogicalAttr {
    /// Number of parameters.
    pub fn arity(&self) -> usize {
        self.params.len()
    }
}

/// The tolerance on a reservoir's level, one for the planner's envelope and the checker: a level may exceed
/// its bound by this much (rounding), else plans the planner calls safe are refused for rounding alone
/// (3.0000000477 > 3).
pub const LEVEL_TOLERANCE: f64 = 1e-6;

/// Unary or reservoir (seed 1 §2.2: borrowings over an interval, consumptions and productions at an instant).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ResourceKind {
    /// At most one `use` at a time (capacity 1); no consume/produce.
    Unary,
    /// A level in `[0, capacity]`: `use` borrows over an interval, `consume` / `produce` change it at an instant.
    Reservoir,
}

/// A resource attribute (`camera`, `storage`, `battery`). Resources are ground (no parameters); the problem
/// gives the initial level and the expected availability profile ([`crate::model::ResourceSetup`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResourceAttr {
    pub name: String,
    pub kind: ResourceKind,
    /// Default capacity (1 for unary); a problem may override it or give a profile over time.
    pub capacity: f64,
    /// Where it is declared in its domain file (1-based); `None` when built in code.
    pub line: Option<usize>,
}
