//! The executive: the executing plan P_t and what it remembers between cycles. The cycle itself is in
//! [`super::cycle`], message integration in [`super::sense`], the act part in [`super::act`], plan repair in
//! [`super::repair`] and complete replanning in [`super::replan`].

use std::collections::{BTreeMap, VecDeque};

use serde::Serialize;

use super::abstraction::Hierarchy;
use super::config::ExecConfig;
use super::cycle_log::CycleLog;
use super::dispatch_policy::PlanDispatch;
use super::failures::FailureMemory;
use super::insertion::{Insertion, Parked};
use super::outcome::{AbortReason, FateReason};
use super::p_t::State;
use super::repair_tree::RepairState;
use super::trace::{CycleRecord, TraceEvent};
use mavtempo_temporal::model::{GoalId, ResourceId, Time};
use mavtempo_temporal::plan::{ActionId, PartialPlan};
use mavtempo_vehicle::goals::{GoalBatch, GoalWatch};
use mavtempo_vehicle::GoalVerdict;
use mavtempo_vehicle::{ActionStart, Arg, Enu};

/// The fate of a goal at the end of a run.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Fate {
    Achieved,
    Rejected,
    Pending,
    /// Withdrawn by its ground station.
    Cancelled,
}

/// A goal's fate and why (the report writes the reason's text, empty without one).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GoalFate {
    pub name: String,
    pub fate: Fate,
    #[serde(serialize_with = "super::outcome::reason_text")]
    pub reason: Option<FateReason>,
}

impl GoalFate {
    /// The reason's text (the planner's detail, for engineers), empty without one.
    pub fn reason_text(&self) -> String {
        self.reason
            .as_ref()
            .map_or(String::new(), |r| r.to_string())
    }

    /// The reason in the operator's words, empty without one.
    pub fn operator_reason(&self) -> String {
        self.reason
            .as_ref()
            .map_or(String::new(), |r| r.operator_text())
    }
}

/// Counters for the summary.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Counters {
    pub repairs: u64,
    pub repair_steps: u64,
    /// The part of `repair_steps` spent inserting new goals (src/executive/src/exec/goal_insertion.rs).
    pub insertion_steps: u64,
    pub replans: u64,
    pub launches: u64,
}

pub struct Executive {
    /// *ExecutingPlan*.
    pub(crate) plan: super::executing_plan::ExecutingPlan,
    pub(crate) cfg: ExecConfig,
    pub(crate) policy: PlanDispatch,
    pub(crate) hierarchy: Hierarchy,
    /// The aggregated level of each resource due to the actions that left the plan, and its rules.
    pub(crate) ledger: super::ledger::ResourceLedger,
    /// LgcS_t.
    pub(crate) state: State,
    /// Started actions, their `i_a`, and those an `END i_a` was sent to.
    pub(crate) dispatched: super::dispatched::Dispatched,
    /// The vehicle time (ms) of the plan's origin: report times are converted with it.
    pub(crate) vehicle_origin_ms: u64,
    /// Interruptions requested by message integration (sent in the act part).
    pub(crate) interrupt: Vec<ActionId>,
    /// Plan repair between cycles: the tree, the request, the episode's steps.
    pub(crate) repair: RepairState,
    /// Set when the plan is not executable any more: the cycle aborts and replans from scratch.
    pub(crate) abort: Option<AbortReason>,
    pub(crate) fates: BTreeMap<GoalId, GoalFate>,
    pub(crate) cycles: CycleLog,
    pub(crate) counters: Counters,
    /// Events of the current cycle.
    pub(crate) pending_trace: Vec<TraceEvent>,
    /// Failures and plan changes of this mission: what repair cannot fix is settled (src/executive/src/exec/failures.rs).
    pub(crate) failures: FailureMemory,
    /// The domain's names given a vehicle meaning (position attribute, location type, goal kinds); empty
    /// until [`Executive::with_mapping`]: positions are then ignored and uploaded goals rejected.
    pub(crate) mapping: crate::mapping::DomainMapping,
    /// New goals waiting for, or in, their insertion attempt (the front one is in progress).
    pub(crate) insertions: VecDeque<Insertion>,
    /// New goals rejected for a reason that may stop holding, waiting to be tried again.
    pub(crate) parked: Vec<Parked>,
    /// Uploads not answered yet, or with goals still being inserted, by number.
    pub(crate) goal_batches: BTreeMap<u64, GoalBatch>,
    pub(crate) next_batch: u64,
    /// Requested goals that never entered the plan (mapping, acceptance test or insertion failed), in the
    /// order they were refused.
    pub(crate) refused: Vec<GoalFate>,
    /// The complete replannings of this mission: abort, attempts, steps, outcome, goals kept and rejected.
    pub(crate) replannings: Vec<super::replan_record::ReplanRecord>,
    /// The operator has the vehicle (why): no action is launched or stopped (src/executive/src/exec/authority.rs).
    pub(crate) paused: Option<String>,
    /// Where the vehicle may go: goals at places outside are refused at intake.
    pub(crate) limits: Option<mavtempo_vehicle::limits::Limits>,
    /// Uploaded goals held in the plan: their ground station is told how each ends.
    pub(crate) watches: BTreeMap<GoalId, GoalWatch>,
    /// The observed moving/still attribute and its still value (`[state] moving`): a motion whose end a
    /// later action holds still ends once the vehicle is still (src/executive/src/exec/still.rs).
    pub(crate) still: Option<(
        mavtempo_temporal::model::AttrId,
        mavtempo_temporal::model::ObjectId,
    )>,
}

