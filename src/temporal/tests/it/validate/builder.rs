//! A test-side plan builder: actions from the domain's tasks, constraints, causal links and goals, with
//! the windows computed by a plain Floyd-Warshall (the test's own oracle, independent of the checker).

use mavtempo_temporal::model::{Domain, GoalId, Problem, Term, Time, Value};
use mavtempo_temporal::plan::solution::{
    CausalLink, Consumer, Establisher, NumBounds, PlanAction, PlanActionId, PlanConstraint,
    PlanGoal, PlanTerm, PlanTp, PlanVar, PlanVarId, Solution, Timepoint,
};

pub struct Builder<'a> {
    pub d: &'a Domain,
    pub p: &'a Problem,
    pub s: Solution,
}

fn plan_value(v: Value) -> PlanTerm {
    match v {
        Value::Obj(o) => PlanTerm::Obj(o),
        Value::Unknown => PlanTerm::Unknown,
    }
}

impl<'a> Builder<'a> {
    /// Only the origin; every goal of the problem unachieved until [`Builder::goal`].
    pub fn new(d: &'a Domain, p: &'a Problem) -> Self {
        let mut s = Solution {
            domain: d.name.clone(),
            problem: p.name.clone(),
            ..Solution::default()
        };
        s.timepoints.push(Timepoint {
            id: PlanTp::ORIGIN,
            name: "origin".into(),
            lb: Some(0),
            ub: Some(0),
        });
        s.goals = p
            .goals
            .iter()
            .enumerate()
            .map(|(i, g)| PlanGoal {
                goal: GoalId::from_index(i),
                name: g.name.clone(),
                achieved: false,
                start: None,
                end: None,
                reason: Some("not planned in this test".into()),
            })
            .collect();
        Builder { d, p, s }
    }

    pub fn tp(&mut self, name: String) -> PlanTp {
        let id = PlanTp(self.s.timepoints.len() as u32);
        self.s.timepoints.push(Timepoint {
            id,
            name,
            lb: None,
            ub: None,
        });
        id
    }

    pub fn constrain(&mut self, from: PlanTp, to: PlanTp, lb: Option<Time>, ub: Option<Time>) {
        self.s.constraints.push(PlanConstraint { from, to, lb, ub });
    }

    /// `b` strictly after `a` (seed 1's `]0, +oo[` precedence).
    pub fn before(&mut self, a: PlanTp, b: PlanTp) {
        self.constrain(a, b, Some(1), None);
    }

    /// An action of task `task`; `args` bind the first symbolic variables by object name, the rest become
    /// plan variables over every object of their type. Adds the task's temporal constraints.
    pub fn action(&mut self, task: &str, args: &[&str]) -> PlanActionId {
        let tid = self.d.task_id(task).expect("test task");
        let t = self.d.task(tid);
        let id = PlanActionId(self.s.actions.len() as u32 + 1);
        let name = format!("a{}", id.0);
        let mut plan_args = Vec::new();
        for (i, v) in t.sym_vars.iter().enumerate() {
            if let Some(o) = args.get(i) {
                plan_args.push(PlanTerm::Obj(self.p.object_id(o).expect("test object")));
            } else {
                let var = PlanVarId(self.s.variables.len() as u32);
                self.s.variables.push(PlanVar {
                    id: var,
                    name: format!("{name}.?{}", v.name),
                    domain: self.p.objects_of(v.ty),
                });
                plan_args.push(PlanTerm::Var(var));
            }
        }
        let tps: Vec<PlanTp> = t
            .timepoints
            .iter()
            .map(|tp| format!("{name}.{tp}"))
            .collect::<Vec<_>>()
            .into_iter()
            .map(|n| self.tp(n))
            .collect();
        for c in &t.temporal {
            let (from, to) = (tps[c.from.index()], tps[c.to.index()]);
            self.constrain(from, to, c.interval.min_ms(), c.interval.max_ms());
        }
        self.s.actions.push(PlanAction {
            id,
            name,
            task_name: t.name.clone(),
            task: tid,
            args: plan_args,
            timepoints: tps,
            num_vars: vec![NumBounds { lo: None, hi: None }; t.num_vars.len()],
        });
        id
    }

    pub fn act(&self, id: PlanActionId) -> &PlanAction {
        self.s.action(id).expect("test action")
    }

    pub fn st(&self, id: PlanActionId) -> PlanTp {
        let a = self.act(id);
        a.timepoints[self.d.task(a.task).start.index()]
    }

    pub fn et(&self, id: PlanActionId) -> PlanTp {
        let a = self.act(id);
        a.timepoints[self.d.task(a.task).end.index()]
    }

    fn term(&self, id: PlanActionId, t: Term) -> PlanTerm {
        match t {
            Term::Obj(o) => PlanTerm::Obj(o),
            Term::Unknown => PlanTerm::Unknown,
            Term::Var(v) => self.act(id).args[v.index()],
        }
    }

