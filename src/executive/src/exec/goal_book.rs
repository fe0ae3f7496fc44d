//! The goal book: every goal requested and how it stands — held in the plan (its fate), refused before it
//! entered, waiting for or in its insertion attempt, parked for another attempt — with the uploads they came
//! in and the ground stations told how each held goal ends. A held goal's watch is told once, when its fate
//! becomes final; a verdict goes to the upload it came in. The rules that decide fates are elsewhere
//! (src/executive/src/exec/goal_insertion.rs, goal_retry.rs, settle.rs, replan.rs); this file keeps the
//! records consistent.

use std::collections::{BTreeMap, VecDeque};

use serde::Serialize;

use super::insertion::{Insertion, Parked};
use super::outcome::FateReason;
use mavtempo_temporal::model::GoalId;
use mavtempo_temporal::plan::PartialPlan;
use mavtempo_vehicle::goals::{GoalBatch, GoalWatch};
use mavtempo_vehicle::GoalVerdict;

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
    fn pending(name: &str) -> Self {
        GoalFate {
            name: name.to_string(),
            fate: Fate::Pending,
            reason: None,
        }
    }

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

#[derive(Default)]
pub(crate) struct GoalBook {
    /// The goals held in the plan (or once held), by goal.
    fates: BTreeMap<GoalId, GoalFate>,
    /// Requested goals that never entered the plan, in the order they were refused.
    refused: Vec<GoalFate>,
    /// New goals waiting for, or in, their insertion attempt (the front one is in progress).
    insertions: VecDeque<Insertion>,
    /// New goals rejected for a reason that may stop holding, waiting to be tried again.
    parked: Vec<Parked>,
    /// Uploads not answered yet, or with goals still being inserted, by number.
    batches: BTreeMap<u64, GoalBatch>,
    next_batch: u64,
    /// Uploaded goals held in the plan: their ground station is told how each ends.
    watches: BTreeMap<GoalId, GoalWatch>,
}

impl GoalBook {
    /// The goals of a solution plan, all pending.
    pub(crate) fn of_plan(plan: &PartialPlan) -> Self {
        let mut book = GoalBook::default();
        for pg in plan.goals() {
            if let Some(g) = plan.problem().goals.get(pg.goal.index()) {
                book.fates.insert(pg.goal, GoalFate::pending(&g.name));
            }
        }
        book
    }

    /// Goal `g` (named `name`) is held in the plan, pending; `watch` is told how it ends.
    pub(crate) fn hold(&mut self, g: GoalId, name: &str, watch: Option<GoalWatch>) {
        self.fates.insert(g, GoalFate::pending(name));
        if let Some(w) = watch {
            self.watches.insert(g, w);
        }
    }