impl Executive {
    /// An executive over a solution plan (the planner's output, or a hand-built plan in tests).
    pub fn new(plan: PartialPlan, cfg: ExecConfig) -> Self {
        let ledger = super::ledger::ResourceLedger::new(plan.problem());
        let mut fates = BTreeMap::new();
        for pg in plan.goals() {
            if let Some(g) = plan.problem().goals.get(pg.goal.index()) {
                fates.insert(
                    pg.goal,
                    GoalFate {
                        name: g.name.clone(),
                        fate: Fate::Pending,
                        reason: None,
                    },
                );
            }
        }
        let hierarchy = Hierarchy::new(plan.domain());
        let policy = PlanDispatch::new(cfg.dispatch);
        let failures = FailureMemory::new(cfg.same_failure_limit, cfg.max_plan_changes_per_min);
        Executive {
            plan: super::executing_plan::ExecutingPlan::new(plan),
            cfg,
            policy,
            hierarchy,
            ledger,
            state: State::default(),
            dispatched: Default::default(),
            vehicle_origin_ms: 0,
            interrupt: Vec::new(),
            repair: RepairState::default(),
            abort: None,
            fates,
            cycles: CycleLog::default(),
            counters: Counters::default(),
            pending_trace: Vec::new(),
            failures,
            mapping: crate::mapping::DomainMapping::default(),
            insertions: VecDeque::new(),
            parked: Vec::new(),
            goal_batches: BTreeMap::new(),
            next_batch: 0,
            refused: Vec::new(),
            replannings: Vec::new(),
            paused: None,
            limits: None,
            watches: BTreeMap::new(),
            still: None,
        }
    }

    /// Where the vehicle may go (`[limits]`, the autopilot's fence): a goal at a place outside is
    /// rejected when it arrives, with the distance and the limit.
    ///
    /// The planner keeps to them too: they become the problem's [`mavtempo_temporal::model::Legs`], so a
    /// move whose straight leg leaves them gets no distance and is no resolver, in plan repair, goal
    /// insertion and complete replanning alike (the one place move durations come from).
    pub fn with_limits(mut self, limits: Option<mavtempo_vehicle::limits::Limits>) -> Self {
        self.limits = limits.filter(|l| !l.is_empty());
        if let Some(l) = &self.limits {
            let mut problem = (**self.plan.problem()).clone();
            problem.legs = crate::leg_limits::legs_within(l);
            self.plan.edit().set_problem(std::sync::Arc::new(problem));
            // A plan made before the limits were known (the autopilot's fence is read at readiness) may
            // hold a move that leaves them: it is made again, complete replanning, before any launch.
            let outside = self
                .plan
                .live_actions()
                .filter(|&a| !self.plan.action(a).num_cons.is_empty())
                .collect::<Vec<_>>()
                .into_iter()
                .find(|&a| self.plan.edit().repropagate_action(a).is_err());
            if let Some(a) = outside {
                let error = format!("{} leaves the vehicle's limits", self.action_text(a));
                tracing::warn!("{error}: the plan is made again");
                self.abort
                    .get_or_insert(super::outcome::AbortReason::NotExecutable { now_ms: 0, error });
            }
        }
        self
    }

    /// The vehicle configuration's `[mapping]`, resolved against this plan's domain
    /// ([`crate::config_check::check`]).
    pub fn with_mapping(mut self, mapping: crate::mapping::DomainMapping) -> Self {
        self.mapping = mapping;
        self
    }

