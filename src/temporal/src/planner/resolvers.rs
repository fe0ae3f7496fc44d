//! Resolvers of each flaw kind (seed 1 §2.2) and their application to the partial plan.
//!
//! Ordering heuristics (least commitment first, existing structure before new actions):
//! - open condition: existing establishers first (no new action), the
//!   earliest possible one first (it extends the current chain of changes from its start, and a wrong early
//!   choice fails fast on a forced threat), then new tasks;
//! - threat: the two precedences first, the one agreeing with the current earliest times first (it
//!   disturbs the schedule least), then binding `≠` on the attribute instance, then `=` on the value;
//! - unary conflict: the order agreeing with the current earliest starts first;
//! - reservoir under-flow: existing productions moved before, consumptions pushed after, then a new
//!   producer task (download_images, recharge_battery) before the checkpoint;
//! - reservoir over-flow: consumptions moved before, productions pushed after, then bounding the
//!   production's quantity variable (a numeric constraint, still least commitment on the timeline).

use crate::model::{ResourceId, TaskId, Term, Value};
use crate::plan::{
    ActionId, CondId, CondKind, Flaw, NTerm, NVar, PartialPlan, PlanError, ReservoirConflict,
    STerm, UsageKind,
};
use crate::stn::{Time, Timepoint, INF};

/// A way to remove a flaw.
#[derive(Clone, Debug, PartialEq)]
pub enum Resolver {
    /// Support `cond` by the existing event (causal link).
    Link {
        cond: CondId,
        event: crate::plan::EventId,
    },
    /// Insert an instance of `task` and support `cond` by its `event`-th event.
    Insert {
        cond: CondId,
        task: TaskId,
        event: usize,
    },
    /// `to − from ≥ delay`.
    Order {
        from: Timepoint,
        to: Timepoint,
        delay: Time,
    },
    /// Binding `≠`.
    Separate(STerm, STerm),
    /// Binding `=`.
    Unify(STerm, STerm),
    /// Insert an instance of `task` whose `usage`-th usage (a production) happens no later than `before`
    /// (and after `after`, the refill it must follow to help).
    InsertProducer {
        task: TaskId,
        usage: usize,
        before: Timepoint,
        after: Option<Timepoint>,
        resource: ResourceId,
    },
    /// Bound a production quantity from above.
    CapQuantity {
        action: ActionId,
        var: NVar,
        hi: f64,
    },
    /// Bound a production quantity from below (a recharge made longer rather than a second one added).
    RaiseQuantity {
        action: ActionId,
        var: NVar,
        lo: f64,
    },
}

impl Resolver {
    /// What the resolver does, for failure reasons.
    pub fn text(&self, plan: &PartialPlan) -> String {
        match self {
            Resolver::Link { event, .. } => {
                format!(
                    "a causal link from {}",
                    plan.owner_text(plan.event(*event).owner)
                )
            }
            Resolver::Insert { task, .. } => {
                format!("inserting {}", plan.domain.task(*task).name)
            }
            Resolver::InsertProducer { task, resource, .. } => format!(
                "inserting {} to produce {}",
                plan.domain.task(*task).name,
                plan.domain.resource(*resource).name
            ),
            Resolver::Order { .. } => "an ordering".into(),
            Resolver::Separate(..) | Resolver::Unify(..) => "a binding".into(),
            Resolver::CapQuantity { action, .. } | Resolver::RaiseQuantity { action, .. } => {
                format!(
                    "bounding the quantity of {}",
                    plan.owner_text(crate::plan::Owner::Action(*action))
                )
            }
        }
    }

    /// Whether applying it inserts an action.
    pub fn inserts(&self) -> bool {
        matches!(
            self,
            Resolver::Insert { .. } | Resolver::InsertProducer { .. }
        )
    }
}

/// The resolvers of `flaw`, in the order the search tries them (filtered by a cheap feasibility test).
pub fn resolvers(plan: &PartialPlan, flaw: &Flaw) -> Vec<Resolver> {
    resolvers_below(plan, flaw, usize::MAX).unwrap_or_default()
}

