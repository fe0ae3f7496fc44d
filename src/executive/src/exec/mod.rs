//! The temporal executive of IxTeT-eXeC (seed 1 §3): the partially executed plan P_t and the rules that
//! keep it executable while it runs. Each rule of the paper lives in one file named after it; where the code
//! departs from a rule, docs/departures.md says how and why:
//!
//! | seed 1 | file |
//! |---|---|
//! | Definition 1, P_t (running / future / past actions, S_t) | [`p_t`] |
//! | eq. (1), (2), cases (1), (2): resource level bounds at t | [`resource_bounds`] |
//! | Definitions 2–5: executable timepoint / goal / action / plan | [`executable`] |
//! | §3.3 report timing: in bounds / too late / too early | [`report_timing`] |
//! | §3.3 resource level: over-consumption / over-production | [`resource_report`] |
//! | §3.3 goal request acceptance test | [`goal_request`] |
//! | (not in the papers) a new goal's bounded insertion attempt beside the plan: rejected first, plan kept | [`goal_insertion`] |
//! | (not in the papers) a goal whose insertion was cut by its budget is tried again | [`goal_retry`] |
//! | §3.3 capacity alteration | [`capacity`] |
//! | §3.3 causal-link removal via the abstraction hierarchy | [`abstraction`] |
//! | §3.5 t_exec per timepoint kind | [`t_exec`] |
//! | §3.5 the dispatch decision (src/dispatch policies) | [`dispatch_policy`] |
//! | seed 2's latest start, kept for the longest durations | [`deferral`] |
//! | seed 2: what an action is for (causal links and reservoirs; dispatch and the failure bounds) | [`goal_support`] |
//! | §5 (future work): contingent durations not squeezed: waits of the plan's STNU (dynamic controllability, docs/stnu.md) | [`squeeze`] |
//! | §3.2 time injected: the caller gives each cycle its time (the vehicle's clock live, a script in tests) | [`pacer`] |
//! | §3.2 ts and μ | [`config`] |
//! | §3.2 the cycle: sense / repair ≤ μ·ts / act | [`cycle`] (state in [`executive`]) |
//! | §3.4 the aggregated past levels and every write of the level the planner sees | [`ledger`] |
//! | §3.2 *ExecutingPlan* behind a handle recording each edit (the repair tree and an insertion restart) | [`executing_plan`] |
//! | §3.2 time injected: mission time read by repair and replanning | [`clock`] |
//! | started actions, their `i_a`, the stops sent | `dispatched` |
//! | data only: the repair tree, insertions and parked goals, replanning records | [`repair_tree`], [`insertion`], [`replan_record`] |
//! | §3.3 message routing | [`sense`] |
//! | §3.3 state values from non-nominal reports, new locations | [`state_update`] |
//! | the domain's names given a vehicle meaning (position, locations, goals) | [`crate::mapping`] |
//! | §3.2, §3.4 plan repair across cycles | [`repair`] |
//! | §3.5 act: ExecTPs, launch / stop, postponement, timeouts | [`act`] |
//! | §3.6 complete replanning: P_ti, T_end, slack d, goal rejection | [`replan`] |
//! | (not in the papers) nothing loops: repeated failures banned, plan changes per minute bounded | [`failures`], [`settle`] |
//! | the per-cycle trace (Fig. 6) | [`trace`] |
//! | a mission run live: cycles, replanning, the report | [`mission`] (time: [`pacer`]) |
//! | (not in the papers) a mission stopped from outside (a signal) | [`interrupt`] |

mod abort;
pub mod abstraction;
pub mod act;
pub mod authority;
pub mod builder;
pub mod cancel;
pub mod capacity;
pub mod clock;
pub mod config;
pub mod cycle;
pub mod cycle_log;
pub mod deferral;
pub mod dispatch_policy;
mod dispatched;
pub mod executable;
pub mod executing_plan;
pub mod executive;
pub mod failures;
pub mod goal_book;
pub mod goal_insertion;
pub mod goal_request;
pub mod goal_retry;
pub mod goal_support;
pub mod insertion;
pub mod instantiate;
pub mod interrupt;
pub mod journal;
pub mod ledger;
pub mod mission;
mod operator_hold;
pub mod operator_text;
pub mod outcome;
pub mod p_t;
pub mod pacer;
pub mod repair;
pub mod repair_tree;
pub mod replan;
pub mod replan_record;
pub mod report_timing;
pub mod reserve;
pub mod resource_bounds;
pub mod resource_report;
pub mod sense;
pub mod settle;
pub mod squeeze;
pub mod state_update;
pub mod still;
pub mod t_exec;
pub mod trace;
pub mod trip_needs;
mod vehicle_binding;

#[cfg(test)]
mod import_graph;

pub use crate::mapping::DomainMapping;
