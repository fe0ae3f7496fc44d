//! Nothing loops: what plan repair and complete replanning cannot fix is detected and settled.
//!
//! Seed 1 repairs and replans whenever the plan stops being executable; it says nothing about the same
//! failure coming back. On a real vehicle it does (a model that disagrees with the vehicle, a missing
//! binding, a camera that always fails): the same action instance is inserted, launched and fails again,
//! forever. Two bounds settle it:
//! - an action instance (task and grounded arguments) failing the same way `k` times in a row is *banned*:
//!   it is never launched again, a complete replanning does not adopt a plan that needs it, and the goals
//!   that depended on it are rejected with that failure as the reason;
//! - plan changes (repairs and complete replannings) are counted per minute of mission time; past the bound,
//!   a goal is rejected (those served by the most failing action first) with the count as the reason.

use std::collections::{BTreeMap, BTreeSet, VecDeque};

use mavtempo_temporal::model::{GoalId, Time};
use mavtempo_temporal::plan::{ActionId, Owner, PartialPlan, STerm};

/// A grounded action instance: the task's name and its arguments' names (`?` when unbound).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Instance {
    pub task: String,
    pub args: Vec<String>,
}

impl Instance {
    pub fn of(plan: &PartialPlan, a: ActionId) -> Self {
        let act = plan.action(a);
        let task = plan.domain().task(act.task);
        let args = act.vars[..task.n_params]
            .iter()
            .map(|&v| match plan.bindings().value(STerm::Var(v)) {
                Some(_) => plan.term_name(STerm::Var(v)),
                None => "?".into(),
            })
            .collect();
        Instance {
            task: task.name.clone(),
            args,
        }
    }

    /// Whether action `a` of `plan` may be this instance (its unbound arguments may take these values).
    pub fn possibly(&self, plan: &PartialPlan, a: ActionId) -> bool {
        let act = plan.action(a);
        let task = plan.domain().task(act.task);
        if task.name != self.task {
            return false;
        }
        act.vars[..task.n_params]
            .iter()
            .zip(&self.args)
            .all(|(&v, name)| match plan.problem().object_id(name) {
                Some(o) => plan.bindings().possibly_equal(STerm::Var(v), STerm::Obj(o)),
                None => false,
            })
    }
}

impl std::fmt::Display for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}({})", self.task, self.args.join(", "))
    }
}

/// How an action instance failed; two failures are "the same way" when their kinds are equal.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FailureKind(String);

impl FailureKind {
    /// Digits are dropped so that the same failure with another measured value is still the same.
    pub fn new(text: &str) -> Self {
        let mut s = String::with_capacity(text.len());
        for c in text.chars() {
            let c = if c.is_ascii_digit() || c == '.' {
                '#'
            } else {
                c
            };
            if !(c == '#' && s.ends_with('#')) {
                s.push(c);
            }
        }
        FailureKind(s)
    }
}

/// A plan change that counts toward the rate bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanChangeKind {
    Repair,
    Replan,
}

/// The memory of failures and plan changes of one mission.
#[derive(Clone, Debug)]
pub struct FailureMemory {
    /// Same-way failures in a row that ban an instance.
    pub k: u32,
    /// Repairs plus replannings allowed within any minute of mission time.
    pub max_changes_per_min: u32,
    streaks: BTreeMap<Instance, (FailureKind, u32, String)>,
    banned: BTreeMap<Instance, String>,
    changes: VecDeque<(Time, PlanChangeKind)>,
    /// Failures in the current window, per instance (to name the culprit when the rate bound is hit).
    recent_failures: VecDeque<(Time, Instance)>,
}

const MINUTE: Time = 60_000;

impl FailureMemory {
    pub fn new(k: u32, max_changes_per_min: u32) -> Self {
        FailureMemory {
            k: k.max(1),
            max_changes_per_min: max_changes_per_min.max(1),
            streaks: BTreeMap::new(),
            banned: BTreeMap::new(),
            changes: VecDeque::new(),
            recent_failures: VecDeque::new(),
        }
    }

    /// A failure of `inst` at `t`, described by `what` (e.g. "failed: camera busy"). Returns the ban's
    /// reason when this failure is the k-th of the same kind in a row.
    pub fn failed(&mut self, inst: &Instance, what: &str, t: Time) -> Option<String> {
        self.recent_failures.push_back((t, inst.clone()));
        let kind = FailureKind::new(what);
        let entry = self
            .streaks
            .entry(inst.clone())
            .or_insert((kind.clone(), 0, what.to_string()));
        if entry.0 != kind {
            *entry = (kind, 0, what.to_string());
        }
        entry.1 += 1;
        if entry.1 < self.k || self.banned.contains_key(inst) {
            return None;
        }
        let reason = format!("{inst} {what} ({} times in a row)", entry.1);
        self.banned.insert(inst.clone(), reason.clone());
        Some(reason)
    }

    /// A nominal completion: the streak of `inst` ends.
    pub fn succeeded(&mut self, inst: &Instance) {
        self.streaks.remove(inst);
    }

    pub fn ban_of(&self, inst: &Instance) -> Option<&str> {
        self.banned.get(inst).map(String::as_str)
    }

    /// The banned instance action `a` necessarily is (all its arguments bound to the banned ones).
    pub fn banned_action(&self, plan: &PartialPlan, a: ActionId) -> Option<(&Instance, &str)> {
        let inst = Instance::of(plan, a);
        self.banned
            .get_key_value(&inst)
            .map(|(i, r)| (i, r.as_str()))
    }

