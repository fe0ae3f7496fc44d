//! The relaxed-planning-graph estimates of a state (Bonet & Geffner's h_add, Hoffmann & Nebel's h_FF):
//! delete effects, negative conditions and durations ignored, each action the union of its two
//! happenings — its conditions those of its start, plus its `over all` and `at end` conditions that its
//! start does not itself add. h_add sums the cost of each goal computed independently (a Dijkstra over
//! atoms, each action costing 1 plus its conditions' costs); the relaxed plan is extracted backwards from
//! the goals through each atom's cheapest achiever, and h_FF is its number of actions. Its actions that
//! apply in the state are the *helpful* ones (FF's helpful actions, Fast Downward's preferred operators):
//! the search tries them first.
//!
//! A numeric condition is a fact of the relaxation of its own, true where it holds in the state and
//! achieved by every action that can move its variable the way it needs (up for `v >= c` and `v > c`,
//! down for `<=` and `<`; any change of a variable it reads for other shapes). An action that changes a
//! variable by an amount that depends on the state, assigns or scales it may move it either way. Its
//! achievers and their conditions are counted like any other's, so a rover short of energy is estimated
//! to need a recharge; a condition no achiever reaches is a dead end, soundly (nothing else changes it).

use super::shortfall::Shortfall;
use super::{AtomId, GroundTask, NumCond, NumExpr, State};
use crate::pddl::ast::{Cmp, NumOp};

const UNREACHED: u32 = u32::MAX;
const NO_ACTION: u32 = u32::MAX;
/// A cost above any a real relaxed plan reaches, below [`UNREACHED`].
const MAX_COST: u32 = 1 << 20;

/// The per-estimate arrays, kept between estimates so that an estimate allocates nothing.
#[derive(Clone, Debug, Default)]
struct Scratch {
    cost: Vec<u32>,
    supporter: Vec<u32>,
    waiting: Vec<u32>,
    sum: Vec<u32>,
    buckets: Vec<Vec<AtomId>>,
    in_plan: Vec<bool>,
    marked: Vec<bool>,
}

impl Scratch {
    fn reset(&mut self, n_facts: usize, pre: &[Vec<AtomId>]) {
        self.cost.clear();
        self.cost.resize(n_facts, UNREACHED);
        self.supporter.clear();
        self.supporter.resize(n_facts, NO_ACTION);
        self.waiting.clear();
        self.waiting.extend(pre.iter().map(|p| p.len() as u32));
        self.sum.clear();
        self.sum.resize(pre.len(), 0);
        for b in &mut self.buckets {
            b.clear();
        }
    }
}

/// A state's estimates; `None` from [`Relaxed::estimate`] when a goal is not even relaxed-reachable (a dead
/// end: no plan goes through the state).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Estimate {
    pub h_add: u32,
    pub h_ff: u32,
    /// The relaxed plan's actions whose relaxed conditions hold in the state, in action order.
    pub helpful: Vec<u32>,
}

/// The relaxation of a ground task, precomputed once.
#[derive(Clone, Debug)]
pub struct Relaxed {
    /// Buffers reused from one estimate to the next (an estimate per evaluated state).
    scratch: Scratch,
    pre: Vec<Vec<AtomId>>,
    add: Vec<Vec<AtomId>>,
    /// Per atom, the actions that need it.
    users: Vec<Vec<u32>>,
    goal: Vec<AtomId>,
    /// Facts: the task's atoms, then one per distinct numeric condition (`n_atoms + k`).
    n_facts: usize,
    n_atoms: usize,
    conds: Vec<NumCond>,
    /// The resources the relaxed plan may run short of.
    shortfall: Shortfall,
}

/// Which way a numeric condition needs its variable to move, or an action may move one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Way {
    Up,
    Down,
    Either,
}

/// The value of an expression that reads no variable and no `?duration`.
fn constant(e: &NumExpr) -> Option<f64> {
    match e {
        NumExpr::Const(v) => Some(*v),
        NumExpr::Var(_) | NumExpr::Duration => None,
        NumExpr::Neg(x) => constant(x).map(|v| -v),
        NumExpr::Bin(op, x, y) => Some(crate::pddl::ast::arithmetic(
            *op,
            constant(x)?,
            constant(y)?,
        )),
    }
}

