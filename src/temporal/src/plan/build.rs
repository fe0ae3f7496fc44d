//! Building the plan: the root node (initial state, predicted timed facts, goals; seed 1 §2.2 "the root node
//! of T consists of the initial state, expected availability profiles of resources, goals ... and a set of
//! constraints"), task insertion, causal-link insertion.

use std::sync::Arc;

use super::changes::ChangeLog;
use super::{
    Action, ActionId, CausalLink, CondId, CondKind, Condition, EventId, EventRec, LinkId, NTerm,
    NVar, NumCons, Owner, PartialPlan, PlanChange, PlanError, PlanGoal, STerm, TimeFloor, Usage,
    UsageId, UsageKind, VarId,
};
use crate::model::{
    Binding, Domain, GoalId, NumConstraint, NumTerm, Problem, ResourceKind, Task, TaskId, Term,
    TimeInterval,
};
use crate::stn::{Inconsistent, Stn, Timepoint, INF};

/// STN bounds of a model interval (open bounds one unit inside, infinities explicit).
pub(crate) fn stn_bounds(i: &TimeInterval) -> (i64, i64) {
    (i.min_ms().unwrap_or(-INF), i.max_ms().unwrap_or(INF))
}

/// The numeric constraints of `task` over an instance's variables (`vars`, `nums`) and timepoints
/// (`tps`); each duration `?d = t2 − t1` adds its constraint to `stn` (unbounded: the propagation narrows
/// it).
pub(crate) fn numeric_constraints(
    task: &Task,
    vars: &[VarId],
    nums: &[NVar],
    tps: &[Timepoint],
    stn: &mut Stn,
) -> Result<Vec<NumCons>, Inconsistent> {
    let sterm = |x: &Term| match *x {
        Term::Var(v) => STerm::Var(vars[v.index()]),
        Term::Obj(o) => STerm::Obj(o),
        Term::Unknown => STerm::Unknown,
    };
    let nterm = |x: &NumTerm| match *x {
        NumTerm::Var(v) => NTerm::Var(nums[v.index()]),
        NumTerm::Const(c) => NTerm::Const(c),
    };
    let mut num_cons = Vec::with_capacity(task.numeric.len());
    for c in &task.numeric {
        num_cons.push(match c {
            NumConstraint::Distance { var, a, b } => NumCons::Distance {
                var: nums[var.index()],
                a: sterm(a),
                b: sterm(b),
            },
            NumConstraint::Duration { var, from, to } => NumCons::Duration {
                var: nums[var.index()],
                c: stn.add_constraint(tps[from.index()], tps[to.index()], -INF, INF)?,
            },
            NumConstraint::Product { var, a, b } => NumCons::Product {
                var: nums[var.index()],
                a: nterm(a),
                b: nterm(b),
            },
            NumConstraint::Sum { var, a, b } => NumCons::Sum {
                var: nums[var.index()],
                a: nterm(a),
                b: nterm(b),
            },
            NumConstraint::Le(a, b) => NumCons::Le(nterm(a), nterm(b)),
            NumConstraint::Equal(a, b) => NumCons::Equal(nterm(a), nterm(b)),
        });
    }
    Ok(num_cons)
}

impl PartialPlan {
    /// The root plan of a problem: initial state and timed facts as events, every goal as an open condition.
    pub fn new(domain: Arc<Domain>, problem: Arc<Problem>) -> Result<Self, PlanError> {
        let n_attrs = domain.attrs.len();
        let n_res = domain.resources.len();
        let mut plan = PartialPlan {
            horizon: problem.horizon,
            stn: crate::stn::Stn::new(),
            bindings: Default::default(),
            numeric: Default::default(),
            actions: Vec::new(),
            events: Vec::new(),
            conds: Vec::new(),
            links: Vec::new(),
            usages: Vec::new(),
            goals: Vec::new(),
            floor: TimeFloor::None,
            events_by_attr: vec![Vec::new(); n_attrs],
            links_by_attr: vec![Vec::new(); n_attrs],
            usages_by_res: vec![Vec::new(); n_res],
            threats: super::candidates::CandidateSet::new(),
            unary: super::candidates::CandidateSet::new(),
            reservoir_dirty: vec![true; n_res],
            trail: Default::default(),
            changes: ChangeLog::default(),
            regress: Default::default(),
            domain,
            problem,
        };
        let origin = plan.stn.origin();
        let problem = plan.problem.clone();
        for f in &problem.initial {
            plan.push_initial(f);
        }
        for (i, tf) in problem.exogenous.iter().enumerate() {
            let at = plan.stn.add_timepoint();
            plan.stn.add_constraint(origin, at, tf.at, tf.at)?;
            plan.push_event(EventRec {
                owner: Owner::Exogenous(i),
                attr: tf.fact.attr,
                args: tf.fact.args.iter().map(|&o| STerm::Obj(o)).collect(),
                cond: None,
                to: tf.fact.value.into(),
                at,
                primary: true,
            });
        }
        for g in 0..problem.goals.len() {
            plan.add_goal(GoalId::from_index(g))?;
        }
        Ok(plan)
    }

