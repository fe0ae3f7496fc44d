//! The executive: the executing plan P_t and what it remembers between cycles. The cycle itself is in
//! [`super::cycle`], message integration in [`super::sense`], the act part in [`super::act`], plan repair in
//! [`super::repair`] and complete replanning in [`super::replan`].

use std::collections::BTreeMap;

use super::abort::Abort;
use super::abstraction::Hierarchy;
use super::clock::{wall_clock, SharedClock};
use super::config::ExecConfig;
use super::cycle_log::CycleLog;
use super::dispatch_policy::PlanDispatch;
use super::failures::FailureMemory;
use super::goal_book::GoalBook;
use super::journal::Journal;
use super::operator_hold::OperatorHold;
use super::outcome::{AbortReason, FateReason};
use super::p_t::State;
use super::repair_tree::RepairState;
use super::trace::{CycleRecord, TraceEvent};
use super::vehicle_binding::VehicleBinding;
use mavtempo_temporal::model::{GoalId, ResourceId, Time};
use mavtempo_temporal::plan::{ActionId, PartialPlan};
use mavtempo_vehicle::{ActionStart, Arg, Enu};

pub use super::goal_book::{Fate, GoalFate};
pub use super::journal::Counters;

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
    /// Started actions, their `i_a`, the stops sent and those requested.
    pub(crate) dispatched: super::dispatched::Dispatched,
    /// The vehicle's time origin, mapping, limits and still attribute.
    pub(crate) vehicle: VehicleBinding,
    /// Plan repair between cycles: the tree, the request, the episode's steps.
    pub(crate) repair: RepairState,
    /// Set when the plan is not executable any more: the cycle aborts and replans from scratch.
    pub(crate) abort: Abort,
    /// Every goal requested and how it stands, with the uploads they came in.
    pub(crate) goals: GoalBook,
    /// The cycles, the events of this one, the counters, the complete replannings.
    pub(crate) journal: Journal,
    /// Failures and plan changes of this mission: what repair cannot fix is settled (src/executive/src/exec/failures.rs).
    pub(crate) failures: FailureMemory,
    /// The operator has the vehicle (why): no action is launched or stopped (src/executive/src/exec/authority.rs).
    pub(crate) operator: OperatorHold,
    /// The companion's own time: the cycle's and the replanning's wall-time bounds and the per-part
    /// timings read it (a `WallClock` unless [`Executive::with_wall_clock`] gives another).
    pub(crate) wall: SharedClock,
}

impl Executive {
    /// An executive over a solution plan (the planner's output, or a hand-built plan in tests).
    pub fn new(plan: PartialPlan, cfg: ExecConfig) -> Self {
        let ledger = super::ledger::ResourceLedger::new(plan.problem());
        let goals = GoalBook::of_plan(&plan);
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
            vehicle: VehicleBinding::default(),
            repair: RepairState::default(),
            abort: Abort::default(),
            goals,
            journal: Journal::default(),
            failures,
            operator: OperatorHold::default(),
            wall: wall_clock(),
        }
    }

    /// The clock the wall-time bounds and the per-part timings read: a `ManualClock` in tests, which drives
    /// `cycle_max_wall_ms` and `replan_max_wall_ms` without waiting.
    pub fn with_wall_clock(mut self, clock: SharedClock) -> Self {
        self.wall = clock;
        self
    }

    /// Where the vehicle may go (`[limits]`, the autopilot's fence): a goal at a place outside is
    /// rejected when it arrives, with the distance and the limit.
    ///
    /// The planner keeps to them too: they become the problem's [`mavtempo_temporal::model::Legs`], so a
    /// move whose straight leg leaves them gets no distance and is no resolver, in plan repair, goal
    /// insertion and complete replanning alike (the one place move durations come from).
    pub fn with_limits(mut self, limits: Option<mavtempo_vehicle::limits::Limits>) -> Self {
        self.vehicle.set_limits(limits);
        if let Some(l) = self.vehicle.limits() {
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
                self.abort_with(AbortReason::NotExecutable { now_ms: 0, error });
            }
        }
        self
    }

    /// The vehicle configuration's `[mapping]`, resolved against this plan's domain
    /// ([`crate::config_check::check`]).
    pub fn with_mapping(mut self, mapping: crate::mapping::DomainMapping) -> Self {
        self.vehicle.mapping = mapping;
        self
    }

    pub fn trace(&mut self, e: TraceEvent) {
        self.journal.trace(e);
    }

    /// The events traced since the last cycle (an abort, a replanning and its rejections) as a record of
    /// their own at `now`, when there are any: how a mission that ends between cycles keeps them.
    pub fn flush_trace(&mut self, now: Time) -> Option<CycleRecord> {
        self.journal.flush(now)
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
        self.goals.goal_fates()
    }

    pub fn set_fate(&mut self, g: GoalId, fate: Fate, reason: Option<FateReason>) {
        self.goals.set_fate(g, fate, reason);
    }

    /// *ExecutingPlan*.
    pub fn plan(&self) -> &PartialPlan {
        &self.plan
    }

    pub fn config(&self) -> &ExecConfig {
        &self.cfg
    }

    pub fn counters(&self) -> &Counters {
        self.journal.counters()
    }

    /// The cycles run so far: busy ones with their events, idle runs aggregated.
    pub fn cycles(&self) -> &CycleLog {
        self.journal.cycles()
    }

    /// The events traced since the last cycle record.
    pub fn pending_events(&self) -> &[TraceEvent] {
        self.journal.pending()
    }

    /// Why execution is aborted, when it is (the caller then replans).
    pub fn abort(&self) -> Option<&AbortReason> {
        self.abort.reason()
    }

    /// The goals still pending (held, neither achieved nor rejected), in goal order.
    pub fn pending_goals(&self) -> Vec<GoalId> {
        self.goals.pending_goals()
    }

    /// The fates of the goals in the plan, by goal (see [`Self::goal_fates`] for every goal requested).
    pub fn fates(&self) -> &BTreeMap<GoalId, GoalFate> {
        self.goals.fates()
    }

    /// The complete replannings of this mission.
    pub fn replannings(&self) -> &[super::replan_record::ReplanRecord] {
        self.journal.replannings()
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
        self.goals
            .insertions()
            .map(|i| i.goal.name.as_str())
            .collect()
    }

    /// Whether an upload is still waiting for a goal's verdict.
    pub fn has_unanswered_uploads(&self) -> bool {
        self.goals.has_unanswered_uploads()
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
        self.vehicle.set_origin(ms);
    }

    /// The plan is not executable any more: this cycle aborts and a complete replanning follows (§3.6; the
    /// next [`Self::replan`] says why). The only way to abort, inside the cycle or from outside it. The first
    /// reason is kept: what follows it before the replanning (a timeout, a failed repair) is its
    /// consequence, not its cause.
    pub fn abort_with(&mut self, reason: AbortReason) {
        self.abort.raise(reason);
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
        self.goals.hold(g, &name, None);
        self.repair.request();
        Ok(g)
    }

    /// The current time floor for new timepoints (§3.4: after the end of the current cycle).
    pub fn cycle_end(&self, now: Time) -> Time {
        now + self.cfg.timestep_ms
    }
}
