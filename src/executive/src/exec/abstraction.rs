//! Causal-link removal via the abstraction hierarchy (seed 1 §3.3 "Causal links removal").
//!
//! Offline, from the domain: the *main attributes* of each task (the attributes of its primary effects).
//! Online: Att^i starts as the attributes of the flaws Att^f; every task having a main attribute in Att^i may
//! be inserted to repair them, so every attribute it mentions joins Att^i, up to a fixed point. The causal
//! links on attributes of Att^i that protect propositions of future actions (or goals) are then broken so
//! that new actions can be inserted into the current plan structure.
//!
//! Grounding: the paper grounds the operator's parameter bound to att_m; here attributes are closed over at
//! the attribute (not instance) level, which can only break more links, never fewer.

use crate::model::AttrId;
use crate::plan::{ActionId, LinkId, Owner, PartialPlan};

/// The abstraction hierarchy computed offline from the domain: the planner's, whose dependencies between
/// attributes are the main attributes of the paper ([`Hierarchy::closure`] gives Att^i).
pub use crate::planner::hierarchy::Hierarchy;

/// Att^f: the attributes of the open conditions and threatened links of the plan.
pub fn flawed_attributes(plan: &mut PartialPlan) -> Vec<AttrId> {
    let mut out: Vec<AttrId> = plan
        .flaws()
        .iter()
        .filter_map(|f| match f {
            crate::plan::Flaw::OpenCondition(c) => Some(plan.cond(*c).attr),
            crate::plan::Flaw::Threat { link, .. } => Some(plan.cond(plan.link(*link).cond).attr),
            _ => None,
        })
        .collect();
    out.sort();
    out.dedup();
    out
}

/// The links to break: active links on an attribute of Att^i protecting a condition of a future action or
/// of a goal, whose establisher is not an event of the same action (internal links are part of the action).
/// Links supporting running actions are kept (breaking them would make the plan non-executable).
pub fn links_to_break(plan: &PartialPlan, att_i: &[AttrId], running: &[ActionId]) -> Vec<LinkId> {
    let mut out = Vec::new();
    for attr in att_i {
        for &l in plan.links_on(*attr) {
            let link = plan.link(l);
            if !link.active || !plan.cond_live(link.cond) {
                continue;
            }
            let owner = plan.cond(link.cond).owner;
            let est = plan.event(link.event).owner;
            let keep = match owner {
                Owner::Action(a) => running.contains(&a) || est == owner,
                Owner::Goal(_) => false,
                _ => true,
            };
            if !keep {
                out.push(l);
            }
        }
    }
    out
}
