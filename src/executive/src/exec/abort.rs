//! Whether execution is aborted and why (seed 1 §3.6). One policy: the first reason is kept until the
//! replanning that follows clears it; what comes after it (a timeout, a failed repair) is its consequence,
//! not its cause.

use super::outcome::AbortReason;

#[derive(Default)]
pub(crate) struct Abort(Option<AbortReason>);

impl Abort {
    /// Execution aborts for `reason`, unless it already did.
    pub(crate) fn raise(&mut self, reason: AbortReason) {
        if self.0.is_none() {
            self.0 = Some(reason);
        }
    }

    pub(crate) fn reason(&self) -> Option<&AbortReason> {
        self.0.as_ref()
    }

    pub(crate) fn is_raised(&self) -> bool {
        self.0.is_some()
    }

    /// A new plan was adopted: execution goes on.
    pub(crate) fn clear(&mut self) {
        self.0 = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_reason_is_kept_until_cleared() {
        let mut a = Abort::default();
        a.raise(AbortReason::Unstated);
        a.raise(AbortReason::VehicleElsewhere { distance_m: 3.0 });
        assert_eq!(a.reason(), Some(&AbortReason::Unstated));
        a.clear();
        assert!(!a.is_raised());
        a.raise(AbortReason::VehicleElsewhere { distance_m: 3.0 });
        assert!(matches!(
            a.reason(),
            Some(AbortReason::VehicleElsewhere { .. })
        ));
    }
}
