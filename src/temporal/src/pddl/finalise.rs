//! What a plan of a PDDL problem with numeric fluents still needs once the planner is done (issue 32):
//!
//! - PDDL 2.1 forbids two happenings closer than ε when one changes a numeric fluent the other reads or
//!   changes; the planner's reservoirs let such accesses share an instant (their changes commute for the
//!   level envelope). Every instance's accesses are put in one order, the earliest schedule's, each at
//!   least 1 ms after the previous (the writer widens orderings between actions to ε);
//! - a fill at a rate lasts `(v - f) / r`, `f` its level at its start: with the accesses in one order that
//!   level is known, and the duration is fixed to it (rounded down to the ms, so the level it reaches is
//!   at most `v`).
//!
//! The plan's reservoir levels hold for every schedule of its partial order, so any order consistent with
//! its network keeps them; the independent checker and the replay on the PDDL check the result.

use std::collections::BTreeMap;

use super::fluents::{Change, Fluents};
use crate::model::{Domain, TpId};
use crate::plan::solution::{PlanConstraint, PlanTp, Solution};
use crate::stn::{Stn, Timepoint, INF};

/// Why a plan's numeric fluents could not be put in one order or its rate-dependent durations fixed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum FinaliseError {
    #[error("the plan's network is inconsistent")]
    Inconsistent,
    #[error("{0}: its accesses to a numeric fluent cannot be ε-separated from another action's")]
    Separation(String),
    #[error("{0}: the fluent it fills is already full at its start (a duration of 0)")]
    AlreadyFull(String),
    #[error(
        "{0}: its duration, fixed by the fluent's level at its start, breaks the plan's network"
    )]
    Duration(String),
}

/// One access in the order: (earliest time, phase, action, plan timepoint, task timepoint).
type Slot = (i64, u8, usize, PlanTp, TpId);

/// Orders the numeric accesses of `sol` and fixes its rate-dependent durations (see the module's doc).
pub fn finalise(
    domain: &Domain,
    fluents: &Fluents,
    sol: &mut Solution,
) -> Result<(), FinaliseError> {
    let any = sol.actions.iter().any(|a| {
        fluents
            .tasks
            .get(a.task.index())
            .is_some_and(|n| !n.accesses.is_empty())
    });
    if !any {
        return Ok(());
    }
    let mut stn = Stn::new();
    for _ in 1..sol.timepoints.len() {
        stn.add_timepoint();
    }
    let tp = |p: PlanTp| Timepoint(p.index() as u32);
    for c in &sol.constraints {
        stn.add_constraint(
            tp(c.from),
            tp(c.to),
            c.lb.unwrap_or(-INF),
            c.ub.unwrap_or(INF),
        )
        .map_err(|_| FinaliseError::Inconsistent)?;
    }
    let mut added: Vec<PlanConstraint> = Vec::new();
    // Per reservoir, its accesses in one order.
    let mut per: BTreeMap<usize, Vec<Slot>> = BTreeMap::new();
    for (k, a) in sol.actions.iter().enumerate() {
        let Some(n) = fluents.tasks.get(a.task.index()) else {
            continue;
        };
        for acc in &n.accesses {
            let Some(p) = a.tp(acc.at) else { continue };
            // An action that reads or changes the instance at both ends holds it between them: others
            // meeting its end come after it, those meeting its start before it.
            let both = n
                .accesses
                .iter()
                .any(|x| x.resource == acc.resource && x.at != acc.at);
            let phase = match (both, acc.at == domain.task(a.task).end) {
                (false, _) => 1,
                (true, true) => 0,
                (true, false) => 2,
            };
            let slot = (stn.lb(tp(p)), phase, k, p, acc.at);
            let list = per.entry(acc.resource.index()).or_default();
            if !list.iter().any(|s| s.2 == k && s.3 == p) {
                list.push(slot);
            }
        }
    }
    for list in per.values_mut() {
        list.sort();
        for w in list.windows(2) {
            let (x, y) = (w[0], w[1]);
            if x.2 == y.2 {
                continue;
            }
            stn.add_constraint(tp(x.3), tp(y.3), 1, INF)
                .map_err(|_| FinaliseError::Separation(sol.actions[y.2].name.clone()))?;
            added.push(PlanConstraint {
                from: x.3,
                to: y.3,
                lb: Some(1),
                ub: None,
            });
        }
    }
    // The levels along each order, and the durations they fix.
    for (r, list) in &per {
        let mut level = fluents
            .initial
            .get(&crate::model::ResourceId::from_index(*r))
            .copied()
            .unwrap_or(0.0);
        let mut reached = None;
        for &(_, _, k, _, at) in list {
            let a = &sol.actions[k];
            let Some(n) = fluents.tasks.get(a.task.index()) else {
                continue;
            };
            let task = domain.task(a.task);
            if let Some(d) = n.duration.filter(|d| d.resource.index() == *r) {
                if at == task.start {
                    let ms = ((d.v - level) / d.r * 1000.0 + 1e-6).floor();
                    if ms < 1.0 {
                        return Err(FinaliseError::AlreadyFull(a.name.clone()));
                    }
                    let (Some(st), Some(et)) = (a.tp(task.start), a.tp(task.end)) else {
                        return Err(FinaliseError::Inconsistent);
                    };
                    let ms = ms as i64;
                    stn.add_constraint(tp(st), tp(et), ms, ms)
                        .map_err(|_| FinaliseError::Duration(a.name.clone()))?;
                    added.push(PlanConstraint {
                        from: st,
                        to: et,
                        lb: Some(ms),
                        ub: Some(ms),
                    });
                    // What a fill at this rate reaches with the duration rounded down.
                    reached = Some(level + ms as f64 / 1000.0 * d.r);
                }
            }
            for acc in n
                .accesses
                .iter()
                .filter(|x| x.resource.index() == *r && x.at == at)
            {
                level = match acc.change {
                    Some(Change::Rate(v)) => reached.take().unwrap_or(v),
                    Some(c) => c.apply(level),
                    None => level,
                };
            }
        }
    }
    sol.constraints.extend(added);
    for (i, t) in sol.timepoints.iter_mut().enumerate() {
        let p = Timepoint(i as u32);
        t.lb = Some(stn.lb(p));
        let ub = stn.ub(p);
        t.ub = (ub < INF).then_some(ub);
    }
    Ok(())
}
