//! Which motions must end with the vehicle still (issue 30). A move ends when the vehicle is within its
//! acceptance radius; ArduPilot then drives on to the point, so an action that needs the vehicle still
//! (a picture, a sample) would start while it rolls. The domain says which actions need it: a `hold` on
//! the attribute the vehicle configuration observes as moving/still (`[state] moving`, e.g.
//! `hold(ROBOT_STATUS(): STILL, (st, et))` in take_picture), supported by a causal link from the motion's
//! own end. Such a motion is started with [`mavtempo_vehicle::Vehicle::start_still`]: it ends once the
//! vehicle is still too. A move followed by a move needs no such wait (the next move's event on the
//! attribute is no hold).

use super::executive::Executive;
use mavtempo_temporal::plan::{ActionId, CondKind, Owner, STerm};

impl Executive {
    /// `[state] moving` of the vehicle configuration, resolved in the domain: its attribute and still
    /// value. Unknown names leave every motion ending within its radius, as before.
    pub fn with_still_state(mut self, moving: Option<&mavtempo_vehicle::observed::Flag>) -> Self {
        let still = moving.and_then(|f| {
            let attr = self.plan.domain().attr_id(&f.attribute)?;
            let value = self.plan.problem().object_id(&f.no)?;
            Some((attr, value))
        });
        self.vehicle.set_still(still);
        self
    }

    /// Whether action `a`'s end makes the vehicle still for a later action that holds it still.
    pub(crate) fn must_end_still(&self, a: ActionId) -> bool {
        let Some((attr, still)) = self.vehicle.still() else {
            return false;
        };
        let end = self.plan.action(a).end;
        self.plan.links_on(attr).iter().any(|&l| {
            let link = self.plan.link(l);
            let ev = self.plan.event(link.event);
            let cond = self.plan.cond(link.cond);
            link.active
                && ev.owner == Owner::Action(a)
                && ev.at == end
                && ev.to == STerm::Obj(still)
                && matches!(cond.kind, CondKind::Hold { .. })
                && cond.owner != Owner::Action(a)
        })
    }
}
