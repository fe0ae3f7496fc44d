//! The operator has the vehicle (issue 30), and why: while held, the executive launches and stops nothing
//! and makes no plan (src/executive/src/exec/authority.rs holds the rules).

#[derive(Default)]
pub(crate) struct OperatorHold(Option<String>);

impl OperatorHold {
    pub(crate) fn take_over(&mut self, why: String) {
        self.0 = Some(why);
    }

    pub(crate) fn hand_back(&mut self) {
        self.0 = None;
    }

    pub(crate) fn is_held(&self) -> bool {
        self.0.is_some()
    }

    pub(crate) fn why(&self) -> Option<&str> {
        self.0.as_deref()
    }
}
