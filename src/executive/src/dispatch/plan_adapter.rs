//! The dispatcher over the project's plan ([`PartialPlan`]): Algorithm 2 reads the plan directly through
//! [`PlanView`]; the marking of Algorithms 3–8 is kept by [`PlanMarking`] from the plan's change log
//! ([`PlanChange`]), which records planning, backtracking, plan repair and the executive's edits (past
//! actions leaving, links broken, goals withdrawn) alike.
//!
//! Two things separate the plan's log from the dispatcher's [`Change`]s:
//! - the plan keeps the causal links of an action that left it (a past action's effects stay in the state),
//!   while the dispatcher's graph drops them with the action; so the adapter keeps every active link of the
//!   plan with its ends and hands the marking only those whose ends are both in the plan, re-attaching them
//!   if the action or goal comes back (a backtrack over its removal);
//! - the executive replaces its plan by a repaired or replanned one: the new plan's log continues the old
//!   one only when it was cloned from it before the cursor ([`PartialPlan::changes_continuing`]); otherwise
//!   the marking is rebuilt by replaying the new plan's log from its beginning.

use std::collections::{HashMap, HashSet};

use super::graph::{CausalView, Change, Establisher, GraphError, Link, Node};
use super::marking::Marking;
use mavtempo_temporal::model::{GoalId, GoalOrigin};
use mavtempo_temporal::plan::{
    ActionId, ChangeCursor, LinkEnds, LinkId, Owner, PartialPlan, PlanChange,
};

/// [`CausalView`] over the plan as it is: live actions, active goals and active links between them.
pub struct PlanView<'a>(pub &'a PartialPlan);

impl PlanView<'_> {
    fn consumer(&self, l: LinkId) -> Option<Node> {
        let plan = self.0;
        let link = plan.link(l);
        if !link.active || !plan.cond_live(link.cond) {
            return None;
        }
        match plan.cond(link.cond).owner {
            Owner::Action(b) => Some(Node::Action(b)),
            Owner::Goal(g) => Some(Node::Goal(g)),
            Owner::Initial | Owner::Exogenous(_) => None,
        }
    }

    fn live_action(&self, a: ActionId) -> Option<ActionId> {
        let id = a;
        (id.index() < self.0.actions().len() && !self.0.action(id).removed).then_some(id)
    }
}

impl CausalView for PlanView<'_> {
    fn for_each_supported(&self, a: ActionId, f: &mut dyn FnMut(Node)) {
        let Some(id) = self.live_action(a) else {
            return;
        };
        let plan = self.0;
        for &e in &plan.action(id).events {
            for &l in plan.links_on(plan.event(e).attr) {
                if plan.link(l).event == e {
                    if let Some(n) = self.consumer(l) {
                        f(n);
                    }
                }
            }
        }
    }

    fn for_each_establisher(&self, n: Node, f: &mut dyn FnMut(ActionId)) {
        let plan = self.0;
        let conds: Vec<_> = match n {
            Node::Action(a) => match self.live_action(a) {
                Some(id) => plan.action(id).conds.clone(),
                None => return,
            },
            Node::Goal(g) => plan
                .goals()
                .iter()
                .filter(|pg| pg.active && pg.goal == g)
                .map(|pg| pg.cond)
                .collect(),
        };
        for c in conds {
            let Some(l) = plan.cond(c).link else { continue };
            let link = plan.link(l);
            if let Owner::Action(a) = plan.event(link.event).owner {
                if link.active && !plan.action(a).removed {
                    f(a);
                }
            }
        }
    }

    fn goal_kind(&self, g: GoalId) -> Option<GoalOrigin> {
        let plan = self.0;
        plan.goals()
            .iter()
            .find(|pg| pg.active && pg.goal == g)
            .and_then(|pg| plan.problem().goals.get(pg.goal.index()))
            .map(|goal| goal.kind)
    }
}

/// `List_goals` kept from a plan's change log.
#[derive(Clone, Debug, Default)]
pub struct PlanMarking {
    marking: Marking,
    /// The log read so far and the position in it (`None`: nothing read yet).
    log: Option<(u64, ChangeCursor)>,
    /// Every active link of the plan with its ends, whether or not both ends are in the plan.
    links: HashMap<LinkId, Link>,
    /// The links touching each node (into it, or out of it for an action).
    touching: HashMap<Node, Vec<LinkId>>,
    actions: HashSet<ActionId>,
    /// Active goals, counted (the same goal may be in the plan twice while a replanning swaps it).
    goals: HashMap<GoalId, u32>,
    rebuilds: u64,
}

impl PlanMarking {
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether action `a` supports an external goal (is in `List_goals`), as of the last [`Self::sync`].
    pub fn supports_external_goal(&self, a: ActionId) -> bool {
        self.marking.supports_external_goal(a)
    }

    pub fn marking(&self) -> &Marking {
        &self.marking
    }

    /// How many times the marking was rebuilt from a plan's whole log (a plan that does not continue the
    /// one read before).
    pub fn rebuilds(&self) -> u64 {
        self.rebuilds
    }

