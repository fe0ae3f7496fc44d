//! The domain's names the executive gives a vehicle meaning to, resolved to ids: which attribute a reported
//! position sets, which type new locations get, what an uploaded goal item becomes. Built from the vehicle
//! configuration's `[mapping]` once it is checked against the domain
//! ([`crate::config_check::check`]); the executive never guesses them from names.

use std::collections::BTreeMap;

use mavtempo_temporal::model::{AttrId, ObjectId, TypeId};
use mavtempo_vehicle::GoalKind;

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

/// Why a vehicle's name (a goal request, a reported state value) has no meaning in the domain.
#[derive(Clone, Debug, PartialEq, thiserror::Error, serde::Serialize, serde::Deserialize)]
#[serde(tag = "mapping", rename_all = "snake_case")]
pub enum MappingError {
    #[error("no goal mapping for {kind} items in the config")]
    NoGoalMapping { kind: String },
    #[error("no home object in the config's [mapping] for return-home items")]
    NoHomeObject,
    #[error("{kind} goal without a location")]
    NoGoalLocation { kind: String },
    #[error(
        "no location type in the config's [mapping] for a new location at ({east:.1}, {north:.1})"
    )]
    NoLocationType { east: f64, north: f64 },
    #[error("no position attribute in the config's [mapping]")]
    NoPositionAttribute,
    #[error("no attribute `{name}` in the domain")]
    NoAttribute { name: String },
    #[error("no object `{name}` in the problem")]
    NoObject { name: String },
    #[error("numbers are not state values of the domain")]
    Number,
}
