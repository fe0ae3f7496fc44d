//! How late a deferred start may go (seed 2's "latest start", made safe for durations the world decides).
//!
//! Seed 2 defers an action that serves no external goal to its latest start, the upper bound the STN gives
//! it. That bound assumes every action after it takes its *shortest* duration: the AUV of seed 2's Fig. 1,
//! sent home at the latest start its 20–30 min transits allow, arrives up to 10 min after its deadline
//! when the water is slow, and the return goal is lost. The bound used here is the latest start if every
//! action not yet ended takes its *longest* duration: the network with each action's duration constraint
//! fixed at its upper bound, solved for latest times from the origin (a shortest-path problem with
//! negative edges: Bellman–Ford with a queue). It is what dynamic controllability's waits give a chain of
//! contingent durations (start no later than the deadline minus the longest durations that follow); where
//! that network is inconsistent (the longest durations cannot all fit), the STN's own bound is kept.
//! Only deferral uses it: a start served as early as possible is unaffected.

use std::collections::{HashMap, VecDeque};

use mavtempo_temporal::plan::PartialPlan;
use mavtempo_temporal::stn::{Time, Timepoint, INF};

/// The latest time of every timepoint with every unfinished action at its longest duration, or `None`
/// when those durations cannot all fit (then the STN's bounds stand).
pub fn latest_at_longest(plan: &PartialPlan) -> Option<Vec<Time>> {
    let stn = plan.temporal_network();
    let n = stn.num_timepoints();
    let durations: HashMap<(Timepoint, Timepoint), ()> = plan
        .live_actions()
        .map(|a| plan.action(a))
        .filter(|act| !plan.is_executed(act.end))
        .map(|act| ((act.start, act.end), ()))
        .collect();
    // Edges `to − from ≤ w` as (from, to, w).
    let mut out: Vec<Vec<(usize, Time)>> = vec![Vec::new(); n];
    for (_, c) in stn.constraints() {
        let mut lb = c.lb;
        if durations.contains_key(&(c.from, c.to)) && c.ub < INF {
            lb = lb.max(c.ub);
        }
        if c.ub < INF {
            out[c.from.index()].push((c.to.index(), c.ub));
        }
        if lb > -INF {
            out[c.to.index()].push((c.from.index(), -lb));
        }
    }
    let origin = stn.origin().index();
    let mut dist = vec![INF; n];
    let mut queued = vec![false; n];
    let mut relaxed = vec![0usize; n];
    dist[origin] = 0;
    let mut queue = VecDeque::from([origin]);
    queued[origin] = true;
    while let Some(u) = queue.pop_front() {
        queued[u] = false;
        for &(v, w) in &out[u] {
            let d = dist[u].saturating_add(w);
            if d < dist[v] {
                dist[v] = d;
                relaxed[v] += 1;
                if relaxed[v] > n {
                    return None; // a negative cycle: the longest durations do not fit
                }
                if !queued[v] {
                    queued[v] = true;
                    queue.push_back(v);
                }
            }
        }
    }
    Some(dist)
}
