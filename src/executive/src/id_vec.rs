//! A vector indexed by a typed id (aries' `RefVec` is the model): the ledger's per-resource tables are read
//! and written with a `ResourceId`, never with a bare position, so a goal's or an action's number cannot
//! index them by mistake.

use std::marker::PhantomData;

use mavtempo_temporal::model::ResourceId;

/// An id that is a position in the table of its kind.
pub trait TypedIndex: Copy {
    fn position(self) -> usize;
}

impl TypedIndex for ResourceId {
    fn position(self) -> usize {
        self.index()
    }
}

#[derive(Clone, Debug)]
pub struct IdVec<I, T> {
    items: Vec<T>,
    id: PhantomData<fn(I)>,
}

impl<I, T> Default for IdVec<I, T> {
    fn default() -> Self {
        IdVec {
            items: Vec::new(),
            id: PhantomData,
        }
    }
}

impl<I: TypedIndex, T> IdVec<I, T> {
    /// The table whose item of id `i` is the `i`-th of `items`.
    pub fn from_items(items: Vec<T>) -> Self {
        IdVec {
            items,
            id: PhantomData,
        }
    }

    pub fn get(&self, i: I) -> Option<&T> {
        self.items.get(i.position())
    }

    pub fn get_mut(&mut self, i: I) -> Option<&mut T> {
        self.items.get_mut(i.position())
    }

    /// Every item, in id order.
    pub fn as_slice(&self) -> &[T] {
        &self.items
    }

    pub fn iter(&self) -> std::slice::Iter<'_, T> {
        self.items.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_are_found_by_their_typed_id_and_a_missing_id_is_none() {
        let mut v: IdVec<ResourceId, f64> = IdVec::from_items(vec![1.0, 2.0]);
        assert_eq!(v.get(ResourceId(1)), Some(&2.0));
        if let Some(x) = v.get_mut(ResourceId(0)) {
            *x = 5.0;
        }
        assert_eq!(v.as_slice(), &[5.0, 2.0]);
        assert_eq!(v.get(ResourceId(2)), None);
    }
}
