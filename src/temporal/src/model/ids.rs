//! Index newtypes: every cross-reference in the model is one of these (cheap, `Copy`, ordered).

use serde::{Deserialize, Serialize};

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