    /// An initial fact as an event at the origin.
    pub(super) fn push_initial(&mut self, f: &crate::model::Fact) {
        let origin = self.stn.origin();
        self.push_event(EventRec {
            owner: Owner::Initial,
            attr: f.attr,
            args: f.args.iter().map(|&o| STerm::Obj(o)).collect(),
            cond: None,
            to: f.value.into(),
            at: origin,
            primary: true,
        });
    }

    /// A new timepoint before the horizon and after the current [`TimeFloor`].
    pub fn new_timepoint(&mut self) -> Result<Timepoint, PlanError> {
        let origin = self.stn.origin();
        let t = self.stn.add_timepoint();
        self.stn.add_constraint(origin, t, 0, self.horizon)?;
        match self.floor {
            TimeFloor::None => {}
            TimeFloor::At(time) => {
                self.stn.add_constraint(origin, t, time, INF)?;
            }
            TimeFloor::After(tp) => {
                self.stn.add_precedence(tp, t)?;
            }
        }
        Ok(t)
    }

    /// Adds goal `g` of the problem as an open condition `hold(attr(args): value, (st, et))` with its windows.
    pub fn add_goal(&mut self, g: GoalId) -> Result<CondId, PlanError> {
        let problem = self.problem.clone();
        let goal = problem
            .goals
            .get(g.index())
            .ok_or_else(|| PlanError::Invalid(format!("no goal {}", g.0)))?;
        let origin = self.stn.origin();
        let st = self.new_timepoint()?;
        let et = self.new_timepoint()?;
        let (lo, hi) = stn_bounds(&goal.start_window);
        self.stn.add_constraint(origin, st, lo.max(0), hi)?;
        let (lo, hi) = stn_bounds(&goal.duration);
        self.stn.add_constraint(st, et, lo.max(0), hi)?;
        let cond = self.push_cond(Condition {
            owner: Owner::Goal(g),
            attr: goal.attr,
            args: goal.args.iter().map(|&o| STerm::Obj(o)).collect(),
            value: goal.value.into(),
            from: st,
            to: et,
            kind: CondKind::Hold { closed: true },
            link: None,
        });
        self.goals.push(PlanGoal {
            goal: g,
            st,
            et,
            cond,
            active: true,
        });
        self.changes.push(PlanChange::GoalAdded(g));
        Ok(cond)
    }

    /// An observed fact (seed 1 §3.3, a state value from a report): `attr(args) = value` from `at` on, an
    /// event of the initial state's kind on a timepoint executed at `at`. Hook for the executive.
    pub fn add_observation(
        &mut self,
        attr: crate::model::AttrId,
        args: &[crate::model::ObjectId],
        value: crate::model::Value,
        at: crate::model::Time,
    ) -> Result<EventId, PlanError> {
        let tp = self.stn.add_timepoint();
        self.stn.execute(tp, at)?;
        Ok(self.push_event(EventRec {
            owner: Owner::Initial,
            attr,
            args: args.iter().map(|&o| STerm::Obj(o)).collect(),
            cond: None,
            to: value.into(),
            at: tp,
            primary: false,
        }))
    }

    fn push_event(&mut self, e: EventRec) -> EventId {
        let id = EventId(self.events.len() as u32);
        let attr = e.attr;
        self.events.push(e);
        self.events_by_attr[attr.index()].push(id);
        for i in 0..self.links_by_attr[attr.index()].len() {
            let l = self.links_by_attr[attr.index()][i];
            self.threats.push(id, l);
        }
        id
    }

    fn push_cond(&mut self, c: Condition) -> CondId {
        self.conds.push(c);
        CondId(self.conds.len() as u32 - 1)
    }

    fn push_usage(&mut self, u: Usage) -> UsageId {
        let id = UsageId(self.usages.len() as u32);
        let r = u.resource;
        let unary = self.domain.resource(r).kind == ResourceKind::Unary;
        self.usages.push(u);
        if unary {
            for i in 0..self.usages_by_res[r.index()].len() {
                let other = self.usages_by_res[r.index()][i];
                self.unary.push(other, id);
            }
        } else {
            self.set_reservoir_dirty(r.index(), true);
        }
        self.usages_by_res[r.index()].push(id);
        id
    }

