//! The domain's names the executive gives a vehicle meaning to, resolved to ids: which attribute a reported
//! position sets, which type new locations get, what an uploaded goal item becomes. Built from the vehicle
//! configuration's `[mapping]` once it is checked against the domain
//! ([`crate::config_check::check`]); the executive never guesses them from names.

use std::collections::BTreeMap;

use crate::model::{AttrId, ObjectId, TypeId};
use crate::GoalKind;

/// How a goal sits on its attribute.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GoalShape {
    /// `attr() = L`: the attribute has no parameters and is valued in the location type (be at L).
    ValueIsLocation,
    /// `attr(L) = true`: one location parameter, boolean (a picture of L, L sampled).
    LocationIsTrue,
}

/// The goal an uploaded item kind becomes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GoalTarget {
    pub attr: AttrId,
    pub shape: GoalShape,
}

/// The resolved `[mapping]`. Empty (the default): positions are ignored and uploaded goals rejected.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DomainMapping {
    /// The attribute a reported position sets.
    pub position: Option<AttrId>,
    /// The type of located objects; new locations get it.
    pub location_type: Option<TypeId>,
    /// The object a return-home goal means.
    pub home_object: Option<ObjectId>,
    pub goals: BTreeMap<GoalKind, GoalTarget>,
}