    /// A held goal's fate; once it is final, its ground station is told (its held list stays true).
    pub(crate) fn set_fate(&mut self, g: GoalId, fate: Fate, reason: Option<FateReason>) {
        if let Some(f) = self.fates.get_mut(&g) {
            f.fate = fate.clone();
            f.reason = reason.clone();
        }
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

    pub(crate) fn fate(&self, g: GoalId) -> Option<&GoalFate> {
        self.fates.get(&g)
    }

    /// Whether held goal `g` is still pending.
    pub(crate) fn is_pending(&self, g: GoalId) -> bool {
        self.fates.get(&g).is_some_and(|f| f.fate == Fate::Pending)
    }

    pub(crate) fn fates(&self) -> &BTreeMap<GoalId, GoalFate> {
        &self.fates
    }

    /// The held goals still pending, in goal order.
    pub(crate) fn pending_goals(&self) -> Vec<GoalId> {
        self.fates
            .iter()
            .filter(|(_, f)| f.fate == Fate::Pending)
            .map(|(&g, _)| g)
            .collect()
    }

    /// Whether some goal is still to be had: held and pending, or on its way in.
    pub(crate) fn any_open(&self) -> bool {
        self.fates.values().any(|f| f.fate == Fate::Pending) || !self.insertions.is_empty()
    }

    /// Held goals in goal order, then those refused, then those being inserted (pending).
    pub(crate) fn goal_fates(&self) -> Vec<GoalFate> {
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

    /// A requested goal left before it entered the plan (rejected or cancelled).
    pub(crate) fn never_held(&mut self, name: &str, fate: Fate, reason: FateReason) {
        self.refused.push(GoalFate {
            name: name.to_string(),
            fate,
            reason: Some(reason),
        });
    }

    /// The last refusal of goal `name` is withdrawn (it is tried again).
    pub(crate) fn withdraw_refusal(&mut self, name: &str) {
        if let Some(k) = self.refused.iter().rposition(|f| f.name == name) {
            self.refused.remove(k);
        }
    }

    /// An upload enters the book; its number is where its goals' verdicts go.
    pub(crate) fn next_batch_number(&mut self) -> u64 {
        let number = self.next_batch;
        self.next_batch += 1;
        number
    }

    pub(crate) fn add_batch(&mut self, number: u64, batch: GoalBatch) {
        self.batches.insert(number, batch);
    }

    /// The verdict of goal `i` of upload `batch`.
    pub(crate) fn decide(&mut self, (batch, i): (u64, usize), verdict: GoalVerdict) {
        if let Some(b) = self.batches.get_mut(&batch) {
            b.decide(i, verdict);
        }
    }

    /// Answers the uploads not answered yet and forgets those whose every goal has its final verdict.
    pub(crate) fn answer_batches(&mut self) {
        for b in self.batches.values_mut() {
            b.answer_now();
        }
        self.batches.retain(|_, b| !b.settled());
    }

    pub(crate) fn has_unanswered_uploads(&self) -> bool {
        !self.batches.is_empty()
    }

    /// Behind the attempt in progress and every waiting goal of at least its priority.
    pub(crate) fn queue_insertion(&mut self, ins: Insertion) {
        let at = self
            .insertions
            .iter()
            .position(|q| !q.started() && q.goal.priority < ins.goal.priority)
            .unwrap_or(self.insertions.len());
        self.insertions.insert(at, ins);
    }

    /// A goal tried again: last in the queue.
    pub(crate) fn requeue(&mut self, ins: Insertion) {
        self.insertions.push_back(ins);
    }

    pub(crate) fn is_inserting(&self) -> bool {
        !self.insertions.is_empty()
    }

    pub(crate) fn insertions(&self) -> impl Iterator<Item = &Insertion> {
        self.insertions.iter()
    }

    /// The attempt in progress (or next).
    pub(crate) fn current(&self) -> Option<&Insertion> {
        self.insertions.front()
    }

    pub(crate) fn current_mut(&mut self) -> Option<&mut Insertion> {
        self.insertions.front_mut()
    }

    /// The attempt in progress ended.
    pub(crate) fn take_current(&mut self) -> Option<Insertion> {
        self.insertions.pop_front()
    }

    /// The waiting or ongoing insertion of goal `name`, taken out of the queue.
    pub(crate) fn take_insertion_named(&mut self, name: &str) -> Option<Insertion> {
        let k = self.insertions.iter().position(|i| i.goal.name == name)?;
        self.insertions.remove(k)
    }

    pub(crate) fn park(&mut self, p: Parked) {
        self.parked.push(p);
    }

    /// The first parked goal for which `ready` holds, taken out.
    pub(crate) fn unpark_first(&mut self, ready: impl Fn(&Parked) -> bool) -> Option<Parked> {
        let i = self.parked.iter().position(ready)?;
        Some(self.parked.remove(i))
    }

    pub(crate) fn has_parked(&self) -> bool {
        !self.parked.is_empty()
    }

    pub(crate) fn parked(&self) -> impl Iterator<Item = &Parked> {
        self.parked.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mavtempo_temporal::model::{AttrId, Goal, GoalOrigin, TimeInterval, Value};

    fn waiting(name: &str, priority: i64) -> Insertion {
        Insertion {
            goal: Goal {
                name: name.to_string(),
                kind: GoalOrigin::External,
                priority,
                attr: AttrId(0),
                args: Vec::new(),
                value: Value::Unknown,
                start_window: TimeInterval::at_least(0),
                duration: TimeInterval::exactly(0),
                achieve: 0,
            },
            reply: (0, 0),
            search: None,
            steps: 0,
            cycles: 0,
            id: None,
            watch: None,
            tries: 1,
        }
    }

    fn queue(book: &GoalBook) -> Vec<&str> {
        book.insertions().map(|i| i.goal.name.as_str()).collect()
    }

    #[test]
    fn insertions_wait_by_priority_and_a_goal_on_its_way_in_is_open() {
        let mut book = GoalBook::default();
        assert!(!book.any_open());
        book.queue_insertion(waiting("low", 1));
        book.queue_insertion(waiting("high", 5));
        book.queue_insertion(waiting("high2", 5));
        assert_eq!(queue(&book), ["high", "high2", "low"]);
        assert!(book.any_open());
        // The one in progress keeps its place whatever arrives.
        if let Some(front) = book.current_mut() {
            front.cycles = 1;
        }
        book.queue_insertion(waiting("urgent", 9));
        assert_eq!(queue(&book), ["high", "urgent", "high2", "low"]);
        assert!(book.take_insertion_named("high2").is_some());
        assert!(book.take_insertion_named("high2").is_none());
        assert_eq!(queue(&book), ["high", "urgent", "low"]);
    }

    #[test]
    fn a_refusal_withdrawn_leaves_the_goal_out_of_the_fates_until_its_next_verdict() {
        let mut book = GoalBook::default();
        let reason = FateReason::Inserting;
        book.never_held("g", Fate::Rejected, reason.clone());
        book.never_held("h", Fate::Rejected, reason);
        book.withdraw_refusal("g");
        let names: Vec<_> = book.goal_fates().into_iter().map(|f| f.name).collect();
        assert_eq!(names, ["h"]);
        book.hold(GoalId(3), "g", None);
        assert!(book.is_pending(GoalId(3)));
        book.set_fate(GoalId(3), Fate::Achieved, None);
        assert!(!book.is_pending(GoalId(3)) && book.pending_goals().is_empty());
    }
}