/// [`resolvers`] when there are fewer than `limit` of them, `None` when there are at least `limit`: the
/// selection only needs a flaw's exact resolvers when their number can still make it win, and proving
/// that a flaw has many stops after `limit` ordering queries (each a shortest-path search) instead of
/// running all of them. The cheap resolvers (no query) are counted first.
pub fn resolvers_below(plan: &PartialPlan, flaw: &Flaw, limit: usize) -> Option<Vec<Resolver>> {
    if limit == 0 {
        return None;
    }
    match flaw {
        Flaw::OpenCondition(c) => open_condition(plan, *c, limit),
        Flaw::Threat { event, link } => threat(plan, *event, *link, limit),
        Flaw::UnaryConflict { a, b } => unary(plan, *a, *b, limit),
        Flaw::Reservoir(c) => Some(reservoir(plan, c)).filter(|rs| rs.len() < limit),
    }
}

fn possibly(plan: &PartialPlan, from: Timepoint, to: Timepoint, delay: Time) -> bool {
    if let Some(answer) = possibly_by_bounds(plan, from, to, delay) {
        return answer;
    }
    !plan.stn.distance_below(from, to, delay)
}

/// [`possibly`] where the timepoints' bounds decide it (no search): impossible when even the latest `to`
/// minus the earliest `from` is short of `delay`; possible when the earliest schedule, or the latest one,
/// already separates them by `delay` (both are solutions of the network). The same tests open the
/// shortest-path search, so the answers agree.
fn possibly_by_bounds(
    plan: &PartialPlan,
    from: Timepoint,
    to: Timepoint,
    delay: Time,
) -> Option<bool> {
    if from == to {
        return Some(delay <= 0);
    }
    let stn = &plan.stn;
    if stn.ub(to).saturating_sub(stn.lb(from)) < delay {
        return Some(false);
    }
    if stn.lb(to) - stn.lb(from) >= delay
        || (stn.ub(to) < INF && stn.ub(from) < INF && stn.ub(to) - stn.ub(from) >= delay)
    {
        return Some(true);
    }
    None
}

/// Whether a task's event value can match the condition's value.
fn value_compatible(plan: &PartialPlan, to: &Term, value: STerm) -> bool {
    match (to, plan.bindings.value(value)) {
        (Term::Unknown, Some(v)) => v == Value::Unknown,
        (Term::Unknown, None) => false,
        (Term::Obj(o), _) => plan.bindings.possibly_equal(STerm::Obj(*o), value),
        (Term::Var(_), Some(Value::Unknown)) => false,
        (Term::Var(_), _) => true,
    }
}

/// The regression depth an instance of `task` inserted for `c` would have.
fn regress_depth(plan: &PartialPlan, c: CondId, task: TaskId) -> u32 {
    let cond = plan.cond(c);
    match (cond.kind, cond.owner) {
        (CondKind::Before(_), crate::plan::Owner::Action(o)) if plan.action(o).task == task => {
            plan.action(o).regress + 1
        }
        _ => 0,
    }
}

/// Whether the problem gives `attr` a value anywhere (initially, by a wildcard default, or as a predicted
/// change): the first value a chain of `from` conditions on it can regress to.
fn attr_has_a_value(plan: &PartialPlan, attr: crate::model::AttrId) -> bool {
    let p = &plan.problem;
    p.initial.iter().any(|f| f.attr == attr)
        || p.defaults.iter().any(|f| f.attr == attr)
        || p.exogenous.iter().any(|f| f.fact.attr == attr)
}

