//! What getting to a goal's place needs of the vehicle's reservoirs, before any search (issue 30: reasons
//! with figures). The domain's motion tasks (a `distance` constraint and a consumption) are inserted, in a
//! root plan of the problem without its goals nor its horizon (the figure is the trip's, whatever the
//! time), as the last leg into the place from wherever the vehicle could come from (any other place within
//! its limits); numeric propagation gives the least that leg consumes. More than the
//! reservoir's capacity cannot be done by any plan (a consumption happens at once, and a level never
//! exceeds the capacity): the goal is rejected at intake with the figure, "getting there needs 1,500 % of
//! the battery", rather than after seconds of search with a planner's dead end.

use super::executive::Executive;
use mavtempo_temporal::model::{Goal, NumConstraint, ObjectId, TaskId, Term, Value};
use mavtempo_temporal::plan::{PartialPlan, UsageKind};

impl Executive {
    /// Why `goal`'s place cannot be reached whatever the plan, with the figure; `None` when it can be
    /// (or the domain has no motion to tell).
    pub(crate) fn trip_beyond_capacity(&self, goal: &Goal) -> Option<String> {
        let place = self.goal_place(goal)?;
        let domain = self.plan.domain().clone();
        let mut problem = (**self.plan.problem()).clone();
        problem.goals.clear();
        problem.horizon = mavtempo_temporal::stn::INF / 4;
        let root = PartialPlan::new(domain.clone(), std::sync::Arc::new(problem)).ok()?;
        let mut worst: Option<(f64, String)> = None;
        let mut any_motion = false;
        let mut reachable = false;
        for (t, task) in domain.tasks.iter().enumerate() {
            let Some((from, to)) = task.numeric.iter().find_map(|c| match c {
                NumConstraint::Distance {
                    a: Term::Var(a),
                    b: Term::Var(b),
                    ..
                } => Some((a.index(), b.index())),
                _ => None,
            }) else {
                continue;
            };
            any_motion = true;
            let mut plan = root.clone();
            let Ok(a) = plan.insert_action(TaskId::from_index(t)) else {
                continue;
            };
            let vars = plan.action(a).vars.clone();
            let (Some(&vf), Some(&vt)) = (vars.get(from), vars.get(to)) else {
                continue;
            };
            if plan.bind_var(vt, place).is_err() || plan.keep_var_off(vf, place).is_err() {
                // No leg into the place stays within the vehicle's limits (Problem::legs).
                continue;
            }
            reachable = true;
            for &u in &plan.action(a).usages {
                let usage = plan.usage(u);
                if !matches!(usage.kind, UsageKind::Consume { .. }) {
                    continue;
                }
                let (least, _) = plan.numeric().term(usage.quantity);
                let res = &domain.resources[usage.resource.index()];
                if res.capacity > 0.0 && least > res.capacity {
                    let pct = 100.0 * least / res.capacity;
                    let why = format!(
                        "getting there needs {} % of the {}",
                        thousands(pct),
                        res.name.to_lowercase()
                    );
                    if worst.as_ref().is_none_or(|(w, _)| pct < *w) {
                        worst = Some((pct, why));
                    }
                } else {
                    // One motion can get there within this reservoir: not this one's limit.
                    return None;
                }
            }
        }
        if any_motion && !reachable {
            return Some("no straight way there stays within the vehicle's limits".into());
        }
        worst.map(|(_, why)| why)
    }

    /// The located object a goal is about: its value (be at L) or an argument (a picture of L).
    fn goal_place(&self, goal: &Goal) -> Option<ObjectId> {
        let p = self.plan.problem();
        let located = |o: ObjectId| p.object(o).and_then(|x| x.position).map(|_| o);
        match goal.value {
            Value::Obj(o) if located(o).is_some() => Some(o),
            _ => goal.args.iter().copied().find_map(located),
        }
    }
}

/// `280`, `1,500`.
fn thousands(v: f64) -> String {
    let s = format!("{:.0}", v);
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}
