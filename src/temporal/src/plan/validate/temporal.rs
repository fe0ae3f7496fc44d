//! Time: re-solving the plan's network, the earliest schedule within the reported windows, and the
//! temporal constraints the model imposes (task durations, horizon, goal windows I^g and durations I^d).

use crate::plan::solution::Solution;

use super::network::{edges_of, solve, Edge};
use super::{show_interval, show_window, Ctx, Violation};
use crate::model::Time;

/// Re-solves the network, checks each reported window against it and returns the earliest schedule
/// within the windows; `None` when the network itself is inconsistent.
pub(super) fn schedule(s: &Solution, out: &mut Vec<Violation>) -> Option<Vec<Time>> {
    let n = s.timepoints.len();
    let names = |cycle: Vec<usize>| {
        let v: Vec<&str> = cycle
            .iter()
            .map(|&i| s.timepoints.get(i).map_or("?", |t| t.name.as_str()))
            .collect();
        v.join(" → ")
    };
    let net: Vec<Edge> = s
        .constraints
        .iter()
        .flat_map(|c| edges_of(c.from.index(), c.to.index(), c.lb, c.ub))
        .collect();
    let bounds = match solve(n, &net) {
        Ok(b) => b,
        Err(cycle) => {
            out.push(Violation::InconsistentNetwork {
                cycle: names(cycle),
            });
            return None;
        }
    };
    let mut with_windows = net;
    for (i, t) in s.timepoints.iter().enumerate() {
        let (clb, cub) = (bounds.lb[i], bounds.ub[i]);
        let lb_ok = t.lb.is_some_and(|l| l >= clb);
        let ub_ok = match (t.ub, cub) {
            (_, None) => true,
            (Some(u), Some(c)) => u <= c,
            (None, Some(_)) => false,
        };
        if !lb_ok || !ub_ok {
            out.push(Violation::WindowOutsideNetwork {
                tp: t.name.clone(),
                reported: show_window(t.lb, t.ub),
                computed: show_window(Some(clb), cub),
            });
        }
        with_windows.extend(edges_of(0, i, t.lb, t.ub));
    }
    match solve(n, &with_windows) {
        Ok(b) => Some(b.lb),
        Err(cycle) => {
            out.push(Violation::InconsistentWindows {
                cycle: names(cycle),
            });
            Some(bounds.lb)
        }
    }
}

/// The model's temporal constraints at the schedule.
pub(super) fn check(cx: &Ctx, out: &mut Vec<Violation>) {
    for a in &cx.s.actions {
        let task = cx.d.task(a.task);
        for c in &task.temporal {
            let value = cx.at(a, c.to) - cx.at(a, c.from);
            if !c.interval.contains(value) {
                let name = |tp: crate::model::TpId| {
                    task.timepoints.get(tp.index()).cloned().unwrap_or_default()
                };
                out.push(Violation::TaskConstraint {
                    action: cx.label(a),
                    from: name(c.from),
                    to: name(c.to),
                    value,
                    interval: show_interval(&c.interval),
                });
            }
        }
        for &tp in &a.timepoints {
            let time = cx.time(tp);
            if time > cx.p.horizon {
                out.push(Violation::AfterHorizon {
                    tp: cx.s.tp_name(tp).to_string(),
                    time,
                    horizon: cx.p.horizon,
                });
            }
        }
    }
    for g in cx.s.goals.iter().filter(|g| g.achieved) {
        let goal = &cx.p.goals[g.goal.index()];
        let (Some(st), Some(et)) = (g.start, g.end) else {
            out.push(Violation::GoalUnsupported {
                goal: goal.name.clone(),
                reason: "its timepoints are missing".into(),
            });
            continue;
        };
        let (st, et) = (cx.time(st), cx.time(et));
        if !goal.start_window.contains(st) {
            out.push(Violation::GoalWindow {
                goal: goal.name.clone(),
                start: st,
                window: show_interval(&goal.start_window),
            });
        }
        if !goal.duration.contains(et - st) {
            out.push(Violation::GoalDuration {
                goal: goal.name.clone(),
                duration: et - st,
                interval: show_interval(&goal.duration),
            });
        }
    }
}
