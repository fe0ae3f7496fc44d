//! Acting (seed 1 §3.5, Figure 1): the timepoints to execute now (*ExecTPs*: executable, with an execution
//! time `t_exec ≤ now`), recomputed after each execution. Seed 1 executes those whose `t_exec` falls before
//! the end of the cycle; this executive wakes at the next `t_exec` instead (the `next` it returns), so a
//! timepoint executes at its `t_exec`, not up to `ts` early (docs/departures.md); starts of executable
//! actions launch them (`START`), ends of preemptive actions stop them (`END`, their time is set by the
//! report), goal timepoints are executed when the goal is achievable; non-executable actions and
//! non-achievable goals are postponed while flexibility remains, and so are those that a wait of the plan's
//! dispatchable network holds until a contingent end is observed ([`super::squeeze`]: dynamic
//! controllability, so that no running action's duration is squeezed); timeouts when a timepoint's upper bound
//! passes unexecuted.

use super::dispatch_policy::Candidate;
use super::executable::{action_executable, goal_achievable, timepoint_executable};
use super::executive::{Executive, Fate};
use super::outcome::AbortReason;
use super::p_t::classify;
use super::squeeze::should_wait;
use super::t_exec::{t_exec, TpKind};
use super::trace::TraceEvent;
use mavtempo_temporal::model::{Preemption, Time};
use mavtempo_temporal::plan::{ActionId, DcPlan, Owner, PartialPlan};
use mavtempo_vehicle::Vehicle;

impl Executive {
    /// The act part at time `now`; returns the next time something is due (to sleep until).
    pub fn act(&mut self, vehicle: &mut dyn Vehicle, now: Time) -> Option<Time> {
        let ts = self.cfg.timestep_ms;
        let mut next: Option<Time> = None;
        let wake = |t: Time, next: &mut Option<Time>| {
            if t > now {
                *next = Some(next.map_or(t, |n: Time| n.min(t)));
            }
        };
        for a in self.dispatched.take_stop_requests() {
            self.stop(vehicle, a);
        }
        self.execute_timed_facts(now, &mut next);
        let mut postponed: Vec<ActionId> = Vec::new();
        // A_t^f once per act part: executing timepoints only adds constraints, which can resolve flaws but
        // never create one, so this set stays a (conservative) superset while ExecTPs is recomputed.
        let flawed = self.plan.flawed_actions();
        loop {
            let running = self.dispatched.started_actions();
            let mut executed = false;
            let pt = classify(&self.plan, now);
            // The starts due now: each is weighed against the running actions and the others due now.
            let mut due: Vec<ActionId> = Vec::new();
            for &a in &pt.future {
                let st = self.plan.action(a).start;
                if self.plan.is_executed(st) {
                    continue;
                }
                let c = self.candidate(st, TpKind::Start);
                let Some(te) = self.policy.exec_time(&self.plan, Some(a), &c, ts) else {
                    continue;
                };
                if te > now {
                    wake(te, &mut next);
                } else if action_executable(&self.plan, a, now, &flawed) {
                    due.push(a);
                } else if !postponed.contains(&a) {
                    postponed.push(a);
                }
            }
            // The dispatchable network of the plan as it is in this pass (only when something is due).
            let mut dc: Option<DcPlan> = None;
            for &a in &due {
                let st = self.plan.action(a).start;
                let net = dc.get_or_insert_with(|| dispatch_network(&self.plan));
                if should_wait(&self.plan, net, &due, st, now, ts) {
                    if !postponed.contains(&a) {
                        postponed.push(a);
                    }
                } else {
                    executed |= self.launch(vehicle, a, now);
                }
            }
            for &a in &running {
                let act = self.plan.action(a);
                if act.removed || self.plan.is_executed(act.end) || self.dispatched.is_stopping(a) {
                    continue;
                }
                let pre = self.plan.domain().task(act.task).preemption;
                let c = self.candidate(act.end, TpKind::End(pre));
                if pre == Preemption::NonPreemptive {
                    wake(c.ub, &mut next);
                    continue;
                }
                let te = t_exec(c.kind, c.lb, c.ub, ts);
                if te <= now {
                    self.stop(vehicle, a);
                } else {
                    wake(te, &mut next);
                }
            }
            for i in 0..self.plan.goals().len() {
                let pg = self.plan.goals()[i].clone();
                if !pg.active || self.plan.is_executed(pg.et) {
                    continue;
                }
                if !self.plan.is_executed(pg.st) {
                    let c = self.candidate(pg.st, TpKind::Goal);
                    let te = t_exec(c.kind, c.lb, c.ub, ts);
                    if te > now {
                        wake(te, &mut next);
                        continue;
                    }
                    if !goal_achievable(&self.plan, pg.goal, now)
                        || should_wait(
                            &self.plan,
                            dc.get_or_insert_with(|| dispatch_network(&self.plan)),
                            &due,
                            pg.st,
                            now,
                            ts,
                        )
                    {
                        continue;
                    }
                    if self.plan.edit().execute_at(pg.st, now).is_err() {
                        continue;
                    }
                    executed = true;
                }
                let c = self.candidate(pg.et, TpKind::Goal);
                if c.lb > now {
                    wake(c.lb, &mut next);
                } else if timepoint_executable(self.plan.temporal_network(), pg.et, now)
                    && self.plan.edit().execute_at(pg.et, now).is_ok()
                {
                    executed = true;
                    let name = self.plan.problem().goals[pg.goal.index()].name.clone();
                    self.set_fate(pg.goal, Fate::Achieved, None);
                    self.trace(TraceEvent::GoalAchieved { goal: name });
                }
            }
            if !executed {
                break;
            }
        }
        for a in postponed {
            if !self.plan.is_executed(self.plan.action(a).start) {
                let action = self.action_text(a);
                self.trace(TraceEvent::Postponed { action });
            }
        }
        self.detect_timeouts(now);
        next
    }

