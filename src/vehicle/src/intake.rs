//! Goal intake: the companion's side of the mission protocol for items addressed to component 191. An upload
//! becomes goal requests ([`super::goals::items_to_goals`]); once the decider has answered, MISSION_ACK and one
//! STATUSTEXT per goal go back (a goal still being inserted into the plan then gets its final STATUSTEXT
//! later, [`GoalIntake::verdict`]). The accepted list can be downloaded again (MISSION_REQUEST_LIST). When
//! the configuration names the ground stations allowed to send goals (`link.goal_sysids`), uploads and
//! clears from any other system are answered MISSION_ACK DENIED with the reason.

// The legacy MISSION_ITEM / MISSION_REQUEST must still be accepted (ArduPilot sends MISSION_REQUEST).
#![allow(deprecated)]

use mavlink::dialects::ardupilotmega::{
    MavMessage, MavMissionResult, MavMissionType, MavSeverity, MISSION_ACK_DATA,
    MISSION_COUNT_DATA, MISSION_REQUEST_INT_DATA, STATUSTEXT_DATA,
};
use mavlink::MavHeader;

use super::driver::COMPANION_COMPONENT;
use super::goals::{items_to_goals, verdict_text, KnownLocations};
use super::items::MissionItem;
use super::types::{GoalRequest, GoalVerdict};

/// STATUSTEXT(s) for `text`: chunks of 50 bytes sharing a non-zero id when longer than one message. A
/// receiver knows a chunked text is complete when a chunk holds a NUL (is shorter than 50 bytes): a text
/// whose length is a multiple of 50 gets an empty last chunk.
pub fn statustext(text: &str, severity: MavSeverity, id: u16) -> Vec<MavMessage> {
    let bytes = text.as_bytes();
    let mut chunks: Vec<&[u8]> = if bytes.is_empty() {
        vec![&[][..]]
    } else {
        bytes.chunks(50).collect()
    };
    if chunks.len() > 1 && bytes.len().is_multiple_of(50) {
        chunks.push(&[][..]);
    }
    let single = chunks.len() == 1;
    chunks
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let mut arr = [0u8; 50];
            arr[..c.len()].copy_from_slice(c);
            MavMessage::STATUSTEXT(STATUSTEXT_DATA {
                severity,
                text: arr.into(),
                id: if single { 0 } else { id },
                chunk_seq: i as u8,
            })
        })
        .collect()
}

#[derive(Debug)]
struct Upload {
    peer: (u8, u8),
    items: Vec<MissionItem>,
    count: u16,
    last_ms: u64,
    retries_left: u32,
}

/// A completed upload waiting for the decider.
#[derive(Debug, Clone)]
pub struct PendingDecision {
    pub peer: (u8, u8),
    pub goals: Vec<GoalRequest>,
    items: Vec<MissionItem>,
}

pub struct GoalIntake {
    pub known: KnownLocations,
    next_goal_number: u32,
    upload: Option<Upload>,
    accepted: Vec<MissionItem>,
    /// The ground station downloading the goal list (requests from anyone else are not ours to answer).
    downloader: Option<(u8, u8)>,
    pub timeout_ms: u64,
    pub retries: u32,
    text_id: u16,
    /// The system ids goals are taken from; `None`: any.
    allowed_systems: Option<Vec<u8>>,
}

impl GoalIntake {
    pub fn new(known: KnownLocations, first_goal_number: u32) -> Self {
        Self {
            known,
            next_goal_number: first_goal_number,
            upload: None,
            accepted: Vec::new(),
            downloader: None,
            timeout_ms: 1500,
            retries: 5,
            text_id: 0,
            allowed_systems: None,
        }
    }

    /// Goals taken only from these system ids (`None`: from any).
    pub fn allowing(mut self, systems: Option<Vec<u8>>) -> Self {
        self.allowed_systems = systems;
        self
    }

    /// When `peer` may not send goals: DENIED and the reason, and true.
    fn refused_sender(&mut self, peer: (u8, u8), out: &mut Vec<MavMessage>) -> bool {
        let Some(allowed) = &self.allowed_systems else {
            return false;
        };
        if allowed.contains(&peer.0) {
            return false;
        }
        let list: Vec<String> = allowed.iter().map(u8::to_string).collect();
        let text = format!(
            "goals from system {} refused: link.goal_sysids allows {}",
            peer.0,
            list.join(", ")
        );
        tracing::warn!("{text}");
        out.push(Self::ack(peer, MavMissionResult::MAV_MISSION_DENIED));
        self.texts(&text, MavSeverity::MAV_SEVERITY_WARNING, out);
        true
    }

