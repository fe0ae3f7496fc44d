//! Index newtypes: every cross-reference in the model is one of these (cheap, `Copy`, ordered).

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

/// What every index newtype is: a position in its owning vector (for the tables generic over their id).
pub trait IndexId: Copy {
    /// The id of the element at position `i` of the owning vector.
    fn from_index(i: usize) -> Self;
}

/// Appends `item`, known as `name`, to a model table and to its name → id map; returns its id.
pub(crate) fn append_named<I: IndexId, T>(
    table: &mut Vec<T>,
    names: &mut HashMap<String, I>,
    name: String,
    item: T,
) -> I {
    let id = I::from_index(table.len());
    names.insert(name, id);
    table.push(item);
    id
}

macro_rules! index_type {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
        pub struct $name(pub u32);

        impl $name {
            /// The position in the owning vector.
            pub fn index(self) -> usize {
                self.0 as usize
            }

            /// The id of the element at position `i` of the owning vector.
            pub fn from_index(i: usize) -> Self {
                // Model tables are built from source files: far below u32::MAX entries.
                Self(u32::try_from(i).unwrap_or(u32::MAX))
            }
        }

        impl IndexId for $name {
            fn from_index(i: usize) -> Self {
                $name::from_index(i)
            }
        }
    };
}

index_type!(
    /// A type (enumeration, object type or the builtin `bool`) in [`crate::model::Domain::types`].
    TypeId
);
index_type!(
    /// An object (enumeration constant, `true`/`false`, problem object) in the problem's object table
    /// (the domain's objects come first, with the same ids).
    ObjectId
);
index_type!(
    /// A logical attribute (state variable) in [`crate::model::Domain::attrs`].
    AttrId
);
index_type!(
    /// A resource attribute in [`crate::model::Domain::resources`].
    ResourceId
);
index_type!(
    /// A task (action template) in [`crate::model::Domain::tasks`].
    TaskId
);
index_type!(
    /// A goal in [`crate::model::Problem::goals`].
    GoalId
);
index_type!(
    /// A symbolic (object-valued) variable of a task, in [`crate::model::Task::sym_vars`]; the task's
    /// parameters come first.
    SymVarId
);
index_type!(
    /// A numeric variable of a task, in [`crate::model::Task::num_vars`].
    NumVarId
);
index_type!(
    /// A named timepoint of a task, in [`crate::model::Task::timepoints`].
    TpId
);
