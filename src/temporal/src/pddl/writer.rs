//! A plan in the IPC format, one line per action sorted by start: `0.000: (navigate r w1 w2) [5.000]`.
//!
//! The planner's plan is flexible (timepoints with windows, variables with domains); this instantiates it
//! as a dispatchable schedule: the checker's bindings, and every timepoint at the earliest time its
//! temporal network allows once PDDL's ε-separation is added — two actions the plan orders (a causal link,
//! a threat's resolution) are at least [`EPSILON_MS`] apart, as PDDL 2.1 validators require of an action
//! that needs another's effect.

use std::fmt;

use crate::model::{Domain, Problem, Time};
use crate::plan::solution::{PlanTerm, Solution};
use crate::plan::validate::Checked;

/// PDDL's ε: the least separation between an effect and what depends on it (10 ms, safe for validators
/// that use ε = 0.01 s as well as those at 0.001 s).
pub const EPSILON_MS: Time = 10;

/// One action of an IPC plan.
#[derive(Debug, Clone, PartialEq)]
pub struct IpcStep {
    pub start_ms: Time,
    /// The action's name, lower-case as in the PDDL file.
    pub action: String,
    pub args: Vec<String>,
    pub duration_ms: Time,
    /// The duration the PDDL fixes (`(= ?duration e)` on static values) in seconds, where it is not a whole
    /// number of milliseconds: printed instead of `duration_ms` (the planner's rounding), since validators
    /// compare it exactly.
    pub exact_s: Option<f64>,
}

/// A plan in the IPC format.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct IpcPlan {
    pub steps: Vec<IpcStep>,
}

impl IpcPlan {
    /// The end of the last action (ms).
    pub fn makespan_ms(&self) -> Time {
        self.steps
            .iter()
            .map(|s| s.start_ms + s.duration_ms)
            .max()
            .unwrap_or(0)
    }
}

/// Whether `s` seconds is a whole number of milliseconds (what `secs` prints exactly).
pub(super) fn whole_ms(s: f64) -> bool {
    let ms = s * 1000.0;
    (ms - ms.round()).abs() < 1e-6
}

fn secs(ms: Time) -> String {
    format!("{}.{:03}", ms.div_euclid(1000), ms.rem_euclid(1000))
}

impl fmt::Display for IpcPlan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for s in &self.steps {
            let mut call = s.action.clone();
            for a in &s.args {
                call.push(' ');
                call.push_str(a);
            }
            writeln!(
                f,
                "{}: ({call}) [{}]",
                secs(s.start_ms),
                s.exact_s
                    .map_or_else(|| secs(s.duration_ms), |x| format!("{x}"))
            )?;
        }
        Ok(())
    }
}

/// Why a checked solution has no IPC plan (each names the action it is about).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum IpcError {
    #[error("{0}: unknown task")]
    UnknownTask(String),
    #[error("{0}: variable without a value")]
    Unbound(String),
    #[error("{0}: a parameter is +oo")]
    Infinite(String),
    #[error("{0}: timepoint missing")]
    NoTimepoint(String),
    #[error("a constraint names an unknown timepoint")]
    UnknownTimepoint,
    #[error("the plan's network is inconsistent once actions are ε-separated")]
    Inconsistent,
}

/// A line of an IPC plan that does not read as `start: (action args) [duration]` (numbered from 1).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("line {line}: expected `start: (action args) [duration]`")]
pub struct IpcLineError {
    pub line: usize,
}

/// The IPC plan of a checked solution (`checked`: what the independent checker instantiated).
pub fn ipc_plan(
    domain: &Domain,
    problem: &Problem,
    sol: &Solution,
    checked: &Checked,
) -> Result<IpcPlan, IpcError> {
    let times = separated_schedule(sol)?;
    let mut steps = Vec::new();
    for a in &sol.actions {
        let task = domain
            .tasks
            .get(a.task.index())
            .ok_or_else(|| IpcError::UnknownTask(a.name.clone()))?;
        let mut args = Vec::new();
        for t in a.args.iter().take(task.n_params) {
            let o = match *t {
                PlanTerm::Obj(o) => o,
                PlanTerm::Var(v) => *checked
                    .bindings
                    .get(v.index())
                    .ok_or_else(|| IpcError::Unbound(a.name.clone()))?,
                PlanTerm::Unknown => return Err(IpcError::Infinite(a.name.clone())),
            };
            args.push(problem.object_name(o).to_string());
        }
        let at = |tp: Option<&crate::plan::solution::PlanTp>| {
            tp.and_then(|t| times.get(t.index()).copied())
                .ok_or_else(|| IpcError::NoTimepoint(a.name.clone()))
        };
        let (st, et) = (at(a.timepoints.first())?, at(a.timepoints.last())?);
        steps.push(IpcStep {
            start_ms: st,
            action: task.name.clone(),
            args,
            duration_ms: et - st,
            exact_s: None,
        });
    }
    steps.sort_by(|x, y| (x.start_ms, &x.action, &x.args).cmp(&(y.start_ms, &y.action, &y.args)));
    Ok(IpcPlan { steps })
}