    /// Adds the causal link `event → cond`: binds the attribute instances and values, orders the event
    /// before the condition, protects the interval (threat candidates against every event on the attribute).
    pub fn add_link(&mut self, event: EventId, cond: CondId) -> Result<LinkId, PlanError> {
        let (e, c) = (&self.events[event.index()], &self.conds[cond.index()]);
        if e.attr != c.attr || e.args.len() != c.args.len() {
            return Err(PlanError::Invalid(
                "link between different attributes".into(),
            ));
        }
        if c.link.is_some() {
            return Err(PlanError::Invalid("condition already supported".into()));
        }
        let pairs: Vec<(STerm, STerm)> =
            e.args.iter().copied().zip(c.args.iter().copied()).collect();
        let (to, value, at, from, delay) = (e.to, c.value, e.at, c.from, c.support_delay());
        for (x, y) in pairs {
            self.bindings.unify(x, y)?;
        }
        self.bindings.unify(to, value)?;
        let precedence = if at == from && delay == 0 {
            None
        } else {
            Some(self.stn.add_constraint(at, from, delay, INF)?)
        };
        self.propagate_changed_bindings()?;
        let l = LinkId(self.links.len() as u32);
        let attr = self.conds[cond.index()].attr;
        self.links.push(CausalLink {
            event,
            cond,
            precedence,
            active: true,
        });
        self.links_by_attr[attr.index()].push(l);
        self.trail.push(super::Entry::CondLink(cond, None));
        self.conds[cond.index()].link = Some(l);
        for i in 0..self.events_by_attr[attr.index()].len() {
            let ev = self.events_by_attr[attr.index()][i];
            self.threats.push(ev, l);
        }
        let ends = self.link_ends(l);
        self.changes.push(PlanChange::LinkAdded(ends));
        Ok(l)
    }

    /// Re-propagates the numeric constraints of actions whose variables' domains changed (distances).
    pub(crate) fn propagate_changed_bindings(&mut self) -> Result<(), PlanError> {
        let changed = self.bindings.take_changed();
        if changed.is_empty() {
            return Ok(());
        }
        for a in 0..self.actions.len() {
            let act = &self.actions[a];
            if act.removed || act.num_cons.is_empty() {
                continue;
            }
            let touched = act.num_cons.iter().any(|c| match c {
                NumCons::Distance { a, b, .. } => [a, b].iter().any(|t| match t {
                    STerm::Var(v) => {
                        let r = self.bindings.class_of(*v);
                        changed.contains(&r) || changed.contains(&v.0)
                    }
                    _ => false,
                }),
                _ => false,
            });
            if touched {
                self.repropagate_action(ActionId(a as u32))?;
            }
        }
        Ok(())
    }

    /// Re-propagates the numeric constraints of action `a` (after one of its variables was narrowed).
    pub fn repropagate_action(&mut self, a: ActionId) -> Result<(), PlanError> {
        let cons = std::mem::take(&mut self.actions[a.index()].num_cons);
        let r = self
            .numeric
            .propagate(&cons, &self.bindings, &self.problem, &mut self.stn);
        self.actions[a.index()].num_cons = cons;
        Ok(r?)
    }

