//! Command protocol client: COMMAND_LONG / COMMAND_INT → COMMAND_ACK, re-sent on ACK timeout (COMMAND_LONG with
//! `confirmation` incremented), IN_PROGRESS extending the wait, a give-up after the configured retries.
//! The timeout runs on the wall clock and on the vehicle's (time_boot_ms), whichever passes it first: a
//! simulator run faster than real time gets its lost ACKs re-sent in its own time, not 20 times later.

use mavlink::dialects::ardupilotmega::{
    MavCmd, MavMessage, MavResult, COMMAND_ACK_DATA, COMMAND_INT_DATA, COMMAND_LONG_DATA,
};

/// How far back the vehicle's clock must jump to be taken for a reboot.
pub const REBOOT_CLOCK_JUMP_MS: u64 = 5_000;

/// While the vehicle is heard, a command is tried this many times more than its configured tries.
pub const HEARD_RETRY_FACTOR: u32 = 3;

/// Who asked for a command (an action id, or an internal request).
pub type Token = u64;

#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    Long(COMMAND_LONG_DATA),
    Int(COMMAND_INT_DATA),
}

impl Command {
    pub fn id(&self) -> MavCmd {
        match self {
            Command::Long(c) => c.command,
            Command::Int(c) => c.command,
        }
    }

    fn message(&self) -> MavMessage {
        match self {
            Command::Long(c) => MavMessage::COMMAND_LONG(c.clone()),
            Command::Int(c) => MavMessage::COMMAND_INT(c.clone()),
        }
    }

    pub fn long(command: MavCmd, target: (u8, u8), p: [f32; 7]) -> Self {
        Command::Long(COMMAND_LONG_DATA {
            param1: p[0],
            param2: p[1],
            param3: p[2],
            param4: p[3],
            param5: p[4],
            param6: p[5],
            param7: p[6],
            command,
            target_system: target.0,
            target_component: target.1,
            confirmation: 0,
        })
    }
}

/// Commands that set the vehicle's mode (DO_REPOSITION switches to GUIDED): the latest one counts.
fn changes_mode(cmd: MavCmd) -> bool {
    matches!(
        cmd,
        MavCmd::MAV_CMD_DO_SET_MODE
            | MavCmd::MAV_CMD_DO_REPOSITION
            | MavCmd::MAV_CMD_NAV_RETURN_TO_LAUNCH
            | MavCmd::MAV_CMD_MISSION_START
    )
}

#[derive(Debug, Clone, PartialEq)]
pub enum CommandOutcome {
    Accepted,
    /// DENIED, FAILED, UNSUPPORTED, ... with the result.
    Rejected(MavResult),
    /// No ACK after all retries.
    TimedOut {
        tries: u32,
    },
}

#[derive(Debug)]
struct Pending {
    token: Token,
    cmd: Command,
    sent_ms: u64,
    /// The vehicle's clock when sent.
    sent_vms: u64,
    tries: u32,
    /// IN_PROGRESS received: wait for the final ACK without re-sending (the action's own timeout governs).
    in_progress: bool,
}

#[derive(Debug)]
pub struct CommandClient {
    pending: Vec<Pending>,
    pub ack_timeout_ms: u64,
    pub retries: u32,
    /// The vehicle's clock (ms since its boot), as telemetry last gave it.
    vnow: u64,
}

impl CommandClient {
    pub fn new(ack_timeout_ms: u64, retries: u32) -> Self {
        Self {
            pending: Vec::new(),
            ack_timeout_ms,
            retries,
            vnow: 0,
        }
    }

    /// The vehicle's clock advanced (or restarted, after a reboot: waits restart from there).
    /// A frame reordered on the link may carry a slightly older time: only a clock far behind is a reboot.
    pub fn set_vehicle_time(&mut self, vnow: u64) {
        if vnow.saturating_add(REBOOT_CLOCK_JUMP_MS) < self.vnow {
            for p in &mut self.pending {
                p.sent_vms = vnow;
            }
            self.vnow = vnow;
        }
        self.vnow = self.vnow.max(vnow);
    }

    /// Commands sent and not yet answered.
    pub fn pending(&self) -> usize {
        self.pending.len()
    }

