//! The executive's answers to ground-station uploads, on the link's side: an upload waits for its answer
//! (MISSION_ACK and a STATUSTEXT per goal, or the syntactic verdicts past a deadline); a goal that was still
//! being inserted into the plan when the upload was answered gets its final STATUSTEXT when the executive
//! reaches it.

use std::time::Instant;

use mavlink::dialects::ardupilotmega::MavMessage;
use tokio::sync::{mpsc, oneshot};

use super::goals::{LaterVerdicts, SyntacticDecider};
use super::intake::{GoalIntake, PendingDecision};
use super::types::{GoalRequest, GoalVerdict};

/// An upload handed to the executive, not answered yet.
pub struct Awaiting {
    pub pending: PendingDecision,
    pub rx: oneshot::Receiver<Vec<GoalVerdict>>,
    pub later: LaterVerdicts,
    pub deadline: Instant,
}

/// An answered upload whose goals are not all decided: their verdicts follow.
pub struct FollowUp {
    goals: Vec<GoalRequest>,
    later: LaterVerdicts,
    open: usize,
}

impl FollowUp {
    /// Sends the verdicts that arrived; false once none can come any more.
    fn pump(&mut self, intake: &mut GoalIntake, out: &mut Vec<MavMessage>) -> bool {
        loop {
            match self.later.try_recv() {
                Ok((i, v)) => {
                    if let Some(g) = self.goals.get(i) {
                        intake.verdict(g, &v, out);
                        self.open = self.open.saturating_sub(1);
                    }
                }
                Err(mpsc::error::TryRecvError::Empty) => return self.open > 0,
                Err(mpsc::error::TryRecvError::Disconnected) => return false,
            }
        }
    }
}

/// Answers the uploads whose verdicts came (or whose deadline passed: syntactic verdicts, so the ground
/// station is not left hanging) and sends the verdicts that followed.
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
        let verdicts = match awaiting[k].rx.try_recv() {
            Ok(v) => v,
            Err(oneshot::error::TryRecvError::Empty) if now < awaiting[k].deadline => {
                k += 1;
                continue;
            }
            Err(_) => {
                tracing::warn!("no goal decision from the executive: syntactic verdicts sent");
                awaiting[k]
                    .pending
                    .goals
                    .iter()
                    .map(SyntacticDecider::verdict)
                    .collect()
            }
        };
        let a = awaiting.remove(k);
        let open = verdicts.iter().filter(|v| !v.is_final()).count();
        let goals = a.pending.goals.clone();
        intake.decided(a.pending, &verdicts, out);
        let mut f = FollowUp {
            goals,
            later: a.later,
            open,
        };
        if open > 0 && f.pump(intake, out) {
            following.push(f);
        }
    }
}