    /// Inserts an instance of `task` (fresh variables, timepoints after the [`TimeFloor`], all its
    /// constraints), with its internal causal links. On `Err` the caller restores a saved level.
    pub fn insert_action(&mut self, task: TaskId) -> Result<ActionId, PlanError> {
        let domain = self.domain.clone();
        let problem = self.problem.clone();
        let t = domain.task(task);
        let id = ActionId(self.actions.len() as u32);
        let vars: Vec<_> = t
            .sym_vars
            .iter()
            .map(|v| self.bindings.new_var(problem.objects_of(v.ty)))
            .collect();
        let sterm = |x: &Term| match *x {
            Term::Var(v) => STerm::Var(vars[v.index()]),
            Term::Obj(o) => STerm::Obj(o),
            Term::Unknown => STerm::Unknown,
        };
        let nums: Vec<_> = t
            .num_vars
            .iter()
            .map(|v| self.numeric.new_var(v.domain.lo(), v.domain.hi()))
            .collect();
        let nterm = |x: &NumTerm| match *x {
            NumTerm::Var(v) => NTerm::Var(nums[v.index()]),
            NumTerm::Const(c) => NTerm::Const(c),
        };
        let mut tps = Vec::with_capacity(t.timepoints.len());
        let start = self.new_timepoint()?;
        for i in 0..t.timepoints.len() {
            if i == t.start.index() {
                tps.push(start);
            } else {
                let origin = self.stn.origin();
                let tp = self.stn.add_timepoint();
                self.stn.add_constraint(origin, tp, 0, self.horizon)?;
                tps.push(tp);
            }
        }
        for c in &t.temporal {
            let (lo, hi) = stn_bounds(&c.interval);
            self.stn
                .add_constraint(tps[c.from.index()], tps[c.to.index()], lo, hi)?;
        }
        for b in &t.bindings {
            match b {
                Binding::Eq(x, y) => self.bindings.unify(sterm(x), sterm(y))?,
                Binding::Ne(x, y) => self.bindings.separate(sterm(x), sterm(y))?,
                Binding::In(v, objs) => self.bindings.restrict_var(vars[v.index()], objs)?,
            }
        }
        let num_cons = numeric_constraints(t, &vars, &nums, &tps, &mut self.stn)?;
        self.numeric
            .propagate(&num_cons, &self.bindings, &problem, &mut self.stn)?;
        self.bindings.take_changed();
        self.actions.push(Action {
            task,
            vars: vars.clone(),
            nums: nums.clone(),
            tps: tps.clone(),
            start,
            end: tps[t.end.index()],
            events: Vec::new(),
            conds: Vec::new(),
            usages: Vec::new(),
            num_cons,
            removed: false,
            regress: 0,
        });
        let owner = Owner::Action(id);
        // Events first (with their `from` conditions), then holds.
        for ev in &t.events {
            let at = tps[ev.at.index()];
            let args: Vec<STerm> = ev.args.iter().map(sterm).collect();
            let eid = EventId(self.events.len() as u32);
            let cond = self.push_cond(Condition {
                owner,
                attr: ev.attr,
                args: args.clone(),
                value: sterm(&ev.from),
                from: at,
                to: at,
                kind: CondKind::Before(eid),
                link: None,
            });
            let e = self.push_event(EventRec {
                owner,
                attr: ev.attr,
                args,
                cond: Some(cond),
                to: sterm(&ev.to),
                at,
                primary: ev.primary,
            });
            self.actions[id.index()].events.push(e);
            self.actions[id.index()].conds.push(cond);
        }
        for h in &t.holds {
            let (from, to) = (tps[h.from.index()], tps[h.to.index()]);
            let cond = self.push_cond(Condition {
                owner,
                attr: h.attr,
                args: h.args.iter().map(sterm).collect(),
                value: sterm(&h.value),
                from,
                to,
                kind: CondKind::Hold { closed: from == to },
                link: None,
            });
            self.actions[id.index()].conds.push(cond);
        }
        for u in &t.usages {
            let kind = match u.kind {
                crate::model::UsageKind::Use { from, to } => UsageKind::Use {
                    from: tps[from.index()],
                    to: tps[to.index()],
                },
                crate::model::UsageKind::Consume { at } => UsageKind::Consume {
                    at: tps[at.index()],
                },
                crate::model::UsageKind::Produce { at } => UsageKind::Produce {
                    at: tps[at.index()],
                },
            };
            let uid = self.push_usage(Usage {
                action: id,
                resource: u.resource,
                kind,
                quantity: nterm(&u.quantity),
                saturating: u.saturating,
            });
            self.actions[id.index()].usages.push(uid);
        }
        self.changes.push(PlanChange::ActionAdded(id));
        self.add_internal_links(id)?;
        Ok(id)
    }

    /// Links a task's conditions to the task's own events when the template makes that support evident:
    /// a hold starting where an event of the task sets the same value on the same attribute instance
    /// (`event(AT: (?from, +oo), st); hold(AT: +oo, (st, et))`), and an event's `from` set by the task's
    /// event at its start (`event(AT: (+oo, ?to), et)`). This is the support IxTeT's task models intend, and
    /// it spares the search a choice it would always make.
    fn add_internal_links(&mut self, a: ActionId) -> Result<(), PlanError> {
        let act = &self.actions[a.index()];
        let (start, events, conds) = (act.start, act.events.clone(), act.conds.clone());
        for c in conds {
            let cond = &self.conds[c.index()];
            let want_at = match cond.kind {
                CondKind::Hold { .. } => cond.from,
                CondKind::Before(_) if cond.from != start => start,
                CondKind::Before(_) => continue,
            };
            let found = events.iter().copied().find(|&e| {
                let ev = &self.events[e.index()];
                ev.at == want_at
                    && ev.attr == cond.attr
                    && ev.args == cond.args
                    && ev.to == cond.value
            });
            if let Some(e) = found {
                self.add_link(e, c)?;
            }
        }
        Ok(())
    }
}