    pub fn send(&mut self, token: Token, cmd: Command, now: u64, out: &mut Vec<MavMessage>) {
        if changes_mode(cmd.id()) {
            // The vehicle is told where to be now: an older mode command still re-sent (a HOLD whose ACK
            // was lost) would undo this one.
            self.pending.retain(|p| !changes_mode(p.cmd.id()));
        }
        out.push(cmd.message());
        self.pending.push(Pending {
            token,
            cmd,
            sent_ms: now,
            sent_vms: self.vnow,
            tries: 1,
            in_progress: false,
        });
    }

    /// Forgets the commands of `token` (its action ended).
    pub fn cancel(&mut self, token: Token) {
        self.pending.retain(|p| p.token != token);
    }

    /// Matches an ACK to the oldest pending command with the same id.
    pub fn on_ack(
        &mut self,
        ack: &COMMAND_ACK_DATA,
        now: u64,
    ) -> Option<(Token, MavCmd, CommandOutcome)> {
        tracing::debug!(command = ?ack.command, result = ?ack.result, vnow = self.vnow, "COMMAND_ACK");
        let i = self
            .pending
            .iter()
            .position(|p| p.cmd.id() == ack.command)?;
        match ack.result {
            MavResult::MAV_RESULT_IN_PROGRESS => {
                // Still working: re-sending would start it again.
                self.pending[i].sent_ms = now;
                self.pending[i].sent_vms = self.vnow;
                self.pending[i].in_progress = true;
                None
            }
            // "Retrying later should work" (e.g. a downlink whose stop is still on its way): tried again
            // after a timeout, as long as tries are left.
            MavResult::MAV_RESULT_TEMPORARILY_REJECTED if self.pending[i].tries <= self.retries => {
                self.pending[i].sent_ms = now;
                self.pending[i].sent_vms = self.vnow;
                None
            }
            MavResult::MAV_RESULT_ACCEPTED => {
                let p = self.pending.remove(i);
                Some((p.token, ack.command, CommandOutcome::Accepted))
            }
            other => {
                let p = self.pending.remove(i);
                Some((p.token, ack.command, CommandOutcome::Rejected(other)))
            }
        }
    }