    pub fn with_policy(mut self, kind: crate::dispatch::PolicyKind) -> Self {
        self.cfg.dispatch = kind;
        self.policy = PlanDispatch::new(kind);
        self
    }

    pub fn trace(&mut self, e: TraceEvent) {
        tracing::debug!("{}", e.line());
        self.pending_trace.push(e);
    }

    /// The events traced since the last cycle (an abort, a replanning and its rejections) as a record of
    /// their own at `now`, when there are any: how a mission that ends between cycles keeps them.
    pub fn flush_trace(&mut self, now: Time) -> Option<CycleRecord> {
        if self.pending_trace.is_empty() {
            return None;
        }
        let c = CycleRecord {
            index: self.cycles.count() + 1,
            time_ms: now,
            events: std::mem::take(&mut self.pending_trace),
            ..CycleRecord::default()
        };
        self.cycles.push(c.clone());
        Some(c)
    }

    /// The action's name with its grounded parameters, e.g. `move(base, p1)`.
    pub fn action_text(&self, a: ActionId) -> String {
        self.action_text_in(&self.plan, a)
    }

    /// [`Self::action_text`] of an action of another plan (e.g. a replanning's).
    pub fn action_text_in(&self, plan: &PartialPlan, a: ActionId) -> String {
        plan.action_text(a)
    }

    /// `START a p_a i_a`: the task name and its grounded parameters in vehicle terms.
    pub fn start_command(&self, a: ActionId, vid: u64) -> ActionStart {
        let act = self.plan.action(a);
        let task = self.plan.domain().task(act.task);
        let home = self.plan.problem().home;
        let mut args = Vec::new();
        for (i, p) in task.params().iter().enumerate() {
            let v = act.vars[i];
            let arg = match self
                .plan
                .bindings()
                .value(mavtempo_temporal::plan::STerm::Var(v))
            {
                Some(mavtempo_temporal::model::Value::Obj(o)) => {
                    let (name, obj) = (
                        self.plan.problem().object_name(o).to_string(),
                        self.plan.problem().object(o),
                    );
                    match obj.and_then(|ob| ob.local(home.as_ref())) {
                        Some((e, n, u)) => Arg::location(&name, Enu::new(e, n, u)),
                        None => Arg::Symbol(name),
                    }
                }
                _ => Arg::Symbol(self.plan.term_name(mavtempo_temporal::plan::STerm::Var(v))),
            };
            args.push((p.name.trim_start_matches('?').to_string(), arg));
        }
        ActionStart {
            id: vid,
            task: task.name.clone(),
            args,
        }
    }

    /// The resource named `name` in the domain.
    pub fn resource(&self, name: &str) -> Option<ResourceId> {
        self.plan.domain().resource_id(name)
    }

    /// Goal fates in the order of the problem, then the goals refused before they entered the plan, then
    /// those whose insertion is still in progress (pending).
    pub fn goal_fates(&self) -> Vec<GoalFate> {
        let inserting = self.insertions.iter().map(|i| GoalFate {
            name: i.goal.name.clone(),
            fate: Fate::Pending,
            reason: Some(FateReason::Inserting),
        });
        self.fates
            .values()
            .cloned()
            .chain(self.refused.iter().cloned())
            .chain(inserting)
            .collect()
    }

    pub fn set_fate(&mut self, g: GoalId, fate: Fate, reason: Option<FateReason>) {
        if let Some(f) = self.fates.get_mut(&g) {
            f.fate = fate.clone();
            f.reason = reason.clone();
        }
        // The ground station that uploaded it is told how it ended (its held list stays true).
        if fate != Fate::Pending {
            if let Some(w) = self.watches.remove(&g) {
                w.tell(match (fate, reason) {
                    (Fate::Achieved, _) => GoalVerdict::Achieved,
                    (Fate::Cancelled, r) => {
                        GoalVerdict::Cancelled(r.map_or(String::new(), |r| r.operator_text()))
                    }
                    (_, r) => GoalVerdict::Rejected(r.map_or(String::new(), |r| r.operator_text())),
                });
            }
        }
    }

    /// *ExecutingPlan*.
    pub fn plan(&self) -> &PartialPlan {
        &self.plan
    }

    pub fn config(&self) -> &ExecConfig {
        &self.cfg
    }

    pub fn counters(&self) -> &Counters {
        &self.counters
    }

    /// The cycles run so far: busy ones with their events, idle runs aggregated.
    pub fn cycles(&self) -> &CycleLog {
        &self.cycles
    }

    /// The events traced since the last cycle record.
    pub fn pending_events(&self) -> &[TraceEvent] {
        &self.pending_trace
    }

