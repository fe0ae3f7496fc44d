//! Bounded recomputation of the bounds after constraints are removed.

use super::network::Stn;

impl Stn {
    /// Recomputes the bounds that depended on the (already deactivated) constraints `removed`.
    pub(crate) fn relax_removed(&mut self, removed: &[u32]) {
        let _ = removed;
        todo!()
    }
}