/// The variables a numeric condition needs moved and which way (a variable compared with a constant),
/// or every variable it reads, either way.
fn needs(c: &NumCond) -> Vec<(u32, Way)> {
    let flip = |w: Way| match w {
        Way::Up => Way::Down,
        Way::Down => Way::Up,
        Way::Either => Way::Either,
    };
    let way = match c.cmp {
        Cmp::Ge | Cmp::Gt => Way::Up,
        Cmp::Le | Cmp::Lt => Way::Down,
        Cmp::Eq => Way::Either,
    };
    match (&c.lhs, &c.rhs) {
        (NumExpr::Var(v), r) if constant(r).is_some() => vec![(*v, way)],
        (l, NumExpr::Var(v)) if constant(l).is_some() => vec![(*v, flip(way))],
        _ => {
            let mut vars = Vec::new();
            c.lhs.vars(&mut vars);
            c.rhs.vars(&mut vars);
            vars.into_iter().map(|v| (v, Way::Either)).collect()
        }
    }
}

/// Which way an effect may move its variable.
fn moves(op: NumOp, amount: &NumExpr) -> Way {
    let by = |up: bool| match constant(amount) {
        Some(c) if c >= 0.0 => {
            if up {
                Way::Up
            } else {
                Way::Down
            }
        }
        Some(c) if c < 0.0 => {
            if up {
                Way::Down
            } else {
                Way::Up
            }
        }
        _ => Way::Either,
    };
    match op {
        NumOp::Increase => by(true),
        NumOp::Decrease => by(false),
        NumOp::Assign | NumOp::ScaleUp | NumOp::ScaleDown => Way::Either,
    }
}

impl Relaxed {
    pub fn new(task: &GroundTask) -> Self {
        let n_atoms = task.atoms.len();
        let mut conds: Vec<NumCond> = Vec::new();
        // Keyed by their text: f64 has no Hash, and a constant is written exactly by Debug.
        let mut known: std::collections::HashMap<String, usize> = Default::default();
        let mut cond_of = |c: &NumCond| -> AtomId {
            let k = *known.entry(format!("{c:?}")).or_insert_with(|| {
                conds.push(c.clone());
                conds.len() - 1
            });
            (n_atoms + k) as AtomId
        };
        let mut num_pre: Vec<Vec<AtomId>> = Vec::with_capacity(task.actions.len());
        for a in &task.actions {
            let all = a
                .start
                .pre
                .num
                .iter()
                .chain(&a.over_all.num)
                .chain(&a.end.pre.num);
            num_pre.push(all.map(&mut cond_of).collect());
        }
        let n_facts = n_atoms + conds.len();
        let wanted: Vec<Vec<(u32, Way)>> = conds.iter().map(needs).collect();
        let mut pre = Vec::with_capacity(task.actions.len());
        let mut add = Vec::with_capacity(task.actions.len());
        let mut users = vec![Vec::new(); n_facts];
        for (i, a) in task.actions.iter().enumerate() {
            let mut p: Vec<AtomId> = a.start.pre.pos.clone();
            p.extend(&num_pre[i]);
            p.extend(
                a.over_all
                    .pos
                    .iter()
                    .chain(&a.end.pre.pos)
                    .filter(|x| !a.start.add.contains(x)),
            );
            p.sort_unstable();
            p.dedup();
            for &x in &p {
                if let Some(u) = users.get_mut(x as usize) {
                    u.push(i as u32);
                }
            }
            let mut e: Vec<AtomId> = a.start.add.iter().chain(&a.end.add).copied().collect();
            for eff in a.start.num.iter().chain(&a.end.num) {
                let way = moves(eff.op, &eff.expr);
                for (k, w) in wanted.iter().enumerate() {
                    let helps = w.iter().any(|&(v, need)| {
                        v == eff.var && (way == Way::Either || need == Way::Either || way == need)
                    });
                    if helps {
                        e.push((n_atoms + k) as AtomId);
                    }
                }
            }
            e.sort_unstable();
            e.dedup();
            pre.push(p);
            add.push(e);
        }
        let mut goal = task.goal.pos.clone();
        goal.sort_unstable();
        goal.dedup();
        Relaxed {
            scratch: Scratch::default(),
            pre,
            add,
            users,
            goal,
            n_facts,
            n_atoms,
            conds,
            shortfall: Shortfall::new(task),
        }
    }