fn open_condition(plan: &PartialPlan, c: CondId, limit: usize) -> Option<Vec<Resolver>> {
    let cond = plan.cond(c);
    let b = &plan.bindings;
    let delay = cond.support_delay();
    let own = match cond.kind {
        CondKind::Before(e) => Some(e),
        CondKind::Hold { .. } => None,
    };
    // New tasks first (no ordering query), then the existing events: those the bounds decide, then
    // those that need a search — stopping as soon as `limit` resolvers are certain.
    let mut inserts: Vec<Resolver> = Vec::new();
    // A condition that takes any value (a PDDL add's prior value) is linked to whatever event precedes
    // it: an action inserted only for it could be left out of the plan. It is selected after every other
    // open condition ([`super::select`]), when a plan's actions are all in, so no plan is lost.
    let establishers_skipped = plan.cond_takes_any(c);
    let establishers = if establishers_skipped {
        Vec::new()
    } else {
        plan.domain.tasks_establishing(cond.attr)
    };
    for task in establishers {
        // A `from` condition that no existing event can support would otherwise be "supported" by
        // inserting another instance whose own `from` condition is just as open, without end until the
        // horizon runs out: the chain is bounded, and the search deepens the bound when it was hit.
        if regress_depth(plan, c, task) > plan.regress.limit {
            // A chain on an attribute with no value in the problem can never reach a first value: the
            // cut loses no plan, and deepening would only grow the chain (the search would never end).
            if attr_has_a_value(plan, cond.attr) {
                plan.regress.cut.set(true);
            }
            continue;
        }
        for (k, ev) in plan.domain.task(task).events.iter().enumerate() {
            if ev.primary && ev.attr == cond.attr && value_compatible(plan, &ev.to, cond.value) {
                inserts.push(Resolver::Insert {
                    cond: c,
                    task,
                    event: k,
                });
            }
        }
    }
    if inserts.len() >= limit {
        return None;
    }
    let mut existing: Vec<(Time, u32)> = Vec::new();
    let mut undecided: Vec<crate::plan::EventId> = Vec::new();
    for &e in plan.events_on(cond.attr) {
        // The value first: it rules out most events (half of them change the attribute to `+oo`), and
        // reads only the event, not its action.
        let ev = plan.event(e);
        if Some(e) == own
            || !b.possibly_equal(ev.to, cond.value)
            || !plan.event_in_effect(e)
            || ev
                .args
                .iter()
                .zip(&cond.args)
                .any(|(&x, &y)| !b.possibly_equal(x, y))
        {
            continue;
        }
        match possibly_by_bounds(plan, ev.at, cond.from, delay) {
            Some(false) => {}
            Some(true) => existing.push((plan.stn.lb(ev.at), e.0)),
            None => undecided.push(e),
        }
    }
    if existing.len() + inserts.len() >= limit {
        return None;
    }
    for e in undecided {
        let ev = plan.event(e);
        if !plan.stn.distance_below(ev.at, cond.from, delay) {
            existing.push((plan.stn.lb(ev.at), e.0));
            if existing.len() + inserts.len() >= limit {
                return None;
            }
        }
    }
    existing.sort();
    if establishers_skipped {
        // A value that takes anything is best linked to the event just before it: the latest first (the
        // earliest, the initial value, leaves every later change of the atom a threat to order).
        existing.reverse();
    }
    let mut out: Vec<Resolver> = existing
        .into_iter()
        .map(|(_, e)| Resolver::Link {
            cond: c,
            event: crate::plan::EventId(e),
        })
        .collect();
    out.extend(inserts);
    Some(out)
}

/// Drops the resolvers a look-ahead proves useless (done only for the selected flaw: it costs ordering
/// queries per event of the attribute).
///
/// `check_single`: also examine a lone link (for the siblings it would leave without any resolver), for a
/// search that leaves the static choices open ([`super::select::Order::StaticChoicesLast`]): there a
/// link's bindings are what decides them. The other order has settled them before, and skips the cost.
pub fn refine(plan: &mut PartialPlan, flaw: &Flaw, rs: &mut Vec<Resolver>, check_single: bool) {
    let Flaw::OpenCondition(c) = flaw else {
        return;
    };
    let own = own_event(plan, *c);
    // d(condition end, x) for every x, shared by every candidate link of this condition.
    let from_end = (rs.len() >= DOOM_SHARED).then(|| plan.stn.distances_from(plan.cond(*c).to));
    rs.retain(|r| match r {
        Resolver::Link { cond, event } => {
            !link_doomed_with(plan, *event, *cond, own, from_end.as_deref())
        }
        _ => true,
    });
    order_links_by_support(plan, *c, rs, check_single);
}

fn own_event(plan: &PartialPlan, c: CondId) -> Option<crate::plan::EventId> {
    match plan.cond(c).kind {
        CondKind::Before(e) => Some(e),
        CondKind::Hold { .. } => None,
    }
}