    /// Why execution is aborted, when it is (the caller then replans).
    pub fn abort(&self) -> Option<&AbortReason> {
        self.abort.as_ref()
    }

    /// The goals still pending (held, neither achieved nor rejected), in goal order.
    pub fn pending_goals(&self) -> Vec<GoalId> {
        self.fates
            .iter()
            .filter(|(_, f)| f.fate == Fate::Pending)
            .map(|(&g, _)| g)
            .collect()
    }

    /// The fates of the goals in the plan, by goal (see [`Self::goal_fates`] for every goal requested).
    pub fn fates(&self) -> &BTreeMap<GoalId, GoalFate> {
        &self.fates
    }

    /// The complete replannings of this mission.
    pub fn replannings(&self) -> &[super::replan_record::ReplanRecord] {
        &self.replannings
    }

    /// LgcS_t: the last known values.
    pub fn state(&self) -> &State {
        &self.state
    }

    /// The aggregated level `[lev_lb, lev_ub]` of each resource due to the actions that left the plan.
    pub fn past_levels(&self) -> &[(f64, f64)] {
        self.ledger.levels()
    }

    /// Whether action `a` was started (`START` sent) and is still remembered as such.
    pub fn has_started(&self, a: ActionId) -> bool {
        self.dispatched.is_started(a)
    }

    /// The names of the new goals waiting for, or in, their insertion attempt, in the order they are tried.
    pub fn insertion_queue(&self) -> Vec<&str> {
        self.insertions
            .iter()
            .map(|i| i.goal.name.as_str())
            .collect()
    }

    /// Whether an upload is still waiting for a goal's verdict.
    pub fn has_unanswered_uploads(&self) -> bool {
        !self.goal_batches.is_empty()
    }

    /// Reported levels within their resource's `resolution + tolerance` (`[resources]` of the vehicle
    /// configuration, [`mavtempo_vehicle::config::ResourceNames::level_tolerance`]: the one rule of
    /// `demo`, `soak` and `run`) of `[RscL_lb, RscL_ub]` are in bounds: noise, not news.
    pub fn with_resource_levels(mut self, r: &mavtempo_vehicle::config::ResourceNames) -> Self {
        let eps = super::resource_report::EPS;
        let tolerances = self
            .plan
            .domain()
            .resources
            .iter()
            .map(|res| r.level_tolerance(&res.name).unwrap_or(eps).max(eps))
            .collect();
        self.ledger.set_tolerances(tolerances);
        self
    }

    /// The vehicle time (ms) of the plan's origin: report times are converted with it.
    pub fn set_vehicle_origin(&mut self, ms: u64) {
        self.vehicle_origin_ms = ms;
    }

    /// The plan is not executable any more: this cycle aborts and a complete replanning follows (§3.6; the
    /// next [`Self::replan`] says why). The only way to abort, inside the cycle or from outside it. The first
    /// reason is kept: what follows it before the replanning (a timeout, a failed repair) is its
    /// consequence, not its cause.
    pub fn abort_with(&mut self, reason: AbortReason) {
        if self.abort.is_none() {
            self.abort = Some(reason);
        }
    }

    /// A value known from outside the messages (e.g. a state restored at start) enters LgcS_t at `t`.
    pub fn set_state_value(
        &mut self,
        key: super::p_t::AttrInstance,
        t: Time,
        value: mavtempo_temporal::model::Value,
    ) {
        self.state.set(key, t, value);
    }

    /// The aggregated past level of resource `r` is `[lb, ub]` (e.g. a level measured before the start).
    pub fn set_past_level(&mut self, r: ResourceId, level: (f64, f64)) {
        self.ledger.set(r, level);
    }

    /// Seed 1 §3.3 "Goal request" straight into *ExecutingPlan* (no insertion attempt beside it): the
    /// acceptance test at `now`, then the goal is an open condition left to plan repair.
    pub fn request_goal(
        &mut self,
        goal: mavtempo_temporal::model::Goal,
        now: Time,
    ) -> Result<GoalId, super::goal_request::Rejection> {
        let name = goal.name.clone();
        let running = super::p_t::classify(&self.plan, now).running;
        let g = super::goal_request::request(self.plan.edit(), goal, now, &running)?;
        self.fates.insert(
            g,
            GoalFate {
                name,
                fate: Fate::Pending,
                reason: None,
            },
        );
        self.repair.request();
        Ok(g)
    }

    /// The current time floor for new timepoints (§3.4: after the end of the current cycle).
    pub fn cycle_end(&self, now: Time) -> Time {
        now + self.cfg.timestep_ms
    }
}