    /// h_add, h_FF and the helpful actions of `state`.
    pub fn estimate(&mut self, state: &State) -> Option<Estimate> {
        let n = self.n_facts;
        let mut sc = std::mem::take(&mut self.scratch);
        sc.reset(n, &self.pre);
        let Scratch {
            cost,
            supporter,
            waiting,
            sum,
            buckets,
            ..
        } = &mut sc;
        // Costs are small integers that only grow as facts are settled: a bucket queue (Dial's Dijkstra)
        // instead of a heap.
        let push = |buckets: &mut Vec<Vec<AtomId>>, c: u32, a: AtomId| {
            let c = c as usize;
            if buckets.len() <= c {
                buckets.resize_with(c + 1, Vec::new);
            }
            buckets[c].push(a);
        };
        for a in 0..self.n_atoms as AtomId {
            if state.has(a) {
                cost[a as usize] = 0;
                push(buckets, 0, a);
            }
        }
        for (k, c) in self.conds.iter().enumerate() {
            let (x, y) = (
                c.lhs.eval(&state.nums, f64::NAN),
                c.rhs.eval(&state.nums, f64::NAN),
            );
            if c.cmp.holds(x, y) {
                cost[self.n_atoms + k] = 0;
                push(buckets, 0, (self.n_atoms + k) as AtomId);
            }
        }
        let mut goals_left = self.goal.iter().filter(|g| !state.has(**g)).count();
        let fire = |act: usize,
                    c: u32,
                    cost: &mut Vec<u32>,
                    supporter: &mut Vec<u32>,
                    buckets: &mut Vec<Vec<AtomId>>| {
            // Capped well below UNREACHED so that the bucket index stays small on absurd sums.
            let c = c.saturating_add(1).min(MAX_COST);
            for &p in &self.add[act] {
                if c < cost[p as usize] {
                    cost[p as usize] = c;
                    supporter[p as usize] = act as u32;
                    push(buckets, c, p);
                }
            }
        };
        for (act, _) in self.pre.iter().enumerate().filter(|(_, p)| p.is_empty()) {
            // An action without conditions fires at once.
            fire(act, 0, cost, supporter, buckets);
        }
        let mut level = 0usize;
        'settle: while level < buckets.len() {
            while let Some(a) = buckets[level].pop() {
                let i = a as usize;
                let c = level as u32;
                if c != cost[i] {
                    continue; // settled at a lower cost already
                }
                if self.goal.binary_search(&a).is_ok() && c > 0 {
                    goals_left -= 1;
                    // With resources, the producers that cover a shortfall need their costs too.
                    if goals_left == 0 && !self.shortfall.any() {
                        break 'settle;
                    }
                }
                for &act in &self.users[i] {
                    let act = act as usize;
                    waiting[act] -= 1;
                    sum[act] = sum[act].saturating_add(c);
                    if waiting[act] == 0 {
                        fire(act, sum[act], cost, supporter, buckets);
                    }
                }
            }
            level += 1;
        }
        let out = self.extract(&mut sc, state);
        self.scratch = sc;
        out
    }

    /// h_add from the costs in `sc`, and the relaxed plan extracted from its supporters, with the
    /// producers that cover its resource shortfall in `state` ([`Shortfall`]).
    fn extract(&self, sc: &mut Scratch, state: &State) -> Option<Estimate> {
        let mut h_add = 0u32;
        for &g in &self.goal {
            match sc.cost[g as usize] {
                UNREACHED => return None,
                c => h_add = h_add.saturating_add(c),
            }
        }
        sc.in_plan.clear();
        sc.in_plan.resize(self.pre.len(), false);
        sc.marked.clear();
        sc.marked.resize(self.n_facts, false);
        let mut plan: Vec<u32> = Vec::new();
        self.support(sc, self.goal.clone(), &mut plan);
        // Applications of a producer beyond the one the plan holds.
        let mut repeats = 0u32;
        // Producers the shortfall adds that are not worth applying in this state: not helpful.
        let mut not_now: Vec<u32> = Vec::new();
        if self.shortfall.any() {
            let action_cost = |act: u32| {
                let i = act as usize;
                (sc.waiting.get(i) == Some(&0)).then(|| sc.sum[i].saturating_add(1))
            };
            for added in self.shortfall.cover(&plan, state, action_cost) {
                let act = added.action as usize;
                if sc.in_plan[act] {
                    repeats = repeats.saturating_add(added.times);
                } else {
                    if !added.worth_now {
                        not_now.push(added.action);
                    }
                    repeats = repeats.saturating_add(added.times - 1);
                    sc.in_plan[act] = true;
                    plan.push(added.action);
                    self.support(sc, self.pre[act].clone(), &mut plan);
                }
            }
        }
        let h_ff = (plan.len() as u32).saturating_add(repeats);
        plan.sort_unstable();
        let helpful = plan
            .iter()
            .copied()
            .filter(|&act| {
                self.pre[act as usize]
                    .iter()
                    .all(|&p| sc.cost[p as usize] == 0)
                    && !not_now.contains(&act)
            })
            .collect();
        Some(Estimate {
            h_add,
            h_ff,
            helpful,
        })
    }

    /// Extends relaxed plan `plan` with each open fact's cheapest achiever, and that achiever's
    /// conditions in turn, from `stack`.
    fn support(&self, sc: &mut Scratch, mut stack: Vec<AtomId>, plan: &mut Vec<u32>) {
        while let Some(a) = stack.pop() {
            let i = a as usize;
            if sc.marked[i] || sc.cost[i] == 0 {
                continue;
            }
            sc.marked[i] = true;
            let act = sc.supporter[i];
            if act == NO_ACTION || sc.in_plan[act as usize] {
                continue;
            }
            sc.in_plan[act as usize] = true;
            plan.push(act);
            stack.extend(&self.pre[act as usize]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Cond, GroundAction};
    use super::*;

    fn action(
        name: &str,
        pre: &[AtomId],
        start_add: &[AtomId],
        end_add: &[AtomId],
    ) -> GroundAction {
        let mut a = super::super::test_tasks::action(
            name,
            pre.to_vec(),
            Vec::new(),
            start_add.to_vec(),
            Vec::new(),
        );
        a.end.add = end_add.to_vec();
        a
    }

    /// Atoms a=0, b=1, g=2, c=3 (never reached). `get-a`: ∅ → a (cost 1); `a-to-b`: a → b (1 + 1 = 2);
    /// `finish`: a, b → g (1 + 1 + 2 = 4); `shortcut`: c → g never applies. Goal g.
    fn tiny() -> GroundTask {
        GroundTask {
            atoms: vec!["a".into(), "b".into(), "g".into(), "c".into()],
            init: Vec::new(),
            goal: Cond {
                pos: vec![2],
                ..Cond::default()
            },
            actions: vec![
                action("get-a", &[], &[], &[0]),
                action("a-to-b", &[0], &[1], &[]),
                action("finish", &[0, 1], &[], &[2]),
                action("shortcut", &[3], &[2], &[]),
            ],
            ..GroundTask::default()
        }
    }

    #[test]
    fn hand_computed_values_on_a_tiny_problem() {
        let t = tiny();
        let mut r = Relaxed::new(&t);
        let e = r.estimate(&t.initial_state()).expect("g is reachable");
        // h_add counts a twice (once under finish, once under a-to-b): 1 + 2 + 1 = 4; h_FF counts each
        // action of the relaxed plan once: get-a, a-to-b, finish.
        assert_eq!(e.h_add, 4);
        assert_eq!(e.h_ff, 3);
        assert_eq!(e.helpful, vec![0], "only get-a applies in the empty state");
        // With a true: a-to-b (cost 1) then finish (1 + 0 + 1 = 2).
        let mut s = t.initial_state();
        s.set(0, true);
        let e = r.estimate(&s).expect("reachable");
        assert_eq!((e.h_add, e.h_ff, e.helpful), (2, 2, vec![1]));
        s.set(2, true);
        assert_eq!(r.estimate(&s).map(|e| (e.h_add, e.h_ff)), Some((0, 0)));
    }

    #[test]
    fn an_end_condition_its_own_start_adds_costs_nothing_and_unreachable_goals_are_dead_ends() {
        let mut t = tiny();
        // `self-help` needs b at its end, which its start adds: relaxed, it needs nothing and gives g.
        let mut a = action("self-help", &[], &[1], &[2]);
        a.end.pre.pos.push(1);
        t.actions.push(a);
        let e = Relaxed::new(&t)
            .estimate(&t.initial_state())
            .expect("reachable");
        assert_eq!((e.h_add, e.h_ff, e.helpful), (1, 1, vec![4]));
        t.goal.pos = vec![3];
        assert_eq!(Relaxed::new(&t).estimate(&t.initial_state()), None);
    }
}
