//! From the partial plan to the plain-data [`Solution`] (what `mavtempo plan` prints and the checker reads).

use std::collections::HashMap;

use super::solution::{
    self, Consumer, Establisher, NumBounds, PlanConstraint, PlanTerm, PlanTp, PlanVar, PlanVarId,
    Solution,
};
use super::{CondKind, EventId, Owner, PartialPlan, STerm};
use crate::model::Value;
use crate::stn::{Time, INF};

fn opt_lb(t: Time) -> Option<Time> {
    (t > -INF).then_some(t)
}

fn opt_ub(t: Time) -> Option<Time> {
    (t < INF).then_some(t)
}

fn opt_f(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl PartialPlan {
    /// The plan as a [`Solution`]. `reasons` gives why goals are not achieved (e.g. the search's failure);
    /// an unsupported goal without a reason is reported as an open condition.
    pub fn to_solution(&self, reasons: &HashMap<crate::model::GoalId, String>) -> Solution {
        let d = &self.domain;
        let p = &self.problem;
        let mut names: Vec<String> = (0..self.stn.num_timepoints())
            .map(|i| format!("t{i}"))
            .collect();
        names[0] = "origin".into();
        for a in self.live_actions() {
            let act = self.action(a);
            let task = d.task(act.task);
            for (k, &tp) in act.tps.iter().enumerate() {
                names[tp.index()] = format!("a{}.{}", a.0, task.timepoints[k]);
            }
        }
        for g in self.goals.iter().filter(|g| g.active) {
            let name = &p.goals[g.goal.index()].name;
            names[g.st.index()] = format!("{name}.st");
            names[g.et.index()] = format!("{name}.et");
        }
        for e in &self.events {
            if let Owner::Exogenous(i) = e.owner {
                names[e.at.index()] = format!("timed{i}");
            }
        }
        let timepoints = self
            .stn
            .timepoints()
            .map(|t| solution::Timepoint {
                id: PlanTp(t.index() as u32),
                name: names[t.index()].clone(),
                lb: opt_lb(self.stn.lb(t)),
                ub: opt_ub(self.stn.ub(t)),
            })
            .collect();
        let constraints = self
            .stn
            .constraints()
            .map(|(_, c)| PlanConstraint {
                from: PlanTp(c.from.index() as u32),
                to: PlanTp(c.to.index() as u32),
                lb: opt_lb(c.lb),
                ub: opt_ub(c.ub),
            })
            .collect();
        // One solution variable per unbound class of the binding CSP.
        let mut class_var: HashMap<u32, PlanVarId> = HashMap::new();
        let mut variables: Vec<PlanVar> = Vec::new();
        let mut term = |t: STerm, name: &dyn Fn() -> String| -> PlanTerm {
            match self.bindings.value(t) {
                Some(Value::Obj(o)) => PlanTerm::Obj(o),
                Some(Value::Unknown) => PlanTerm::Unknown,
                None => {
                    let STerm::Var(v) = t else {
                        return PlanTerm::Unknown;
                    };
                    let root = self.bindings.class_of(v);
                    let id = *class_var.entry(root).or_insert_with(|| {
                        let id = PlanVarId(variables.len() as u32);
                        variables.push(PlanVar {
                            id,
                            name: name(),
                            domain: self.bindings.domain(v).to_vec(),
                        });
                        id
                    });
                    PlanTerm::Var(id)
                }
            }
        };
        let mut actions = Vec::new();
        for a in self.live_actions() {
            let act = self.action(a);
            let task = d.task(act.task);
            let args = act
                .vars
                .iter()
                .enumerate()
                .map(|(k, &v)| {
                    term(STerm::Var(v), &|| {
                        format!("a{}.?{}", a.0, task.sym_vars[k].name)
                    })
                })
                .collect();
            let num_vars = act
                .nums
                .iter()
                .map(|&n| {
                    let (lo, hi) = self.numeric.bounds(n);
                    NumBounds {
                        lo: opt_f(lo),
                        hi: opt_f(hi),
                    }
                })
                .collect();
            actions.push(solution::PlanAction {
                id: solution::PlanActionId(a.0),
                name: format!("a{}", a.0),
                task_name: task.name.clone(),
                task: act.task,
                args,
                timepoints: act.tps.iter().map(|t| PlanTp(t.index() as u32)).collect(),
                num_vars,
            });
        }
        let mut different = Vec::new();
        for (x, y) in self.bindings.ne_pairs() {
            let (tx, ty) = (
                term(STerm::Var(x), &|| format!("?v{}", x.0)),
                term(STerm::Var(y), &|| format!("?v{}", y.0)),
            );
            if let (PlanTerm::Var(a), PlanTerm::Var(b)) = (tx, ty) {
                different.push((a, b));
            }
        }
        let mut causal_links = Vec::new();
        for l in &self.links {
            if !l.active || !self.cond_live(l.cond) {
                continue;
            }
            let Some(establisher) = self.establisher(l.event) else {
                continue;
            };
            let cond = self.cond(l.cond);
            let consumer = match (cond.owner, cond.kind) {
                (Owner::Goal(goal), _) => Consumer::Goal { goal },
                (Owner::Action(a), CondKind::Before(e)) => {
                    let Some(k) = self.action(a).events.iter().position(|&x| x == e) else {
                        continue;
                    };
                    Consumer::EventFrom {
                        action: solution::PlanActionId(a.0),
                        event: k,
                    }
                }
                (Owner::Action(a), CondKind::Hold { .. }) => {
                    let act = self.action(a);
                    let Some(k) = act.conds.iter().position(|&x| x == l.cond) else {
                        continue;
                    };
                    Consumer::Hold {
                        action: solution::PlanActionId(a.0),
                        hold: k - act.events.len(),
                    }
                }
                _ => continue,
            };
            causal_links.push(solution::CausalLink {
                establisher,
                consumer,
                attr: cond.attr,
                args: cond.args.iter().map(|&t| term(t, &|| "?".into())).collect(),
                value: term(cond.value, &|| "?".into()),
                from: PlanTp(self.event(l.event).at.index() as u32),
                to: PlanTp(cond.to.index() as u32),
            });
        }
        let goals = p
            .goals
            .iter()
            .enumerate()
            .map(|(i, g)| {
                let gid = crate::model::GoalId::from_index(i);
                let pg = self.goals.iter().find(|pg| pg.goal == gid && pg.active);
                let achieved = pg.is_some_and(|pg| self.cond(pg.cond).link.is_some());
                let reason = (!achieved).then(|| {
                    reasons.get(&gid).cloned().unwrap_or_else(|| match pg {
                        Some(_) => "open condition (not supported)".into(),
                        None => "not in the plan (rejected)".into(),
                    })
                });
                solution::PlanGoal {
                    goal: gid,
                    name: g.name.clone(),
                    achieved,
                    start: pg.map(|pg| PlanTp(pg.st.index() as u32)),
                    end: pg.map(|pg| PlanTp(pg.et.index() as u32)),
                    reason,
                }
            })
            .collect();
        Solution {
            domain: d.name.clone(),
            problem: p.name.clone(),
            timepoints,
            constraints,
            variables,
            different,
            actions,
            causal_links,
            goals,
        }
    }

    /// Where an event comes from, in the solution's terms (`None` for a removed action's event).
    fn establisher(&self, e: EventId) -> Option<Establisher> {
        match self.event(e).owner {
            Owner::Initial => Some(Establisher::Initial),
            Owner::Exogenous(index) => Some(Establisher::Timed { index }),
            Owner::Action(a) => {
                let act = self.action(a);
                if act.removed {
                    return None;
                }
                let k = act.events.iter().position(|&x| x == e)?;
                Some(Establisher::Event {
                    action: solution::PlanActionId(a.0),
                    event: k,
                })
            }
            Owner::Goal(_) => None,
        }
    }
}
