//! Structural checks: every index of the solution points into the domain, the problem or the solution
//! itself, and every action fits its task. Later checks rely on these.

use std::collections::HashSet;

use crate::model::{Domain, GoalId, Problem, Task};
use crate::plan::solution::{
    CausalLink, Consumer, Establisher, PlanActionId, PlanTerm, PlanTp, Solution,
};

use super::Violation;

pub(super) fn check(d: &Domain, p: &Problem, s: &Solution) -> Vec<Violation> {
    let mut out = Vec::new();
    let mut bad = |msg: String| out.push(Violation::Malformed(msg));
    if s.domain != d.name || s.problem != p.name {
        bad(format!(
            "a plan for {}/{} checked against {}/{}",
            s.domain, s.problem, d.name, p.name
        ));
    }
    let n = s.timepoints.len();
    if n == 0 {
        bad("no timepoints (the origin is timepoint 0)".into());
    }
    for (i, t) in s.timepoints.iter().enumerate() {
        if t.id.index() != i {
            bad(format!("timepoint {} is listed at position {i}", t.name));
        }
    }
    let tp_ok = |t: PlanTp| t.index() < n;
    for c in &s.constraints {
        if !tp_ok(c.from) || !tp_ok(c.to) {
            bad(format!("constraint {:?} names an unknown timepoint", c));
        }
    }
    let nv = s.variables.len();
    for (i, v) in s.variables.iter().enumerate() {
        if v.id.index() != i {
            bad(format!("variable {} is listed at position {i}", v.name));
        }
        if let Some(o) = v.domain.iter().find(|o| o.index() >= p.objects.len()) {
            bad(format!(
                "variable {} has unknown object {} in its domain",
                v.name, o.0
            ));
        }
    }
    for (a, b) in &s.different {
        if a.index() >= nv || b.index() >= nv {
            bad(format!(
                "≠ constraint between unknown variables {} and {}",
                a.0, b.0
            ));
        }
    }
    let term_ok = |t: &PlanTerm| match t {
        PlanTerm::Obj(o) => o.index() < p.objects.len(),
        PlanTerm::Var(v) => v.index() < nv,
        PlanTerm::Unknown => true,
    };
    let mut ids = HashSet::new();
    for a in &s.actions {
        if !ids.insert(a.id) {
            bad(format!("action id {} used twice", a.id.0));
        }
        let Some(task) = d.tasks.get(a.task.index()) else {
            bad(format!("action {}: unknown task {}", a.name, a.task.0));
            continue;
        };
        if task.name != a.task_name {
            bad(format!(
                "action {}: task {} is named {}, not {}",
                a.name, a.task.0, task.name, a.task_name
            ));
        }
        // (what the action has, what the task declares, how many of each, none dangling)
        let arities = [
            (
                "arguments",
                "symbolic variables",
                a.args.len(),
                task.sym_vars.len(),
                a.args.iter().all(term_ok),
            ),
            (
                "timepoints",
                "timepoints",
                a.timepoints.len(),
                task.timepoints.len(),
                a.timepoints.iter().all(|&t| tp_ok(t)),
            ),
            (
                "numeric variables",
                "numeric variables",
                a.num_vars.len(),
                task.num_vars.len(),
                true,
            ),
        ];
        for (has, declared, n, m, resolved) in arities {
            if n != m {
                bad(format!(
                    "action {}: {n} {has} for the {m} {declared} of {}",
                    a.name, task.name
                ));
            } else if !resolved {
                bad(format!("action {}: a dangling one of its {has}", a.name));
            }
        }
    }
    for (i, l) in s.causal_links.iter().enumerate() {
        if let Err(msg) = link_ok(d, p, s, l) {
            bad(format!("causal link #{i}: {msg}"));
        }
        if !tp_ok(l.from) || !tp_ok(l.to) || !l.args.iter().all(term_ok) || !term_ok(&l.value) {
            bad(format!("causal link #{i}: dangling timepoint or term"));
        }
    }
    let mut seen = HashSet::new();
    for g in &s.goals {
        if g.goal.index() >= p.goals.len() {
            bad(format!("goal {}: unknown goal id {}", g.name, g.goal.0));
        }
        seen.insert(g.goal);
        if g.start.is_some_and(|t| !tp_ok(t)) || g.end.is_some_and(|t| !tp_ok(t)) {
            bad(format!("goal {}: dangling timepoint", g.name));
        }
    }
    for (i, g) in p.goals.iter().enumerate() {
        if !seen.contains(&GoalId::from_index(i)) {
            bad(format!(
                "goal {} of the problem is missing from the solution",
                g.name
            ));
        }
    }
    out
}

/// A reference of a causal link to nothing.
#[derive(Debug, thiserror::Error)]
enum Dangling {
    #[error("unknown attribute {0}")]
    Attr(u32),
    #[error("unknown timed fact #{0}")]
    Timed(usize),
    #[error("unknown action id {0}")]
    Action(u32),
    #[error("action {action} has no {what} #{index}")]
    Part {
        action: String,
        what: &'static str,
        index: usize,
    },
    #[error("unknown goal id {0}")]
    Goal(u32),
}

/// The link's establisher and consumer exist (their contents are compared later, over time).
fn link_ok(d: &Domain, p: &Problem, s: &Solution, l: &CausalLink) -> Result<(), Dangling> {
    if l.attr.index() >= d.attrs.len() {
        return Err(Dangling::Attr(l.attr.0));
    }
    match l.establisher {
        Establisher::Initial => {}
        Establisher::Timed { index } => {
            if index >= p.exogenous.len() {
                return Err(Dangling::Timed(index));
            }
        }
        Establisher::Event { action, event } => {
            part(d, s, action, event, "event", |t| t.events.len())?
        }
    }
    match l.consumer {
        Consumer::Hold { action, hold } => part(d, s, action, hold, "hold", |t| t.holds.len())?,
        Consumer::EventFrom { action, event } => {
            part(d, s, action, event, "event", |t| t.events.len())?
        }
        Consumer::Goal { goal } => {
            if goal.index() >= p.goals.len() {
                return Err(Dangling::Goal(goal.0));
            }
        }
    }
    Ok(())
}

/// Action `action` exists and its task has a `what` number `index` (`count` of them).
fn part(
    d: &Domain,
    s: &Solution,
    action: PlanActionId,
    index: usize,
    what: &'static str,
    count: impl Fn(&Task) -> usize,
) -> Result<(), Dangling> {
    let a = s.action(action).ok_or(Dangling::Action(action.0))?;
    if index >= d.tasks.get(a.task.index()).map_or(0, count) {
        return Err(Dangling::Part {
            action: a.name.clone(),
            what,
            index,
        });
    }
    Ok(())
}
