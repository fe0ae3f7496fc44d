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

use crate::model::{AttrId, Domain, TaskId};
use crate::plan::{ActionId, LinkId, Owner, PartialPlan};

/// The abstraction hierarchy information computed offline from the domain.
#[derive(Clone, Debug)]
pub struct Hierarchy {
    /// For each attribute, the tasks of which it is a main attribute.
    main_of: Vec<Vec<TaskId>>,
    /// For each task, every attribute it mentions.
    attrs_of: Vec<Vec<AttrId>>,
}

impl Hierarchy {
    pub fn new(domain: &Domain) -> Self {
        let mut main_of = vec![Vec::new(); domain.attrs.len()];
        let mut attrs_of = Vec::with_capacity(domain.tasks.len());
        for (i, task) in domain.tasks.iter().enumerate() {
            for a in task.main_attributes() {
                main_of[a.index()].push(TaskId::from_index(i));
            }
            attrs_of.push(task.attributes());
        }
        Hierarchy { main_of, attrs_of }
    }

    /// Att^i: the fixed point from Att^f.
    pub fn closure(&self, flawed: &[AttrId]) -> Vec<AttrId> {
        let mut att: Vec<AttrId> = flawed.to_vec();
        let mut i = 0;
        while i < att.len() {
            let a = att[i];
            i += 1;
            for task in &self.main_of[a.index()] {
                for &b in &self.attrs_of[task.index()] {
                    if !att.contains(&b) {
                        att.push(b);
                    }
                }
            }
        }
        att.sort();
        att
    }
}

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
