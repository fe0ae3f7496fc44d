//! [`Trail`]: undo entries in the order they were pushed, and [`Level`]s into it.

/// A position in a [`Trail`]: restoring it undoes every entry pushed after it.
#[derive(Copy, Clone, Eq, PartialEq, Ord, PartialOrd, Hash, Debug, Default)]
pub struct Level(usize);

impl Level {
    /// The level of an empty trail: restoring it undoes everything.
    pub const ROOT: Level = Level(0);
}

/// Undo entries, newest last.
#[derive(Clone, Debug)]
pub struct Trail<E> {
    entries: Vec<E>,
}

// Not derived: a derived `Default` would require `E: Default`.
impl<E> Default for Trail<E> {
    fn default() -> Self {
        Self::new()
    }
}

impl<E> Trail<E> {
    pub const fn new() -> Self {
        Trail {
            entries: Vec::new(),
        }
    }

    /// Records how to undo a change (push it before or right after making the change).
    pub fn push(&mut self, entry: E) {
        self.entries.push(entry);
    }

    /// The current level: restoring it later undoes what is pushed from now on.
    pub fn level(&self) -> Level {
        Level(self.entries.len())
    }

    /// Number of entries held.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Removes and returns the newest entry if it was pushed after `level` (`None` once `level` is
    /// reached). The restore loop of a store whose undo needs the whole store, trail aside:
    /// `while let Some(e) = self.trail.pop_after(level) { self.undo(e) }`.
    pub fn pop_after(&mut self, level: Level) -> Option<E> {
        if self.entries.len() > level.0 {
            self.entries.pop()
        } else {
            None
        }
    }

    /// Undoes every entry pushed after `level`, newest first, by `undo`.
    pub fn restore(&mut self, level: Level, mut undo: impl FnMut(E)) {
        while let Some(entry) = self.pop_after(level) {
            undo(entry);
        }
    }

    /// Forgets every entry: nothing done so far can be undone, and restoring a level saved before does
    /// nothing (for a store whose reader announces the reverse changes itself, so the trail would only grow).
    pub fn clear(&mut self) {
        self.entries.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A trail holding `entries`, oldest first.
    fn trail_of<T>(entries: impl IntoIterator<Item = T>) -> Trail<T> {
        let mut t = Trail::new();
        entries.into_iter().for_each(|e| t.push(e));
        t
    }

    /// Restores `l`, returning the entries undone in the order they were handed back.
    fn undo<T>(t: &mut Trail<T>, l: Level) -> Vec<T> {
        let mut undone = Vec::new();
        t.restore(l, |e| undone.push(e));
        undone
    }

    #[test]
    fn restore_undoes_newest_first_down_to_the_level() {
        let mut t = trail_of([1]);
        let l = t.level();
        t.push(2);
        t.push(3);
        assert_eq!(undo(&mut t, l), [3, 2]);
        assert_eq!(t.level(), l);
        assert_eq!(t.len(), 1);
    }

    #[test]
    fn restoring_a_level_above_the_current_one_does_nothing() {
        let mut t = trail_of(['a', 'b']);
        let high = t.level();
        t.restore(Level::ROOT, |_| {});
        assert!(t.is_empty());
        t.push('c');
        assert!(undo(&mut t, high).is_empty());
        assert_eq!(t.len(), 1);
    }

    #[test]
    fn pop_after_stops_at_the_level() {
        let mut t = trail_of([10, 20]);
        let l = t.level();
        t.push(30);
        assert_eq!(t.pop_after(l), Some(30));
        assert_eq!(t.pop_after(l), None);
        assert_eq!(t.len(), 2);
    }

    #[test]
    fn clear_makes_earlier_levels_restore_nothing() {
        let mut t = trail_of([1]);
        let l = t.level();
        t.push(2);
        t.clear();
        t.push(3);
        let undone = undo(&mut t, l);
        assert!(undone.is_empty(), "{undone:?}");
        assert_eq!(undo(&mut t, Level::ROOT), [3]);
    }
}