/// The earliest times of the solution's network where every ordering between two actions' timepoints (or
/// an action's and a timed initial literal's) is at least [`EPSILON_MS`].
fn separated_schedule(sol: &Solution) -> Result<Vec<Time>, IpcError> {
    let n = sol.timepoints.len();
    // Who a timepoint belongs to: an action, or itself (a timed literal's change, a goal); the origin none.
    let mut owner: Vec<Option<usize>> = (0..n)
        .map(|i| (i != 0).then_some(sol.actions.len() + i))
        .collect();
    for (i, a) in sol.actions.iter().enumerate() {
        for tp in &a.timepoints {
            if let Some(o) = owner.get_mut(tp.index()) {
                *o = Some(i);
            }
        }
    }
    let edges: Vec<(usize, usize, Option<Time>, Option<Time>)> = sol
        .constraints
        .iter()
        .map(|c| {
            let (f, t) = (c.from.index(), c.to.index());
            // Two different owners, one of them an action (a goal's own window is not separated).
            let n_act = sol.actions.len();
            let across = matches!((owner.get(f), owner.get(t)),
                (Some(Some(x)), Some(Some(y))) if x != y && (*x < n_act || *y < n_act));
            let lb = match c.lb {
                Some(l) if across && l >= 0 => Some(l.max(EPSILON_MS)),
                l => l,
            };
            (f, t, lb, c.ub)
        })
        .collect();
    let mut t: Vec<Time> = vec![0; n];
    for _ in 0..=n {
        let mut changed = false;
        for &(f, to, lb, ub) in &edges {
            if f >= n || to >= n {
                return Err(IpcError::UnknownTimepoint);
            }
            if let Some(l) = lb {
                if t[to] < t[f] + l {
                    t[to] = t[f] + l;
                    changed = true;
                }
            }
            if let Some(u) = ub {
                if t[f] < t[to] - u {
                    t[f] = t[to] - u;
                    changed = true;
                }
            }
        }
        if !changed {
            return if t.first().copied().unwrap_or(0) == 0 {
                Ok(t)
            } else {
                Err(IpcError::Inconsistent)
            };
        }
    }
    Err(IpcError::Inconsistent)
}

/// Reads an IPC plan (`start: (action args) [duration]` per line; `;` comments and blank lines skipped).
pub fn parse_ipc(text: &str) -> Result<Vec<IpcStep>, IpcLineError> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split(';').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let bad = || IpcLineError { line: i + 1 };
        let (start, rest) = line.split_once(':').ok_or_else(bad)?;
        let open = rest.find('(').ok_or_else(bad)?;
        let close = rest.find(')').ok_or_else(bad)?;
        let call: Vec<String> = rest
            .get(open + 1..close)
            .ok_or_else(bad)?
            .split_whitespace()
            .map(str::to_lowercase)
            .collect();
        let dur = rest
            .get(close + 1..)
            .and_then(|r| r.trim().strip_prefix('['))
            .and_then(|r| r.strip_suffix(']'))
            .ok_or_else(bad)?;
        let ms = |s: &str| -> Result<Time, IpcLineError> {
            s.trim()
                .parse::<f64>()
                .map(|v| (v * 1000.0).round() as Time)
                .map_err(|_| bad())
        };
        let exact_s = dur.trim().parse::<f64>().ok().filter(|&v| !whole_ms(v));
        let (action, args) = call.split_first().ok_or_else(bad)?;
        out.push(IpcStep {
            start_ms: ms(start)?,
            action: action.clone(),
            args: args.to_vec(),
            duration_ms: ms(dur)?,
            exact_s,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_duration_finer_than_a_millisecond_is_printed_as_the_pddl_gives_it() {
        let p = IpcPlan {
            steps: vec![IpcStep {
                start_ms: 1,
                action: "turn_to".into(),
                args: vec!["satellite0".into()],
                duration_ms: 530,
                exact_s: Some(0.5297),
            }],
        };
        let text = p.to_string();
        assert_eq!(text, "0.001: (turn_to satellite0) [0.5297]\n");
        assert_eq!(parse_ipc(&text), Ok(p.steps));
    }

    #[test]
    fn prints_and_reads_back_the_ipc_format() {
        let p = IpcPlan {
            steps: vec![IpcStep {
                start_ms: 10,
                action: "navigate".into(),
                args: vec!["rover0".into(), "waypoint3".into()],
                duration_ms: 5_000,
                exact_s: None,
            }],
        };
        let text = p.to_string();
        assert_eq!(text, "0.010: (navigate rover0 waypoint3) [5.000]\n");
        assert_eq!(parse_ipc(&text), Ok(p.steps.clone()));
        assert_eq!(p.makespan_ms(), 5_010);
        assert!(parse_ipc("0.0 (x)").is_err());
    }
}
