//! The live page's goals table (issue 30): per goal what it asks, where, its start window, where it came
//! from and its state in the operator's words — a goal held in the plan is `accepted`, not "pending".

use std::collections::{BTreeMap, BTreeSet};

use super::data::GoalView;
use crate::exec::executive::{Executive, Fate};
use crate::exec::outcome::FateReason;
use crate::model::{interval_string, Goal, ObjectId, Problem, Value};
use crate::vehicle::held::Station;

/// Where each goal came from, remembered once seen (a goal leaves the intake's held list when settled).
#[derive(Debug, Default)]
pub struct Sources {
    /// The problem's own goals, as at the first cycle.
    problem: Option<BTreeSet<String>>,
    seen: BTreeMap<String, String>,
}

impl Sources {
    fn source(&mut self, name: &str, holder: Option<Station>) -> String {
        if let Some(s) = self.seen.get(name) {
            return s.clone();
        }
        let s = match holder {
            Some((sys, comp)) => format!("ground station {sys}/{comp}"),
            None if self.problem.as_ref().is_some_and(|p| p.contains(name)) => "problem".into(),
            None => "upload".into(),
        };
        // A goal not yet held (still being inserted) may be held next cycle: only settle what is known.
        if holder.is_some() || s == "problem" {
            self.seen.insert(name.to_string(), s.clone());
        }
        s
    }
}

/// The goals' rows. `holders`: the goals ground stations hold and which station; `cancel`: the page can
/// withdraw held goals (its form is on).
pub fn goal_rows(
    ex: &Executive,
    holders: &[(String, Station)],
    sources: &mut Sources,
    cancel: bool,
) -> Vec<GoalView> {
    let problem = ex.plan().problem();
    if sources.problem.is_none() {
        sources.problem = Some(problem.goals.iter().map(|g| g.name.clone()).collect());
    }
    let held: BTreeMap<&str, Station> = holders.iter().map(|(n, s)| (n.as_str(), *s)).collect();
    ex.goal_fates()
        .into_iter()
        .map(|g| {
            let goal = problem.goals.iter().find(|pg| pg.name == g.name);
            let holder = held.get(g.name.as_str()).copied();
            let inserting = matches!(g.reason, Some(FateReason::Inserting));
            let state = match g.fate {
                Fate::Pending if inserting => "inserting",
                Fate::Pending => "accepted",
                Fate::Achieved => "achieved",
                Fate::Rejected => "rejected",
                Fate::Cancelled => "cancelled",
            };
            GoalView {
                reason: g.operator_reason(),
                fate: serde_json::to_value(&g.fate)
                    .ok()
                    .and_then(|v| v.as_str().map(str::to_string))
                    .unwrap_or_default(),
                what: goal.map_or(String::new(), |pg| what(ex, problem, pg)),
                place: goal.map_or(String::new(), |pg| place(problem, pg)),
                window: goal.map_or(String::new(), |pg| interval_string(&pg.start_window)),
                source: sources.source(&g.name, holder),
                state: state.into(),
                cancellable: cancel && holder.is_some() && g.fate == Fate::Pending,
                name: g.name,
            }
        })
        .collect()
}

/// `PICTURE(p1) = true`.
fn what(ex: &Executive, problem: &Problem, g: &Goal) -> String {
    format!(
        "{} = {}",
        problem.instance_string(ex.plan().domain(), g.attr, &g.args),
        problem.value_name(g.value)
    )
}

/// The first place the goal names (an argument or its value) that has a position: `p1 (30 m E, 2 m N)`.
fn place(problem: &Problem, g: &Goal) -> String {
    let value = match g.value {
        Value::Obj(o) => Some(o),
        Value::Unknown => None,
    };
    let located = |o: &ObjectId| {
        let obj = problem.objects.get(o.index())?;
        let (e, n, _) = obj.local(problem.home.as_ref())?;
        Some(format!("{} ({e:.0} m E, {n:.0} m N)", obj.name))
    };
    g.args
        .iter()
        .chain(value.iter())
        .find_map(located)
        .unwrap_or_default()
}