    /// Reads the plan's changes since the last call. On `Err` (a log that does not fit the structure, a
    /// bug) the marking is reset and rebuilt at the next call.
    pub fn sync(&mut self, plan: &PartialPlan) -> Result<(), GraphError> {
        let id = plan.change_log_id();
        let continued = self
            .log
            .and_then(|(log, cursor)| plan.changes_continuing(log, cursor));
        let changes = match continued {
            Some(c) => c,
            None => {
                *self = PlanMarking {
                    rebuilds: self.rebuilds + u64::from(self.log.is_some()),
                    ..PlanMarking::default()
                };
                plan.changes_since(ChangeCursor::default())
            }
        };
        for c in changes {
            if let Err(e) = self.apply(plan, c) {
                *self = PlanMarking {
                    rebuilds: self.rebuilds,
                    ..PlanMarking::default()
                };
                return Err(e);
            }
        }
        // Backtracking is announced in the log: the marking's own trail is never restored here.
        self.marking.forget_trail();
        self.log = Some((id, plan.change_cursor()));
        Ok(())
    }

    fn apply(&mut self, plan: &PartialPlan, c: &PlanChange) -> Result<(), GraphError> {
        match *c {
            PlanChange::ActionAdded(a) => {
                let k = a;
                self.marking.apply(&Change::ActionAdded(k))?;
                self.actions.insert(k);
                self.attach(Node::Action(k))
            }
            PlanChange::ActionRemoved(a) => {
                let k = a;
                self.marking.apply(&Change::ActionRemoved(k))?;
                self.actions.remove(&k);
                Ok(())
            }
            PlanChange::GoalAdded(g) => {
                let k = g;
                let n = self.goals.entry(k).or_insert(0);
                *n += 1;
                if *n > 1 {
                    return Ok(());
                }
                let kind = plan
                    .problem()
                    .goals
                    .get(g.index())
                    .map_or(GoalOrigin::Internal, |goal| goal.kind);
                self.marking.apply(&Change::GoalAdded(k, kind))?;
                self.attach(Node::Goal(k))
            }
            PlanChange::GoalRemoved(g) => {
                let k = g;
                let n = self.goals.get_mut(&k).ok_or(GraphError::UnknownGoal(k))?;
                *n -= 1;
                if *n == 0 {
                    self.goals.remove(&k);
                    self.marking.apply(&Change::GoalRemoved(k))?;
                }
                Ok(())
            }
            PlanChange::LinkAdded(ends) => {
                let (k, link) = link_of(ends)?;
                if self.links.insert(k, link).is_some() {
                    return Err(GraphError::DuplicateLink(k));
                }
                for n in ends_of(link) {
                    self.touching.entry(n).or_default().push(k);
                }
                if self.live(link) {
                    self.marking.apply(&Change::LinkAdded(k, link))?;
                }
                Ok(())
            }
            PlanChange::LinkRemoved(ends) => {
                let k = ends.link;
                let link = self.links.remove(&k).ok_or(GraphError::UnknownLink(k))?;
                for n in ends_of(link) {
                    if let Some(v) = self.touching.get_mut(&n) {
                        v.retain(|x| *x != k);
                    }
                }
                if self.marking.graph().link(k).is_some() {
                    self.marking.apply(&Change::LinkRemoved(k))?;
                }
                Ok(())
            }
        }
    }

    /// Hands the marking the known links of `n` whose other end is in the plan (`n` just (re)entered it).
    fn attach(&mut self, n: Node) -> Result<(), GraphError> {
        let keys = self.touching.get(&n).cloned().unwrap_or_default();
        for k in keys {
            let Some(&link) = self.links.get(&k) else {
                continue;
            };
            if self.live(link) && self.marking.graph().link(k).is_none() {
                self.marking.apply(&Change::LinkAdded(k, link))?;
            }
        }
        Ok(())
    }

    fn live(&self, link: Link) -> bool {
        let from = match link.from {
            Establisher::Initial => true,
            Establisher::Action(a) => self.actions.contains(&a),
        };
        let to = match link.to {
            Node::Action(a) => self.actions.contains(&a),
            Node::Goal(g) => self.goals.contains_key(&g),
        };
        from && to
    }
}

fn link_of(ends: LinkEnds) -> Result<(LinkId, Link), GraphError> {
    let k = ends.link;
    let from = match ends.establisher {
        Owner::Initial | Owner::Exogenous(_) => Establisher::Initial,
        Owner::Action(a) => Establisher::Action(a),
        Owner::Goal(_) => return Err(GraphError::MalformedLink(k)),
    };
    let to = match ends.consumer {
        Owner::Action(a) => Node::Action(a),
        Owner::Goal(g) => Node::Goal(g),
        Owner::Initial | Owner::Exogenous(_) => return Err(GraphError::MalformedLink(k)),
    };
    Ok((k, Link { from, to }))
}

fn ends_of(link: Link) -> impl Iterator<Item = Node> {
    let from = match link.from {
        Establisher::Action(a) => Some(Node::Action(a)),
        Establisher::Initial => None,
    };
    from.into_iter().chain(Some(link.to))
}