/// When several links can support a condition of an action and they bind its variables differently,
/// tries the one leaving the fewest other conditions of the action without an existing (not doomed)
/// establisher first: e.g. `go(?from, vent1)` needs `CONNECTED(?from, vent1)`, and linking it to
/// `CONNECTED(vent2, vent1)` lets `AUV_AT = vent2` be supported where the vehicle already is, while
/// `CONNECTED(surface, vent1)` would need yet another trip. (Ties keep the earliest-first order.)
fn order_links_by_support(
    plan: &mut PartialPlan,
    c: CondId,
    rs: &mut Vec<Resolver>,
    check_single: bool,
) {
    let crate::plan::Owner::Action(a) = plan.cond(c).owner else {
        return;
    };
    let links = rs
        .iter()
        .take_while(|r| matches!(r, Resolver::Link { .. }))
        .count();
    if links == 0 || (links == 1 && !check_single) {
        return;
    }
    let siblings: Vec<CondId> = plan
        .open_conditions()
        .filter(|&o| o != c && plan.cond(o).owner == crate::plan::Owner::Action(a))
        .collect();
    if siblings.is_empty() {
        return;
    }
    let mut cost: Vec<(usize, usize)> = Vec::with_capacity(links);
    for (i, r) in rs[..links].iter().enumerate() {
        let level = plan.save();
        let unsupported = match apply(plan, r) {
            Ok(()) => {
                let mut unsupported = 0;
                for &o in &siblings {
                    let own = own_event(plan, o);
                    let rs = open_condition(plan, o, usize::MAX).unwrap_or_default();
                    if rs.is_empty() {
                        // The bindings the link makes leave a sibling without any resolver.
                        unsupported = DEAD;
                        break;
                    }
                    let linked = rs.iter().any(|x| match x {
                        Resolver::Link { cond, event } => !link_doomed(plan, *event, *cond, own),
                        _ => false,
                    });
                    unsupported += usize::from(!linked);
                }
                unsupported
            }
            Err(_) => usize::MAX,
        };
        plan.restore(level);
        cost.push((unsupported, i));
    }
    cost.sort();
    let reordered: Vec<Resolver> = cost
        .iter()
        .filter(|&&(u, _)| u != DEAD)
        .map(|&(_, i)| rs[i].clone())
        .collect();
    rs.splice(..links, reordered);
}

/// [`order_links_by_support`]'s cost of a link that leaves a sibling condition without any resolver: a
/// dead end the next step would find, dropped at once.
const DEAD: usize = usize::MAX - 1;

/// Look-ahead on a candidate causal link `e → c`: some other event necessarily changes the attribute
/// instance to another value inside the protected interval (it can be neither before the establisher nor
/// after the condition, nor separated or unified by bindings), so the link would create a threat without
/// resolver. Rejecting it here saves the steps that would discover the dead end.
fn link_doomed(
    plan: &PartialPlan,
    e: crate::plan::EventId,
    c: CondId,
    own: Option<crate::plan::EventId>,
) -> bool {
    link_doomed_with(plan, e, c, own, None)
}

/// Candidate links of one condition at or above which [`refine`] computes the distances from the
/// condition's end once for all of them.
const DOOM_SHARED: usize = 8;

/// [`link_doomed`], with `from_end[x]` = d(end of `c`, x) when known: an event can follow the condition iff
/// that distance reaches the condition's end delay, so only the events that cannot need a search for the
/// other order.
fn link_doomed_with(
    plan: &PartialPlan,
    e: crate::plan::EventId,
    c: CondId,
    own: Option<crate::plan::EventId>,
    from_end: Option<&[Time]>,
) -> bool {
    let cond = plan.cond(c);
    let b = &plan.bindings;
    let te = plan.event(e).at;
    plan.events_on(cond.attr).iter().any(|&e2| {
        if e2 == e || Some(e2) == own {
            return false;
        }
        let ev2 = plan.event(e2);
        if let crate::plan::Owner::Action(a) = ev2.owner {
            if plan.action(a).removed {
                return false;
            }
        }
        let same_instance = ev2
            .args
            .iter()
            .zip(&cond.args)
            .all(|(&x, &y)| b.necessarily_equal(x, y));
        if !same_instance || b.possibly_equal(ev2.to, cond.value) {
            return false;
        }
        // Doomed only if neither order is possible: the bounds first (either proving an order possible
        // settles it), a search only for what they leave open.
        let after = possibly_by_bounds(plan, cond.to, ev2.at, cond.end_delay())
            .or_else(|| from_end.map(|d| d[ev2.at.index()] >= cond.end_delay()));
        if after == Some(true) {
            return false;
        }
        let before = possibly_by_bounds(plan, ev2.at, te, 1);
        if before == Some(true) {
            return false;
        }
        let impossible = |bounds: Option<bool>, from, to, delay| {
            bounds == Some(false) || plan.stn.distance_below(from, to, delay)
        };
        impossible(before, ev2.at, te, 1) && impossible(after, cond.to, ev2.at, cond.end_delay())
    })
}

