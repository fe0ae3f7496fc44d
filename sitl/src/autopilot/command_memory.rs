//! Idempotent command answers over a lossy radio: the last command of each kind from each sender and the
//! result it was acknowledged with. A frame the link duplicated (same sequence number) or a re-sent
//! COMMAND_LONG (`confirmation` > 0, same parameters) is answered with that result again instead of being
//! executed twice: the re-sent capture does not take a second picture, the re-sent downlink start is told
//! IN_PROGRESS rather than TEMPORARILY_REJECTED, a HOLD re-sent after its ACK was lost does not override the
//! move commanded since. A re-sent copy must come soon after the previous one, with a higher `confirmation`.

use std::collections::HashMap;

use mavlink::dialects::ardupilotmega::{MavCmd, MavResult};

use super::commands::Cmd;

/// What a command was answered with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Answer {
    pub result: MavResult,
    pub progress: u8,
}

#[derive(Debug, Clone)]
struct Entry {
    p: [f32; 7],
    int: Option<(i32, i32)>,
    seq: u8,
    /// The highest `confirmation` seen of it, and when (sim ms) its last copy came.
    confirmation: u8,
    seen_ms: u64,
    answer: Option<Answer>,
}

/// A re-sent copy comes within this long (sim ms) of the previous one (the sender's ACK timeout, with
/// margin); later, the same command re-sent is a new request whose first copy was lost (e.g. the next
/// picture, taken with the same parameters).
pub const RESEND_WINDOW_MS: u64 = 5_000;

/// Key: sender's system and component, command id.
type Key = (u8, u8, u32);

#[derive(Debug, Default)]
pub struct CommandMemory {
    last: HashMap<Key, Entry>,
}

/// Commands that ask for a message: harmless to do twice, and a re-sent one wants the message.
fn is_request(cmd: MavCmd) -> bool {
    matches!(
        cmd,
        MavCmd::MAV_CMD_REQUEST_MESSAGE
            | MavCmd::MAV_CMD_REQUEST_AUTOPILOT_CAPABILITIES
            | MavCmd::MAV_CMD_GET_HOME_POSITION
            | MavCmd::MAV_CMD_SET_MESSAGE_INTERVAL
    )
}

fn key(c: &Cmd) -> Key {
    (c.from.sysid, c.from.compid, c.command as u32)
}

impl CommandMemory {
    /// The answer to give again when `c` is a duplicate or a re-sent copy of the last command of its kind;
    /// otherwise `c` is remembered as the command now executed.
    pub fn repeat(&mut self, c: &Cmd, now_ms: u64) -> Option<Answer> {
        if is_request(c.command) {
            // Asking again is asking for the message again: always answered in full.
            return None;
        }
        let k = key(c);
        let int = c.int.map(|(x, y, _)| (x, y));
        if let Some(e) = self.last.get_mut(&k) {
            let same = e.int == int
                && e.p
                    .iter()
                    .zip(&c.p)
                    .all(|(a, b)| a.to_bits() == b.to_bits());
            let duplicate = e.seq == c.seq;
            let resent = c.confirmation > e.confirmation
                && now_ms.saturating_sub(e.seen_ms) <= RESEND_WINDOW_MS;
            if same && (duplicate || resent) {
                e.confirmation = e.confirmation.max(c.confirmation);
                e.seen_ms = now_ms;
                if let Some(answer) = e.answer {
                    return Some(answer);
                }
            }
        }
        self.last.insert(
            k,
            Entry {
                p: c.p,
                int,
                seq: c.seq,
                confirmation: c.confirmation,
                seen_ms: now_ms,
                answer: None,
            },
        );
        None
    }

    /// The last command of its kind from this sender was answered (again, for a long-running one: its
    /// final ACK). Only what was done is answered again: a refused command is executed again when re-sent
    /// (nothing happened the first time).
    pub fn answered(&mut self, sysid: u8, compid: u8, command: MavCmd, answer: Answer) {
        if let Some(e) = self.last.get_mut(&(sysid, compid, command as u32)) {
            let done = matches!(
                answer.result,
                MavResult::MAV_RESULT_ACCEPTED | MavResult::MAV_RESULT_IN_PROGRESS
            );
            e.answer = done.then_some(answer);
        }
    }

    /// A reboot forgets everything.
    pub fn clear(&mut self) {
        self.last.clear();
    }
}