    fn candidate(&self, tp: mavtempo_temporal::stn::Timepoint, kind: TpKind) -> Candidate {
        Candidate {
            tp,
            kind,
            lb: self.plan.earliest(tp),
            ub: self.plan.latest(tp),
        }
    }

    /// `START a p_a i_a`, and the start timepoint executed at `now`.
    fn launch(&mut self, vehicle: &mut dyn Vehicle, a: ActionId, now: Time) -> bool {
        let st = self.plan.action(a).start;
        if !timepoint_executable(self.plan.temporal_network(), st, now) {
            return false;
        }
        if let Err(e) = super::instantiate::instantiate_at_start(self.plan.edit(), a) {
            self.action_failed(a, &format!("cannot be instantiated ({e})"), now);
            let action = self.action_text(a);
            self.abort_with(AbortReason::CannotInstantiate { action, error: e });
            return false;
        }
        if let Some(reason) = self.launch_banned(a) {
            self.abort_with(reason);
            return false;
        }
        let vid = self.dispatched.new_id();
        let cmd = self.start_command(a, vid);
        let action = self.action_text(a);
        let started = if self.must_end_still(a) {
            vehicle.start_still(cmd)
        } else {
            vehicle.start(cmd)
        };
        if let Err(e) = started {
            self.action_failed(a, &format!("refused by the vehicle ({e})"), now);
            self.abort_with(AbortReason::StartRefused {
                action,
                error: e.to_string(),
            });
            return false;
        }
        if let Err(e) = self.plan.edit().execute_at(st, now) {
            self.abort_with(AbortReason::StartInconsistent {
                action,
                error: e.to_string(),
            });
            return false;
        }
        self.dispatched.started(a, vid);
        self.journal.launched();
        let inst = super::failures::Instance::of(&self.plan, a);
        self.failures.launched(inst, now);
        let end = self.plan.action(a).end;
        let (lb, ub) = (self.plan.earliest(end), self.plan.latest(end));
        let planned_end_ms = Some((lb, (ub < mavtempo_temporal::stn::INF).then_some(ub)));
        self.trace(TraceEvent::Launch {
            action,
            vid,
            planned_end_ms,
        });
        true
    }

    /// `END i_a` for a preemptive action (its end's time comes with the report).
    /// The problem's predicted timed facts (e.g. a visibility window opening) happen by themselves: their
    /// timepoints are executed when their time comes, so that the actions after them become executable.
    fn execute_timed_facts(&mut self, now: Time, next: &mut Option<Time>) {
        let tps: Vec<_> = self
            .plan
            .events()
            .iter()
            .filter(|e| matches!(e.owner, Owner::Exogenous(_)))
            .map(|e| e.at)
            .filter(|&tp| !self.plan.is_executed(tp))
            .collect();
        for tp in tps {
            let at = self.plan.earliest(tp);
            if at <= now {
                match self.plan.edit().execute_at(tp, at) {
                    // A timepoint executed: the repair in progress restarts from the plan as it is (§3.2).
                    Ok(()) => {}
                    Err(e) => tracing::warn!("timed fact at {at} ms: {e}"),
                }
            } else if next.is_none_or(|n| at < n) {
                *next = Some(at);
            }
        }
    }

    pub fn stop(&mut self, vehicle: &mut dyn Vehicle, a: ActionId) {
        let Some(vid) = self.dispatched.id_of(a) else {
            return;
        };
        if self.dispatched.is_stopping(a) {
            return;
        }
        let action = self.action_text(a);
        match vehicle.stop(vid) {
            Ok(()) => {
                self.dispatched.stop_sent(a);
                self.trace(TraceEvent::Stop { action, vid });
            }
            Err(e) => tracing::warn!(%action, "stop refused: {e}"),
        }
    }

    /// A timepoint whose upper bound passed unexecuted (a report that did not come, an action or goal that
    /// could not start in time): the plan is not executable any more.
    fn detect_timeouts(&mut self, now: Time) {
        let stn = self.plan.temporal_network();
        let mut late: Option<String> = None;
        let mut no_report: Vec<ActionId> = Vec::new();
        for a in self.plan.live_actions() {
            let act = self.plan.action(a);
            // The start first: an action that could not start in time is late at its start, not its end.
            let late_tp = [(act.start, "start"), (act.end, "end")]
                .into_iter()
                .find(|&(tp, _)| !stn.is_executed(tp) && stn.ub(tp) < now);
            if let Some((_, what)) = late_tp {
                late = Some(format!("{what} of {}", self.action_text(a)));
                if what == "end" && self.dispatched.is_started(a) {
                    no_report.push(a);
                }
            }
        }
        for a in no_report {
            self.action_failed(a, "sent no report by its latest end", now);
        }
        let stn = self.plan.temporal_network();
        for pg in self.plan.goals().iter().filter(|g| g.active) {
            if !stn.is_executed(pg.st) && stn.ub(pg.st) < now {
                late = Some(format!(
                    "start of goal {}",
                    self.plan.problem().goals[pg.goal.index()].name
                ));
            }
        }
        if let Some(timepoint) = late {
            self.trace(TraceEvent::Timeout {
                timepoint: timepoint.clone(),
            });
            self.abort_with(AbortReason::Timeout { timepoint });
        }
    }
}

/// The plan's dispatchable network; why a plan is not DC goes to the debug log (its waits still apply).
fn dispatch_network(plan: &PartialPlan) -> DcPlan {
    let (dc, why) = plan.dispatch_network();
    if let Some(why) = why {
        tracing::debug!(%why, "plan not dynamically controllable");
    }
    dc
}