/// Which of the orderings `(from, to, delay)` are possible, unless `base` plus the number of possible ones
/// reaches `limit` (then `None`): the bounds decide first, searches run only for the rest and stop as soon
/// as the count is certain.
fn possible_orders(
    plan: &PartialPlan,
    orders: [(Timepoint, Timepoint, Time); 2],
    base: usize,
    limit: usize,
) -> Option<[bool; 2]> {
    let mut count = base;
    let mut ok = [false; 2];
    let mut open = [false; 2];
    for (i, &(from, to, delay)) in orders.iter().enumerate() {
        match possibly_by_bounds(plan, from, to, delay) {
            Some(p) => {
                ok[i] = p;
                count += usize::from(p);
            }
            None => open[i] = true,
        }
    }
    if count >= limit {
        return None;
    }
    for (i, &(from, to, delay)) in orders.iter().enumerate() {
        if open[i] && !plan.stn.distance_below(from, to, delay) {
            ok[i] = true;
            count += 1;
            if count >= limit {
                return None;
            }
        }
    }
    Some(ok)
}

fn threat(
    plan: &PartialPlan,
    e: crate::plan::EventId,
    l: crate::plan::LinkId,
    limit: usize,
) -> Option<Vec<Resolver>> {
    let link = plan.link(l);
    let cond = plan.cond(link.cond);
    let ev = plan.event(e);
    let est = plan.event(link.event).at;
    let after = Resolver::Order {
        from: cond.to,
        to: ev.at,
        delay: cond.end_delay(),
    };
    let before = Resolver::Order {
        from: ev.at,
        to: est,
        delay: 1,
    };
    // The binding resolvers first: they cost no ordering query.
    let mut bind = Vec::new();
    let b = &plan.bindings;
    for (&x, &y) in ev.args.iter().zip(&cond.args) {
        if !b.necessarily_equal(x, y) {
            bind.push(Resolver::Separate(x, y));
        }
    }
    if b.possibly_equal(ev.to, cond.value) {
        bind.push(Resolver::Unify(ev.to, cond.value));
    }
    if bind.len() >= limit {
        return None;
    }
    let [after_ok, before_ok] = possible_orders(
        plan,
        [(cond.to, ev.at, cond.end_delay()), (ev.at, est, 1)],
        bind.len(),
        limit,
    )?;
    let mut out = Vec::new();
    let later_first = plan.stn.lb(ev.at) >= plan.stn.lb(est);
    match (after_ok, before_ok, later_first) {
        (true, true, true) => out.extend([after, before]),
        (true, true, false) => out.extend([before, after]),
        (true, false, _) => out.push(after),
        (false, true, _) => out.push(before),
        (false, false, _) => {}
    }
    out.extend(bind);
    Some(out)
}

fn unary(
    plan: &PartialPlan,
    a: crate::plan::UsageId,
    b: crate::plan::UsageId,
    limit: usize,
) -> Option<Vec<Resolver>> {
    let span = |u| match plan.usage(u).kind {
        UsageKind::Use { from, to } => Some((from, to)),
        _ => None,
    };
    let (Some((fa, ta)), Some((fb, tb))) = (span(a), span(b)) else {
        return Some(Vec::new());
    };
    let a_first = Resolver::Order {
        from: ta,
        to: fb,
        delay: 0,
    };
    let b_first = Resolver::Order {
        from: tb,
        to: fa,
        delay: 0,
    };
    let mut out = Vec::new();
    let [ok_a, ok_b] = possible_orders(plan, [(ta, fb, 0), (tb, fa, 0)], 0, limit)?;
    if plan.stn.lb(fa) <= plan.stn.lb(fb) {
        if ok_a {
            out.push(a_first);
        }
        if ok_b {
            out.push(b_first);
        }
    } else {
        if ok_b {
            out.push(b_first);
        }
        if ok_a {
            out.push(a_first);
        }
    }
    Some(out)
}

/// The ordering resolvers of a reservoir conflict: each usage of `before` moved before the checkpoint,
/// then each of `after` pushed after it (whichever the network still allows).
fn order_around(
    plan: &PartialPlan,
    c: &ReservoirConflict,
    before: &[(crate::plan::UsageId, Timepoint)],
    after: &[(crate::plan::UsageId, Timepoint)],
    out: &mut Vec<Resolver>,
) {
    for &(_, t) in before {
        if possibly(plan, t, c.point, 1) {
            out.push(Resolver::Order {
                from: t,
                to: c.point,
                delay: 1,
            });
        }
    }
    for &(_, t) in after {
        if possibly(plan, c.point, t, 1) {
            out.push(Resolver::Order {
                from: c.point,
                to: t,
                delay: 1,
            });
        }
    }
}