    fn ack(peer: (u8, u8), result: MavMissionResult) -> MavMessage {
        MavMessage::MISSION_ACK(MISSION_ACK_DATA {
            target_system: peer.0,
            target_component: peer.1,
            mavtype: result,
            mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
            opaque_id: 0,
        })
    }

    fn request(peer: (u8, u8), seq: u16) -> MavMessage {
        MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
            seq,
            target_system: peer.0,
            target_component: peer.1,
            mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
        })
    }

    fn texts(&mut self, text: &str, severity: MavSeverity, out: &mut Vec<MavMessage>) {
        self.text_id = self.text_id.wrapping_add(1).max(1);
        out.extend(statustext(text, severity, self.text_id));
    }

    /// A mission item the dialect cannot parse (typically a command id it does not know): read where it
    /// goes and which command it carries from the raw payload (MISSION_ITEM and MISSION_ITEM_INT share
    /// the offsets: seq at 28, command at 30, target system and component at 32 and 33), answer
    /// MISSION_ACK UNSUPPORTED at once with the reason, and end that sender's upload so the intake is free.
    pub fn unparsable_item(
        &mut self,
        header: MavHeader,
        message_id: u32,
        payload: &[u8],
        our_system: u8,
        out: &mut Vec<MavMessage>,
    ) {
        const MISSION_ITEM: u32 = 39;
        const MISSION_ITEM_INT: u32 = 73;
        if message_id != MISSION_ITEM && message_id != MISSION_ITEM_INT {
            return;
        }
        // MAVLink 2 trims trailing zero bytes: read past the end as zeros.
        let byte = |i: usize| payload.get(i).copied().unwrap_or(0);
        let seq = u16::from_le_bytes([byte(28), byte(29)]);
        let command = u16::from_le_bytes([byte(30), byte(31)]);
        let (ts, tc) = (byte(32), byte(33));
        if !((ts == our_system || ts == 0) && tc == COMPANION_COMPONENT) {
            return;
        }
        let peer = (header.system_id as u8, header.component_id);
        if self.refused_sender(peer, out) {
            return;
        }
        if self.upload.as_ref().is_some_and(|u| u.peer == peer) {
            self.upload = None;
        }
        out.push(Self::ack(peer, MavMissionResult::MAV_MISSION_UNSUPPORTED));
        self.texts(
            &format!("goal item {seq}: command {command} is not a MAVLink command this companion knows; upload refused"),
            MavSeverity::MAV_SEVERITY_WARNING,
            out,
        );
    }

    /// Feeds a message; returns a completed upload to decide on.
    pub fn handle(
        &mut self,
        header: MavHeader,
        msg: &MavMessage,
        our_system: u8,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> Option<PendingDecision> {
        let peer = (header.system_id as u8, header.component_id);
        let for_us = |ts: u8, tc: u8| (ts == our_system || ts == 0) && tc == COMPANION_COMPONENT;
        match msg {
            MavMessage::MISSION_COUNT(c) if for_us(c.target_system, c.target_component) => {
                if self.refused_sender(peer, out) {
                    return None;
                }
                if c.mission_type != MavMissionType::MAV_MISSION_TYPE_MISSION {
                    out.push(Self::ack(peer, MavMissionResult::MAV_MISSION_UNSUPPORTED));
                    return None;
                }
                if let Some(u) = &self.upload {
                    if u.peer != peer {
                        out.push(Self::ack(peer, MavMissionResult::MAV_MISSION_DENIED));
                        return None;
                    }
                }
                if c.count == 0 {
                    self.upload = None;
                    self.accepted.clear();
                    out.push(Self::ack(peer, MavMissionResult::MAV_MISSION_ACCEPTED));
                    return None;
                }
                self.upload = Some(Upload {
                    peer,
                    items: Vec::with_capacity(usize::from(c.count)),
                    count: c.count,
                    last_ms: now,
                    retries_left: self.retries,
                });
                out.push(Self::request(peer, 0));
                None
            }
            MavMessage::MISSION_ITEM_INT(it) if for_us(it.target_system, it.target_component) => {
                self.item(peer, it.seq, MissionItem::from_int(it), now, out)
            }
            MavMessage::MISSION_ITEM(it) if for_us(it.target_system, it.target_component) => {
                self.item(peer, it.seq, MissionItem::from_float(it), now, out)
            }
            MavMessage::MISSION_REQUEST_LIST(r) if for_us(r.target_system, r.target_component) => {
                self.downloader = Some(peer);
                out.push(MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
                    count: self.accepted.len() as u16,
                    target_system: peer.0,
                    target_component: peer.1,
                    mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
                    opaque_id: 0,
                }));
                None
            }
            MavMessage::MISSION_REQUEST_INT(r)
                if for_us(r.target_system, r.target_component) && self.downloader == Some(peer) =>
            {
                self.send_stored(peer, r.seq, out);
                None
            }
            MavMessage::MISSION_REQUEST(r)
                if for_us(r.target_system, r.target_component) && self.downloader == Some(peer) =>
            {
                self.send_stored(peer, r.seq, out);
                None
            }
            MavMessage::MISSION_ACK(a)
                if for_us(a.target_system, a.target_component) && self.downloader == Some(peer) =>
            {
                self.downloader = None;
                None
            }
            MavMessage::MISSION_CLEAR_ALL(r) if for_us(r.target_system, r.target_component) => {
                if self.refused_sender(peer, out) {
                    return None;
                }
                self.accepted.clear();
                out.push(Self::ack(peer, MavMissionResult::MAV_MISSION_ACCEPTED));
                None
            }
            _ => None,
        }
    }

    fn send_stored(&self, peer: (u8, u8), seq: u16, out: &mut Vec<MavMessage>) {
        match self
            .accepted
            .get(usize::from(seq))
            .and_then(|i| i.to_int(seq, peer, MavMissionType::MAV_MISSION_TYPE_MISSION))
        {
            Some(item) => out.push(MavMessage::MISSION_ITEM_INT(item)),
            None => out.push(Self::ack(
                peer,
                MavMissionResult::MAV_MISSION_INVALID_SEQUENCE,
            )),
        }
    }

    fn item(
        &mut self,
        peer: (u8, u8),
        seq: u16,
        item: MissionItem,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> Option<PendingDecision> {
        let u = self.upload.as_mut().filter(|u| u.peer == peer)?;
        if usize::from(seq) != u.items.len() {
            // Out of order: ask again for the one we need (a request sent: the timeout starts again).
            u.last_ms = now;
            out.push(Self::request(peer, u.items.len() as u16));
            return None;
        }
        u.items.push(item);
        u.last_ms = now;
        u.retries_left = self.retries;
        if u.items.len() < usize::from(u.count) {
            out.push(Self::request(peer, u.items.len() as u16));
            return None;
        }
        let u = self.upload.take()?;
        match items_to_goals(&u.items, &self.known, self.next_goal_number) {
            Ok(goals) => Some(PendingDecision {
                peer,
                goals,
                items: u.items,
            }),
            Err(e) => {
                tracing::warn!("goal upload refused: {e}");
                out.push(Self::ack(peer, e.ack));
                self.texts(
                    &format!("goals refused: {e}"),
                    MavSeverity::MAV_SEVERITY_ERROR,
                    out,
                );
                None
            }
        }
    }

    /// Sends MISSION_ACK and one STATUSTEXT per goal for the decider's verdicts.
    pub fn decided(
        &mut self,
        pending: PendingDecision,
        verdicts: &[GoalVerdict],
        out: &mut Vec<MavMessage>,
    ) {
        self.next_goal_number += pending.goals.len() as u32;
        out.push(Self::ack(
            pending.peer,
            MavMissionResult::MAV_MISSION_ACCEPTED,
        ));
        for (g, v) in pending
            .goals
            .iter()
            .zip(
                verdicts
                    .iter()
                    .chain(std::iter::repeat(&GoalVerdict::Rejected(
                        "no decision".into(),
                    ))),
            )
        {
            self.verdict(g, v, out);
        }
        self.accepted = pending.items;
    }

    /// The STATUSTEXT of one goal's verdict: in the answer, or later for a goal that was still being
    /// inserted into the plan when the upload was answered.
    pub fn verdict(
        &mut self,
        goal: &GoalRequest,
        verdict: &GoalVerdict,
        out: &mut Vec<MavMessage>,
    ) {
        let severity = match verdict {
            GoalVerdict::Accepted | GoalVerdict::Inserting => MavSeverity::MAV_SEVERITY_INFO,
            GoalVerdict::Rejected(_) => MavSeverity::MAV_SEVERITY_WARNING,
        };
        self.texts(&verdict_text(goal, verdict), severity, out);
    }

    /// Re-requests on timeout; cancels the upload after the retries.
    pub fn tick(&mut self, now: u64, out: &mut Vec<MavMessage>) {
        let Some(u) = self.upload.as_mut() else {
            return;
        };
        if now.saturating_sub(u.last_ms) < self.timeout_ms {
            return;
        }
        if u.retries_left == 0 {
            out.push(Self::ack(
                u.peer,
                MavMissionResult::MAV_MISSION_OPERATION_CANCELLED,
            ));
            self.upload = None;
            self.texts(
                "goal upload timeout",
                MavSeverity::MAV_SEVERITY_WARNING,
                out,
            );
            return;
        }
        u.retries_left -= 1;
        u.last_ms = now;
        out.push(Self::request(u.peer, u.items.len() as u16));
    }
}