    /// Re-sends what timed out; returns the commands given up on.
    pub fn tick(
        &mut self,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> Vec<(Token, MavCmd, CommandOutcome)> {
        let mut gave_up = Vec::new();
        let (timeout, retries, vnow) = (self.ack_timeout_ms, self.retries, self.vnow);
        self.pending.retain_mut(|p| {
            let waited = now
                .saturating_sub(p.sent_ms)
                .max(vnow.saturating_sub(p.sent_vms));
            if p.in_progress || waited < timeout {
                return true;
            }
            // The vehicle is heard (its clock ran the wait out) but not answering this command: a lossy
            // radio, not a dead link. Tried longer, within a bound.
            let heard = vnow.saturating_sub(p.sent_vms) >= timeout;
            let limit = if heard {
                retries
                    .saturating_add(1)
                    .saturating_mul(HEARD_RETRY_FACTOR)
                    .saturating_sub(1)
            } else {
                retries
            };
            if p.tries > limit {
                gave_up.push((
                    p.token,
                    p.cmd.id(),
                    CommandOutcome::TimedOut { tries: p.tries },
                ));
                return false;
            }
            if let Command::Long(c) = &mut p.cmd {
                c.confirmation = c.confirmation.wrapping_add(1);
            }
            p.tries += 1;
            p.sent_ms = now;
            p.sent_vms = vnow;
            tracing::debug!(command = ?p.cmd.id(), try_ = p.tries, vnow, "no COMMAND_ACK: re-sent");
            out.push(p.cmd.message());
            true
        });
        gave_up
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ack(command: MavCmd, result: MavResult) -> COMMAND_ACK_DATA {
        COMMAND_ACK_DATA {
            command,
            result,
            ..Default::default()
        }
    }

    /// Sends `MAV_CMD_USER_1` (param1..7 = `param`) as request `id` at time 0.
    fn send_user_1(c: &mut CommandClient, id: Token, param: f32, out: &mut Vec<MavMessage>) {
        let command = Command::long(MavCmd::MAV_CMD_USER_1, (1, 1), [param; 7]);
        c.send(id, command, 0, out);
    }

    #[test]
    fn retries_with_confirmation_incremented_then_gives_up() {
        let mut c = CommandClient::new(100, 2);
        let mut out = Vec::new();
        c.send(
            7,
            Command::long(
                MavCmd::MAV_CMD_DO_SET_MODE,
                (1, 1),
                [1.0, 4.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            ),
            0,
            &mut out,
        );
        assert!(c.tick(99, &mut out).is_empty());
        assert_eq!(out.len(), 1);
        assert!(c.tick(100, &mut out).is_empty());
        assert!(c.tick(200, &mut out).is_empty());
        let confirmations: Vec<u8> = out
            .iter()
            .map(|m| match m {
                MavMessage::COMMAND_LONG(l) => l.confirmation,
                _ => 255,
            })
            .collect();
        assert_eq!(confirmations, vec![0, 1, 2]);
        let gave_up = c.tick(300, &mut out);
        assert_eq!(
            gave_up,
            vec![(
                7,
                MavCmd::MAV_CMD_DO_SET_MODE,
                CommandOutcome::TimedOut { tries: 3 }
            )]
        );
    }

    #[test]
    fn the_vehicle_clock_times_out_a_lost_ack_before_the_wall_clock() {
        // A simulator at 20x: 2 s of vehicle time pass in 100 ms of wall time.
        let mut c = CommandClient::new(2_000, 1);
        let mut out = Vec::new();
        c.set_vehicle_time(10_000);
        c.send(
            3,
            Command::long(MavCmd::MAV_CMD_IMAGE_START_CAPTURE, (1, 1), [0.0; 7]),
            0,
            &mut out,
        );
        c.set_vehicle_time(11_999);
        assert!(c.tick(50, &mut out).is_empty());
        assert_eq!(out.len(), 1, "not yet: 1,999 ms of vehicle time");
        c.set_vehicle_time(12_000);
        assert!(c.tick(100, &mut out).is_empty());
        assert_eq!(
            out.len(),
            2,
            "re-sent after 2 s of vehicle time, 0.1 s of wall time"
        );
        // A reboot restarts the vehicle's clock: the wait restarts from there, not from 12 s.
        c.set_vehicle_time(500);
        assert!(c.tick(150, &mut out).is_empty());
        assert_eq!(out.len(), 2);
        // The vehicle is heard but does not answer: tried (1 + 1) x 3 times in all, then given up.
        for (i, t) in [2_500, 4_500, 6_500, 8_500].into_iter().enumerate() {
            c.set_vehicle_time(t);
            assert!(c.tick(200, &mut out).is_empty());
            assert_eq!(out.len(), 3 + i);
        }
        c.set_vehicle_time(10_500);
        assert_eq!(c.tick(200, &mut out).len(), 1, "then given up");
    }

    #[test]
    fn temporarily_rejected_is_tried_again_while_tries_are_left() {
        let mut c = CommandClient::new(100, 1);
        let mut out = Vec::new();
        send_user_1(&mut c, 2, 1.0, &mut out);
        let busy = ack(
            MavCmd::MAV_CMD_USER_1,
            MavResult::MAV_RESULT_TEMPORARILY_REJECTED,
        );
        assert_eq!(c.on_ack(&busy, 10), None);
        assert!(c.tick(109, &mut out).is_empty());
        assert!(c.tick(110, &mut out).is_empty());
        assert_eq!(out.len(), 2, "re-sent after a timeout");
        assert_eq!(
            c.on_ack(&busy, 120),
            Some((
                2,
                MavCmd::MAV_CMD_USER_1,
                CommandOutcome::Rejected(MavResult::MAV_RESULT_TEMPORARILY_REJECTED)
            )),
            "no tries left"
        );
    }

    #[test]
    fn in_progress_extends_and_result_is_delivered() {
        let mut c = CommandClient::new(100, 0);
        let mut out = Vec::new();
        send_user_1(&mut c, 1, 0.0, &mut out);
        assert_eq!(
            c.on_ack(
                &ack(MavCmd::MAV_CMD_USER_1, MavResult::MAV_RESULT_IN_PROGRESS),
                90
            ),
            None
        );
        assert!(
            c.tick(10_000, &mut out).is_empty(),
            "in progress: no re-send, no give-up"
        );
        assert_eq!(out.len(), 1);
        let got = c.on_ack(
            &ack(MavCmd::MAV_CMD_USER_1, MavResult::MAV_RESULT_DENIED),
            160,
        );
        assert_eq!(
            got,
            Some((
                1,
                MavCmd::MAV_CMD_USER_1,
                CommandOutcome::Rejected(MavResult::MAV_RESULT_DENIED)
            ))
        );
        assert_eq!(
            c.on_ack(
                &ack(MavCmd::MAV_CMD_USER_1, MavResult::MAV_RESULT_ACCEPTED),
                170
            ),
            None
        );
    }
}