    /// Banned instances action `a` may still become (some argument unbound).
    pub fn possibly_banned<'a>(
        &'a self,
        plan: &'a PartialPlan,
        a: ActionId,
    ) -> impl Iterator<Item = (&'a Instance, &'a str)> + 'a {
        self.banned
            .iter()
            .filter(move |(i, _)| i.possibly(plan, a))
            .map(|(i, r)| (i, r.as_str()))
    }

    pub fn any_banned(&self) -> bool {
        !self.banned.is_empty()
    }

    /// A plan change at `t`. Returns the number of changes within the last minute when it exceeds the
    /// bound (the window is then cleared: the caller settles it by rejecting a goal).
    pub fn plan_changed(&mut self, t: Time, kind: PlanChangeKind) -> Option<usize> {
        self.changes.push_back((t, kind));
        while self.changes.front().is_some_and(|&(c, _)| c <= t - MINUTE) {
            self.changes.pop_front();
        }
        while self
            .recent_failures
            .front()
            .is_some_and(|(c, _)| *c <= t - MINUTE)
        {
            self.recent_failures.pop_front();
        }
        let n = self.changes.len();
        if n > self.max_changes_per_min as usize {
            self.changes.clear();
            return Some(n);
        }
        None
    }

    /// The instance that failed most within the last minute.
    pub fn most_failing(&self) -> Option<(Instance, usize)> {
        let mut count: BTreeMap<&Instance, usize> = BTreeMap::new();
        for (_, i) in &self.recent_failures {
            *count.entry(i).or_default() += 1;
        }
        count
            .into_iter()
            .max_by_key(|&(i, n)| (n, std::cmp::Reverse(i.clone())))
            .map(|(i, n)| (i.clone(), n))
    }
}

/// The goals that depend on action `a` in `plan`: reached forward from `a` by
/// [`super::goal_support::supported_by`] (causal links and reservoir productions).
pub fn dependent_goals(plan: &PartialPlan, a: ActionId) -> Vec<GoalId> {
    let mut goals = BTreeSet::new();
    let mut seen = BTreeSet::from([a]);
    let mut todo = vec![a];
    while let Some(x) = todo.pop() {
        let mut next: Vec<ActionId> = Vec::new();
        super::goal_support::supported_by(plan, x, &mut |owner| match owner {
            Owner::Goal(g) => {
                goals.insert(g);
            }
            Owner::Action(b) => next.push(b),
            _ => {}
        });
        for b in next {
            if !plan.action(b).removed && seen.insert(b) {
                todo.push(b);
            }
        }
    }
    goals
        .into_iter()
        .filter(|g| plan.goals().iter().any(|pg| pg.goal == *g && pg.active))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inst(t: &str, a: &[&str]) -> Instance {
        Instance {
            task: t.into(),
            args: a.iter().map(|s| s.to_string()).collect(),
        }
    }

    #[test]
    fn k_same_failures_in_a_row_ban_the_instance() {
        let mut m = FailureMemory::new(3, 10);
        let d = inst("download_images", &["W1"]);
        assert_eq!(m.failed(&d, "failed: not visible at 120 s", 0), None);
        assert_eq!(m.failed(&d, "failed: not visible at 121 s", 1), None);
        let r = m.failed(&d, "failed: not visible at 130 s", 2);
        assert!(r
            .as_deref()
            .is_some_and(|r| r.contains("download_images(W1)")
                && r.contains("not visible")
                && r.contains("3 times")));
        assert!(m.ban_of(&d).is_some());
        // Another instance of the same task is not banned.
        assert!(m.ban_of(&inst("download_images", &["W2"])).is_none());
    }

    #[test]
    fn another_failure_kind_or_a_success_restarts_the_streak() {
        let mut m = FailureMemory::new(2, 10);
        let p = inst("take_picture", &["p1"]);
        assert_eq!(m.failed(&p, "failed: busy", 0), None);
        assert_eq!(m.failed(&p, "timed out", 1), None);
        m.succeeded(&p);
        assert_eq!(m.failed(&p, "timed out", 2), None);
        assert!(m.failed(&p, "timed out", 3).is_some());
        // Banned once: no second ban reason.
        assert_eq!(m.failed(&p, "timed out", 4), None);
    }

    #[test]
    fn plan_changes_are_bounded_per_minute_of_mission_time() {
        let mut m = FailureMemory::new(3, 3);
        for t in [0, 10_000, 20_000] {
            assert_eq!(m.plan_changed(t, PlanChangeKind::Repair), None);
        }
        assert_eq!(m.plan_changed(30_000, PlanChangeKind::Replan), Some(4));
        // The window was cleared; spread out changes never hit the bound.
        for t in (100_000..1_000_000).step_by(25_000) {
            assert_eq!(m.plan_changed(t, PlanChangeKind::Repair), None);
        }
    }

    #[test]
    fn most_failing_names_the_culprit() {
        let mut m = FailureMemory::new(9, 3);
        let a = inst("move", &["l0", "l1"]);
        let b = inst("take_picture", &["l1"]);
        m.failed(&a, "x", 0);
        m.failed(&b, "y", 1);
        m.failed(&b, "y", 2);
        assert_eq!(m.most_failing(), Some((b, 2)));
    }
}
