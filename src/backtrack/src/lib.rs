//! The one undo trail of mavtempo's backtracking stores: the STN, the binding and numeric CSPs, the partial
//! plan and the dispatcher's marking.
//!
//! A store records, before each change, an entry saying how to undo it ([`Trail::push`]); a [`Level`] is a
//! position in its trail ([`Trail::level`]), and restoring it undoes every entry pushed since, newest first
//! ([`Trail::restore`], or [`Trail::pop_after`] when the undo needs the whole store). Undoing costs time
//! proportional to the changes undone, so a search never clones a store. Each store keeps its own entry
//! type and undoes its entries itself; the trail only orders them.
//!
//! Levels are positions, not a stack of saved states: saving costs nothing (the STN saves around every
//! constraint it adds), any number of levels can be held, and restoring one invalidates only the levels
//! above it. Restoring a level above the current one does nothing.
//!
//! [`Backtrack`] is the interface every such store offers: `save` a level, `restore` it.

mod trail;

pub use trail::{Level, Trail};

/// A store whose changes can be undone back to a saved level.
pub trait Backtrack {
    /// What [`Backtrack::save`] returns: a [`Level`], or a composition of the levels of sub-stores.
    type Level: Copy;

    /// The current level (saving does not change the store).
    fn save(&mut self) -> Self::Level;

    /// Undoes every change made after `level` was saved. Levels saved after `level` become invalid;
    /// `level` itself stays valid (it can be restored again after more changes).
    fn restore(&mut self, level: Self::Level);
}

/// Implements [`Backtrack`] for a store by its inherent `save` and `restore` (which its callers use
/// without importing the trait): `backtrack::impl_backtrack!(Stn, Level);`.
#[macro_export]
macro_rules! impl_backtrack {
    ($store:ty, $level:ty) => {
        impl $crate::Backtrack for $store {
            type Level = $level;

            fn save(&mut self) -> $level {
                <$store>::save(self)
            }

            fn restore(&mut self, level: $level) {
                <$store>::restore(self, level)
            }
        }
    };
}