    /// A causal link to `consumer`, its proposition read from the consumer, its start from `establisher`.
    pub fn link(&mut self, establisher: Establisher, consumer: Consumer) {
        let (attr, args, value, to) = match consumer {
            Consumer::Hold { action, hold } => {
                let h = &self.d.task(self.act(action).task).holds[hold];
                let args = h.args.iter().map(|&t| self.term(action, t)).collect();
                let to = self.act(action).timepoints[h.to.index()];
                (h.attr, args, self.term(action, h.value), to)
            }
            Consumer::EventFrom { action, event } => {
                let e = &self.d.task(self.act(action).task).events[event];
                let args = e.args.iter().map(|&t| self.term(action, t)).collect();
                let to = self.act(action).timepoints[e.at.index()];
                (e.attr, args, self.term(action, e.from), to)
            }
            Consumer::Goal { goal } => {
                let g = &self.p.goals[goal.index()];
                let args = g.args.iter().map(|&o| PlanTerm::Obj(o)).collect();
                let to = self.s.goals[goal.index()].end.expect("goal placed first");
                (g.attr, args, plan_value(g.value), to)
            }
        };
        let from = match establisher {
            Establisher::Event { action, event } => {
                let e = &self.d.task(self.act(action).task).events[event];
                self.act(action).timepoints[e.at.index()]
            }
            _ => PlanTp::ORIGIN,
        };
        self.s.causal_links.push(CausalLink {
            establisher,
            consumer,
            attr,
            args,
            value,
            from,
            to,
        });
    }

    /// Places goal `name` (I^g and I^d as constraints) strictly after `after`, marked achieved.
    pub fn goal(&mut self, name: &str, after: PlanTp) -> GoalId {
        let gid = self.p.goal_id(name).expect("test goal");
        let g = &self.p.goals[gid.index()];
        let (sw, dur) = (g.start_window, g.duration);
        let st = self.tp(format!("{name}.st"));
        let et = self.tp(format!("{name}.et"));
        self.constrain(PlanTp::ORIGIN, st, sw.min_ms(), sw.max_ms());
        self.constrain(st, et, dur.min_ms(), dur.max_ms());
        self.before(after, st);
        let pg = &mut self.s.goals[gid.index()];
        pg.achieved = true;
        pg.start = Some(st);
        pg.end = Some(et);
        pg.reason = None;
        gid
    }

    /// A causal link from event `event` of `from` to hold `hold` of `to`.
    pub fn event_to_hold(
        &mut self,
        from: PlanActionId,
        event: usize,
        to: PlanActionId,
        hold: usize,
    ) {
        self.link(
            Establisher::Event {
                action: from,
                event,
            },
            Consumer::Hold { action: to, hold },
        );
    }

    /// Places goal `name` after `after` (as [`Builder::goal`]), supported by event `event` of `action`.
    pub fn achieve(
        &mut self,
        name: &str,
        after: PlanTp,
        action: PlanActionId,
        event: usize,
    ) -> GoalId {
        let goal = self.goal(name, after);
        self.link(
            Establisher::Event { action, event },
            Consumer::Goal { goal },
        );
        goal
    }

    /// Every timepoint within the horizon, then the windows by Floyd-Warshall.
    pub fn finish(mut self) -> Solution {
        for i in 1..self.s.timepoints.len() {
            self.constrain(
                PlanTp::ORIGIN,
                PlanTp(i as u32),
                Some(0),
                Some(self.p.horizon),
            );
        }
        if let Some((lb, ub)) = windows(&self.s) {
            for (t, (l, u)) in self.s.timepoints.iter_mut().zip(lb.into_iter().zip(ub)) {
                t.lb = Some(l);
                t.ub = u;
            }
        }
        self.s
    }
}

const INF: i64 = i64::MAX / 4;

/// Floyd-Warshall windows (`None` when inconsistent).
pub fn windows(s: &Solution) -> Option<(Vec<Time>, Vec<Option<Time>>)> {
    let n = s.timepoints.len();
    let mut d = vec![vec![INF; n]; n];
    for (i, row) in d.iter_mut().enumerate() {
        row[i] = 0;
    }
    for c in &s.constraints {
        let (f, t) = (c.from.index(), c.to.index());
        if let Some(ub) = c.ub {
            d[f][t] = d[f][t].min(ub);
        }
        if let Some(lb) = c.lb {
            d[t][f] = d[t][f].min(-lb);
        }
    }
    for k in 0..n {
        for i in 0..n {
            for j in 0..n {
                if d[i][k] < INF && d[k][j] < INF && d[i][k] + d[k][j] < d[i][j] {
                    d[i][j] = d[i][k] + d[k][j];
                }
            }
        }
    }
    if (0..n).any(|i| d[i][i] < 0) {
        return None;
    }
    let lb = (0..n)
        .map(|i| if d[i][0] >= INF { 0 } else { (-d[i][0]).max(0) })
        .collect();
    let ub = (0..n).map(|i| (d[0][i] < INF).then_some(d[0][i])).collect();
    Some((lb, ub))
}
