//! Types and objects. Enumeration constants, `true`/`false` and problem objects all live in one object
//! table so that every symbolic value is an [`ObjectId`].

use serde::Serialize;

use super::{GeoPoint, ObjectId, Position, TypeId};

/// How a type's members are given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum TypeKind {
    /// Closed set of constants listed in the domain (`type status = {STILL, MOVING};`); `bool` is one.
    Enum,
    /// Objects declared by problems (`type location;`), possibly extended at run time (a new location).
    Object,
}

/// A value type of symbolic variables and logical attributes.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Type {
    pub name: String,
    pub kind: TypeKind,
    /// For enumerations: the constants in declaration order (for object types, see the problem's table).
    pub members: Vec<ObjectId>,
    /// Where it is declared in its domain file (1-based); `None` for `bool` and types built in code.
    pub line: Option<usize>,
}

/// A constant: an enumeration member or a problem object.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Object {
    pub name: String,
    pub ty: TypeId,
    /// Coordinates, for objects that are places (`object base: location at (0, 0);`).
    pub position: Option<Position>,
}

impl Object {
    /// Local east/north/up metres of this object relative to `home`, if it has a position.
    pub fn local(&self, home: Option<&GeoPoint>) -> Option<(f64, f64, f64)> {
        self.position.map(|p| p.to_local(home))
    }
}
