//! The executive's answers to ground-station uploads and clears, on the link's side: an upload waits for its
//! answer (the verdicts of its new goals, the confirmation of the goals it cancels); past a deadline it is
//! answered with what is known, never "accepted" before the executive said so (a goal not decided yet is
//! "received, verdict to follow"). The verdicts that come after the answer, and each goal's end (achieved,
//! rejected by a replanning, cancelled), follow as STATUSTEXTs and keep the held list true.

use std::time::Instant;

use mavlink::dialects::ardupilotmega::MavMessage;
use tokio::sync::{mpsc, oneshot};

use super::goals::{LaterVerdicts, SyntacticDecider};
use super::intake::{GoalIntake, PendingDecision};
use super::types::{GoalRequest, GoalVerdict};

/// An upload (or a clear) handed to the executive, not answered yet.
pub struct Awaiting {
    pub pending: PendingDecision,
    /// The verdicts of its new goals (`None`: it has none).
    pub rx: Option<oneshot::Receiver<Vec<GoalVerdict>>>,
    /// The names the executive withdrew (`None`: nothing to cancel).
    pub cancel_rx: Option<oneshot::Receiver<Vec<String>>>,
    pub later: Option<LaterVerdicts>,
    pub deadline: Instant,
}

/// An answered upload whose goals' words may still come: the verdicts the answer did not wait for and the
/// goals' ends.
pub struct FollowUp {
    goals: Vec<GoalRequest>,
    /// The executive's first answer when the upload was answered before it came.
    first: Option<oneshot::Receiver<Vec<GoalVerdict>>>,
    later: Option<LaterVerdicts>,
}

impl FollowUp {
    fn tell(&self, i: usize, v: &GoalVerdict, intake: &mut GoalIntake, out: &mut Vec<MavMessage>) {
        if let Some(g) = self.goals.get(i) {
            intake.verdict(g, v, out);
            intake.settle(g, v);
        }
    }

    /// Sends the words that arrived; false once none can come any more.
    fn pump(&mut self, intake: &mut GoalIntake, out: &mut Vec<MavMessage>) -> bool {
        if let Some(rx) = &mut self.first {
            match rx.try_recv() {
                Ok(verdicts) => {
                    self.first = None;
                    for (i, v) in verdicts.iter().enumerate() {
                        if v.is_final() {
                            self.tell(i, v, intake, out);
                        }
                    }
                }
                Err(oneshot::error::TryRecvError::Empty) => {}
                Err(oneshot::error::TryRecvError::Closed) => self.first = None,
            }
        }
        let Some(later) = &mut self.later else {
            return self.first.is_some();
        };
        let mut got = Vec::new();
        let open = loop {
            match later.try_recv() {
                Ok(w) => got.push(w),
                Err(mpsc::error::TryRecvError::Empty) => break true,
                Err(mpsc::error::TryRecvError::Disconnected) => break false,
            }
        };
        for (i, v) in got {
            self.tell(i, &v, intake, out);
        }
        open || self.first.is_some()
    }
}

/// Answers the uploads whose verdicts came (or whose deadline passed: what is known so far, the rest to
/// follow; the syntactic verdicts only when the executive is gone) and sends the words that followed.
pub fn answer_uploads(
    intake: &mut GoalIntake,
    awaiting: &mut Vec<Awaiting>,
    following: &mut Vec<FollowUp>,
    now: Instant,
    out: &mut Vec<MavMessage>,
) {
    following.retain_mut(|f| f.pump(intake, out));
    let mut k = 0;
    while k < awaiting.len() {
        let a = &mut awaiting[k];
        let late = now >= a.deadline;
        let verdicts = match a.rx.as_mut().map(|rx| rx.try_recv()) {
            None => Some(Vec::new()),
            Some(Ok(v)) => {
                a.rx = None;
                Some(v)
            }
            Some(Err(oneshot::error::TryRecvError::Empty)) => None,
            Some(Err(oneshot::error::TryRecvError::Closed)) => {
                tracing::warn!("no goal decision from the executive: syntactic verdicts sent");
                a.rx = None;
                Some(
                    a.pending
                        .goals
                        .iter()
                        .map(SyntacticDecider::verdict)
                        .collect(),
                )
            }
        };
        let cancelled = match a.cancel_rx.as_mut().map(|rx| rx.try_recv()) {
            None => Some(Some(Vec::new())),
            Some(Ok(names)) => Some(Some(names)),
            Some(Err(oneshot::error::TryRecvError::Empty)) => None,
            Some(Err(oneshot::error::TryRecvError::Closed)) => Some(None),
        };
        if !late && (verdicts.is_none() || cancelled.is_none()) {
            k += 1;
            continue;
        }
        let a = awaiting.remove(k);
        let verdicts =
            verdicts.unwrap_or_else(|| vec![GoalVerdict::Inserting; a.pending.goals.len()]);
        let cancelled = if a.pending.cancel.is_empty() {
            Some(Vec::new())
        } else {
            cancelled.flatten()
        };
        let goals = a.pending.goals.clone();
        intake.decided(a.pending, &verdicts, cancelled, out);
        let mut f = FollowUp {
            goals,
            first: a.rx,
            later: a.later,
        };
        if f.pump(intake, out) {
            following.push(f);
        }
    }
}