fn reservoir(plan: &PartialPlan, c: &ReservoirConflict) -> Vec<Resolver> {
    let mut out = Vec::new();
    if c.overflow {
        order_around(plan, c, &c.open_decreases, &c.open_increases, &mut out);
        let u = plan.usage(c.at);
        if let NTerm::Var(v) = u.quantity {
            let (lo, hi) = plan.numeric.bounds(v);
            let new_hi = hi - (c.level - c.capacity);
            if new_hi >= lo && new_hi < hi {
                out.push(Resolver::CapQuantity {
                    action: u.action,
                    var: v,
                    hi: new_hi,
                });
            }
        }
    } else {
        // The level never exceeds the capacity, so a decrease larger than the capacity runs out whatever
        // the plan does: no producer, order or refill can help (a capacity fallen below a picture's size).
        let (_, need) = plan.numeric.term(plan.usage(c.at).quantity);
        if need > c.capacity + 1e-6 {
            return out;
        }
        order_around(plan, c, &c.open_increases, &c.open_decreases, &mut out);
        for &(t, refill) in c.refill.iter().flatten() {
            if possibly(plan, t, refill, 1) {
                out.push(Resolver::Order {
                    from: t,
                    to: refill,
                    delay: 1,
                });
            }
        }
        let deficit = -c.level;
        for &p in &c.short_producers {
            let u = plan.usage(p);
            if let NTerm::Var(v) = u.quantity {
                let (lo, hi) = plan.numeric.bounds(v);
                // As much as the deficit asks, or all this producer can give (the rest from another).
                let new_lo = (lo + deficit).min(hi);
                if new_lo > lo {
                    out.push(Resolver::RaiseQuantity {
                        action: u.action,
                        var: v,
                        lo: new_lo,
                    });
                }
            }
        }
        for task in plan.domain.tasks_producing(c.resource) {
            for (k, u) in plan.domain.task(task).usages.iter().enumerate() {
                if u.resource == c.resource
                    && u.primary
                    && matches!(u.kind, crate::model::UsageKind::Produce { .. })
                {
                    out.push(Resolver::InsertProducer {
                        task,
                        usage: k,
                        before: c.point,
                        after: c.reset,
                        resource: c.resource,
                    });
                }
            }
        }
    }
    out
}

/// Applies `r` to the plan. On `Err` the plan may be half-changed: the caller restores its saved level.
pub fn apply(plan: &mut PartialPlan, r: &Resolver) -> Result<(), PlanError> {
    match *r {
        Resolver::Link { cond, event } => plan.add_link(event, cond).map(|_| ()),
        Resolver::Insert { cond, task, event } => {
            let depth = regress_depth(plan, cond, task);
            let a = plan.insert_action(task)?;
            plan.actions[a.index()].regress = depth;
            let e = *plan
                .action(a)
                .events
                .get(event)
                .ok_or_else(|| PlanError::Invalid("no such event".into()))?;
            plan.add_link(e, cond).map(|_| ())
        }
        Resolver::Order { from, to, delay } => {
            plan.stn.add_constraint(from, to, delay, INF)?;
            Ok(())
        }
        Resolver::Separate(x, y) => {
            plan.bindings.separate(x, y)?;
            plan.propagate_changed_bindings()
        }
        Resolver::Unify(x, y) => {
            plan.bindings.unify(x, y)?;
            plan.propagate_changed_bindings()
        }
        Resolver::InsertProducer {
            task,
            usage,
            before,
            after,
            resource: _,
        } => {
            let a = plan.insert_action(task)?;
            let u = *plan
                .action(a)
                .usages
                .get(usage)
                .ok_or_else(|| PlanError::Invalid("no such usage".into()))?;
            let at = match plan.usage(u).kind {
                UsageKind::Produce { at } | UsageKind::Consume { at } => at,
                UsageKind::Use { to, .. } => to,
            };
            plan.stn.add_constraint(at, before, 1, INF)?;
            if let Some(after) = after {
                plan.stn.add_constraint(after, at, 1, INF)?;
            }
            Ok(())
        }
        Resolver::CapQuantity { action, var, hi } => {
            plan.numeric.narrow(var, f64::NEG_INFINITY, hi)?;
            plan.repropagate_action(action)
        }
        Resolver::RaiseQuantity { action, var, lo } => {
            plan.numeric.narrow(var, lo, f64::INFINITY)?;
            plan.repropagate_action(action)
        }
    }
}
