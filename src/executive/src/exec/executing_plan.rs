//! *ExecutingPlan* behind a handle that records every edit (seed 1 §3.2: whenever the plan changes — a
//! message integrated, a timepoint executed — the repair tree is rooted again at it, and so is a new goal's
//! insertion attempt beside it). Reading goes through `Deref`; editing through [`ExecutingPlan::edit`],
//! which records the change, so no edit can forget to restart the searches.

use std::ops::Deref;

use mavtempo_temporal::plan::{ActionId, PartialPlan};

pub struct ExecutingPlan {
    plan: PartialPlan,
    /// Edited since the repair tree was last rooted or developed.
    repair_stale: bool,
    /// Edited (or replaced) since the insertion in progress was rooted.
    insertion_stale: bool,
}

impl Deref for ExecutingPlan {
    type Target = PartialPlan;
    fn deref(&self) -> &PartialPlan {
        &self.plan
    }
}

impl ExecutingPlan {
    pub fn new(plan: PartialPlan) -> Self {
        ExecutingPlan {
            plan,
            repair_stale: false,
            insertion_stale: false,
        }
    }

    /// The plan to edit: the repair tree and the insertion in progress start again from it.
    pub fn edit(&mut self) -> &mut PartialPlan {
        self.repair_stale = true;
        self.insertion_stale = true;
        &mut self.plan
    }

    /// A message was integrated (§3.2: "if nothing changed meanwhile — no message, no timepoint executed —
    /// the tree is kept"): the searches start again whether or not the message edits the plan.
    pub fn message_integrated(&mut self) {
        self.repair_stale = true;
        self.insertion_stale = true;
    }

    /// A search's plan becomes *ExecutingPlan* (a repair's labelled node or solution, an accepted
    /// insertion, a complete replanning): an insertion rooted at the old one starts again; the repair
    /// tree that found it goes on.
    pub fn replace(&mut self, plan: PartialPlan) {
        self.plan = plan;
        self.insertion_stale = true;
    }

    /// The actions a flaw involves (Definition 4's `A_t^f`): the flaws are computed, the plan unchanged.
    pub fn flawed_actions(&mut self) -> Vec<ActionId> {
        super::executable::flawed_actions(&mut self.plan)
    }

    /// Whether the plan has no flaw (computed, the plan unchanged).
    pub fn is_flawless(&mut self) -> bool {
        self.plan.flaws().is_empty()
    }

    /// The flaws' texts (computed, the plan unchanged).
    pub fn flaw_texts(&mut self) -> Vec<String> {
        let plan = &mut self.plan;
        plan.flaws().iter().map(|f| plan.flaw_text(f)).collect()
    }

    /// Whether the plan changed since the repair tree was last developed; the record is cleared.
    pub fn take_repair_stale(&mut self) -> bool {
        std::mem::take(&mut self.repair_stale)
    }

    /// Whether the plan changed since the insertion in progress was rooted; the record is cleared.
    pub fn take_insertion_stale(&mut self) -> bool {
        std::mem::take(&mut self.insertion_stale)
    }

    /// The insertion in progress starts again though the plan did not change (the queue did, or a repair
    /// is about to change the plan).
    pub fn restart_insertion(&mut self) {
        self.insertion_stale = true;
    }
}
