//! Goal intake: the companion's side of the mission protocol for items addressed to component 191. An upload
//! becomes goal requests ([`super::item_goals::items_to_goals`]: items that are no goal are skipped, each
//! with a warning) and replaces the list the same station uploaded before ([`super::held`]: goals left out
//! are cancelled); once the executive has answered, MISSION_ACK and the STATUSTEXTs go back (one per goal,
//! or counts by reason for a large list); a goal still being inserted into the plan gets its final
//! STATUSTEXT later ([`GoalIntake::verdict`]), and so does its end (achieved, rejected, cancelled).
//! MISSION_REQUEST_LIST reads back the goals the station still holds; MISSION_CLEAR_ALL cancels them.
//!
//! Nobody can jam it: each station has its own upload (at most [`MAX_UPLOADS`] at once), a declared count
//! over [`MAX_GOAL_ITEMS`] is refused at once, an upload that stops progressing is cancelled after its
//! retries, and a second station speaking with the same ids from another address is refused rather than
//! mixed in. Every refusal comes with a STATUSTEXT saying why. When the configuration names the ground
//! stations allowed to send goals (`link.goal_sysids`), uploads and clears from any other system are
//! answered MISSION_ACK DENIED with the reason.

// The legacy MISSION_ITEM / MISSION_REQUEST must still be accepted (ArduPilot sends MISSION_REQUEST).
#![allow(deprecated)]

use mavlink::dialects::ardupilotmega::{
    MavMessage, MavMissionResult, MavMissionType, MavSeverity, MISSION_ACK_DATA,
    MISSION_COUNT_DATA, MISSION_REQUEST_INT_DATA, STATUSTEXT_DATA,
};
use mavlink::MavHeader;
use std::collections::BTreeMap;
use std::net::SocketAddr;

use super::driver::COMPANION_COMPONENT;
use super::goals::{verdict_text, KnownLocations};
use super::held::{HeldGoal, HeldGoals, Station};
use super::item_goals::{items_to_goals, rename, ItemError};
use super::items::MissionItem;
use super::types::{GoalRequest, GoalVerdict};

/// The most items one upload may declare (MISSION_COUNT); more is refused at once.
pub const MAX_GOAL_ITEMS: u16 = 256;
/// Uploads in progress at once (one per station).
pub const MAX_UPLOADS: usize = 8;
/// Past this many lines, an answer's texts are counts by reason.
pub const SUMMARY_OVER: usize = 20;

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
    /// The address it comes from (UDP), so a station sharing its ids is not mixed in.
    origin: Option<SocketAddr>,
    items: Vec<MissionItem>,
    count: u16,
    last_ms: u64,
    retries_left: u32,
}

/// A completed upload (or a clear) waiting for the executive: goals to request and goals to cancel.
#[derive(Debug, Clone)]
pub struct PendingDecision {
    pub peer: Station,
    /// The goals new in the list, to decide on.
    pub goals: Vec<GoalRequest>,
    /// The goals the station held and left out (or cleared), to cancel, and why in its words.
    pub cancel: Vec<String>,
    pub cancel_reason: String,
    new: Vec<HeldGoal>,
    kept: Vec<HeldGoal>,
    skipped: Vec<ItemError>,
}

pub struct GoalIntake {
    pub known: KnownLocations,
    next_goal_number: u32,
    uploads: BTreeMap<Station, Upload>,
    held: HeldGoals,
    /// The ground station downloading its goal list, and the list as it was when asked.
    download: Option<(Station, Vec<MissionItem>)>,
    pub timeout_ms: u64,
    pub retries: u32,
    text_id: u16,
    /// The system ids goals are taken from; `None`: any.
    allowed_systems: Option<Vec<u8>>,
}

/// Whether item 0 is a home position as ArduPilot ground stations send it (pymavlink's mavwp, MAVProxy's
/// `wp load`, Mission Planner): a waypoint in the absolute global frame.
fn home_first(items: &[MissionItem]) -> bool {
    items.first().is_some_and(|i| {
        i.command == mavlink::dialects::ardupilotmega::MavCmd::MAV_CMD_NAV_WAYPOINT as u16
            && i.frame == 0
            && items.len() > 1
    })
}

/// Lines counted by what they say: `n × text` per distinct text, in first-seen order.
fn counted<'a>(lines: impl Iterator<Item = &'a str>) -> Vec<(usize, &'a str)> {
    let mut out: Vec<(usize, &str)> = Vec::new();
    for l in lines {
        match out.iter_mut().find(|(_, t)| *t == l) {
            Some((n, _)) => *n += 1,
            None => out.push((1, l)),
        }
    }
    out
}

impl GoalIntake {
    /// The goals each station holds.
    pub fn held(&self) -> &HeldGoals {
        &self.held
    }

    pub fn new(known: KnownLocations, first_goal_number: u32) -> Self {
        Self {
            known,
            next_goal_number: first_goal_number,
            uploads: BTreeMap::new(),
            held: HeldGoals::default(),
            download: None,
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
    fn refused_sender(&mut self, peer: Station, out: &mut Vec<MavMessage>) -> bool {
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
        self.refuse(peer, MavMissionResult::MAV_MISSION_DENIED, &text, out);
        true
    }

    /// MISSION_ACK `result` and a STATUSTEXT saying why.
    fn refuse(
        &mut self,
        peer: Station,
        result: MavMissionResult,
        text: &str,
        out: &mut Vec<MavMessage>,
    ) {
        tracing::warn!("{text}");
        out.push(Self::ack(peer, result));
        self.texts(text, MavSeverity::MAV_SEVERITY_WARNING, out);
    }

    fn ack(peer: Station, result: MavMissionResult) -> MavMessage {
        MavMessage::MISSION_ACK(MISSION_ACK_DATA {
            target_system: peer.0,
            target_component: peer.1,
            mavtype: result,
            mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
            opaque_id: 0,
        })
    }

    fn request(peer: Station, seq: u16) -> MavMessage {
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
    /// the offsets: seq at 28, command at 30, target system and component at 32 and 33). In the upload in
    /// progress it is kept as an item no goal is made of (skipped with a warning when the list is
    /// complete); otherwise it is ignored.
    pub fn unparsable_item(
        &mut self,
        header: MavHeader,
        message_id: u32,
        payload: &[u8],
        our_system: u8,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> Option<PendingDecision> {
        const MISSION_ITEM: u32 = 39;
        const MISSION_ITEM_INT: u32 = 73;
        if message_id != MISSION_ITEM && message_id != MISSION_ITEM_INT {
            return None;
        }
        // MAVLink 2 trims trailing zero bytes: read past the end as zeros.
        let byte = |i: usize| payload.get(i).copied().unwrap_or(0);
        let seq = u16::from_le_bytes([byte(28), byte(29)]);
        let command = u16::from_le_bytes([byte(30), byte(31)]);
        let (ts, tc) = (byte(32), byte(33));
        if !((ts == our_system || ts == 0) && tc == COMPANION_COMPONENT) {
            return None;
        }
        let peer = (header.system_id as u8, header.component_id);
        let mut item = MissionItem::new(
            mavlink::dialects::ardupilotmega::MavCmd::MAV_CMD_NAV_WAYPOINT,
            mavlink::dialects::ardupilotmega::MavFrame::MAV_FRAME_MISSION,
        );
        item.command = command;
        self.item(peer, None, seq, item, now, out)
    }

    /// Feeds a message from `origin` (the UDP address it came from, if any); returns a completed upload or
    /// a clear to decide on.
    pub fn handle(
        &mut self,
        header: MavHeader,
        msg: &MavMessage,
        origin: Option<SocketAddr>,
        our_system: u8,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> Option<PendingDecision> {
        let peer = (header.system_id as u8, header.component_id);
        let for_us = |ts: u8, tc: u8| (ts == our_system || ts == 0) && tc == COMPANION_COMPONENT;
        match msg {
            MavMessage::MISSION_COUNT(c) if for_us(c.target_system, c.target_component) => {
                self.count(peer, origin, c.count, c.mission_type, now, out)
            }
            MavMessage::MISSION_ITEM_INT(it) if for_us(it.target_system, it.target_component) => {
                self.item(peer, origin, it.seq, MissionItem::from_int(it), now, out)
            }
            MavMessage::MISSION_ITEM(it) if for_us(it.target_system, it.target_component) => {
                self.item(peer, origin, it.seq, MissionItem::from_float(it), now, out)
            }
            MavMessage::MISSION_REQUEST_LIST(r) if for_us(r.target_system, r.target_component) => {
                let items = self.held.items(peer);
                out.push(MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
                    count: items.len() as u16,
                    target_system: peer.0,
                    target_component: peer.1,
                    mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
                    opaque_id: 0,
                }));
                self.download = Some((peer, items));
                None
            }
            MavMessage::MISSION_REQUEST_INT(r) if for_us(r.target_system, r.target_component) => {
                self.send_stored(peer, r.seq, out);
                None
            }
            MavMessage::MISSION_REQUEST(r) if for_us(r.target_system, r.target_component) => {
                self.send_stored(peer, r.seq, out);
                None
            }
            MavMessage::MISSION_ACK(a)
                if for_us(a.target_system, a.target_component)
                    && self.download.as_ref().is_some_and(|(p, _)| *p == peer) =>
            {
                self.download = None;
                None
            }
            MavMessage::MISSION_CLEAR_ALL(r) if for_us(r.target_system, r.target_component) => {
                if self.refused_sender(peer, out) {
                    return None;
                }
                self.uploads.remove(&peer);
                self.withdraw_all(
                    peer,
                    "cleared by the ground station (MISSION_CLEAR_ALL)",
                    out,
                )
            }
            _ => None,
        }
    }

    /// Every goal `peer` holds is to be cancelled; answered at once when it holds none.
    fn withdraw_all(
        &mut self,
        peer: Station,
        reason: &str,
        out: &mut Vec<MavMessage>,
    ) -> Option<PendingDecision> {
        let names = self.held.names(peer);
        if names.is_empty() {
            out.push(Self::ack(peer, MavMissionResult::MAV_MISSION_ACCEPTED));
            return None;
        }
        Some(PendingDecision {
            peer,
            goals: Vec::new(),
            cancel: names,
            cancel_reason: reason.to_string(),
            new: Vec::new(),
            kept: Vec::new(),
            skipped: Vec::new(),
        })
    }

    fn count(
        &mut self,
        peer: Station,
        origin: Option<SocketAddr>,
        count: u16,
        mission_type: MavMissionType,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> Option<PendingDecision> {
        if self.refused_sender(peer, out) {
            return None;
        }
        if mission_type != MavMissionType::MAV_MISSION_TYPE_MISSION {
            let text =
                "goal upload refused: only mission lists carry goals (not fences or rally points)";
            self.refuse(peer, MavMissionResult::MAV_MISSION_UNSUPPORTED, text, out);
            return None;
        }
        if count > MAX_GOAL_ITEMS {
            let text =
                format!("goal upload refused: {count} items declared, at most {MAX_GOAL_ITEMS}");
            self.refuse(peer, MavMissionResult::MAV_MISSION_NO_SPACE, &text, out);
            return None;
        }
        match self.uploads.get(&peer) {
            Some(u) if u.origin != origin => {
                let text = format!(
                    "goal upload refused: system {} component {} is already uploading from another address (two stations share these ids)",
                    peer.0, peer.1
                );
                self.refuse(peer, MavMissionResult::MAV_MISSION_DENIED, &text, out);
                return None;
            }
            None if self.uploads.len() >= MAX_UPLOADS => {
                let text = format!(
                    "goal upload refused: {MAX_UPLOADS} other stations are uploading; try again"
                );
                self.refuse(peer, MavMissionResult::MAV_MISSION_DENIED, &text, out);
                return None;
            }
            _ => {}
        }
        if count == 0 {
            self.uploads.remove(&peer);
            return self.withdraw_all(peer, "an empty goal list was uploaded", out);
        }
        // A new MISSION_COUNT from the same station starts its upload again (a retry).
        self.uploads.insert(
            peer,
            Upload {
                origin,
                items: Vec::with_capacity(usize::from(count)),
                count,
                last_ms: now,
                retries_left: self.retries,
            },
        );
        out.push(Self::request(peer, 0));
        None
    }

    fn send_stored(&self, peer: Station, seq: u16, out: &mut Vec<MavMessage>) {
        let Some((_, items)) = self.download.as_ref().filter(|(p, _)| *p == peer) else {
            return;
        };
        match items
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
        peer: Station,
        origin: Option<SocketAddr>,
        seq: u16,
        item: MissionItem,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> Option<PendingDecision> {
        let retries = self.retries;
        // Another address speaking with the same ids is not mixed into this upload.
        let u = self
            .uploads
            .get_mut(&peer)
            .filter(|u| origin.is_none() || u.origin == origin)?;
        if usize::from(seq) != u.items.len() {
            // Out of order: ask again for the one we need (a request sent: the timeout starts again).
            u.last_ms = now;
            out.push(Self::request(peer, u.items.len() as u16));
            return None;
        }
        u.items.push(item);
        u.last_ms = now;
        u.retries_left = retries;
        if u.items.len() < usize::from(u.count) {
            out.push(Self::request(peer, u.items.len() as u16));
            return None;
        }
        let u = self.uploads.remove(&peer)?;
        Some(self.list(peer, &u.items))
    }

    /// A complete list from `peer`: its goals against those it holds.
    fn list(&mut self, peer: Station, items: &[MissionItem]) -> PendingDecision {
        let offset = usize::from(home_first(items));
        let mut list = items_to_goals(&items[offset..], &self.known, self.next_goal_number);
        for g in &mut list.goals {
            g.items = g.items.start + offset..g.items.end + offset;
        }
        for e in &mut list.skipped {
            e.seq += offset;
        }
        if offset == 1 {
            list.skipped.insert(
                0,
                ItemError {
                    seq: 0,
                    reason: "the home position, not a goal".into(),
                    ack: MavMissionResult::MAV_MISSION_ACCEPTED,
                },
            );
        }
        let mut r = self.held.replace(peer, items, &list);
        for (k, g) in r.new.iter_mut().enumerate() {
            rename(
                &mut g.request,
                format!("g{}", self.next_goal_number as usize + k),
            );
        }
        PendingDecision {
            peer,
            goals: r.new.iter().map(|g| g.request.clone()).collect(),
            cancel: r.dropped,
            cancel_reason: format!("left out of the goal list system {} uploaded again", peer.0),
            new: r.new,
            kept: r.kept,
            skipped: list.skipped,
        }
    }

    /// Answers a decided upload or clear: MISSION_ACK, then the STATUSTEXTs (skipped items, cancelled
    /// goals, each new goal's verdict; counts by reason past [`SUMMARY_OVER`] lines). `cancelled`: the
    /// names the executive withdrew, `None` when it did not confirm (then MISSION_ACK ERROR: the goals may
    /// still be held).
    pub fn decided(
        &mut self,
        pending: PendingDecision,
        verdicts: &[GoalVerdict],
        cancelled: Option<Vec<String>>,
        out: &mut Vec<MavMessage>,
    ) {
        self.next_goal_number += pending.goals.len() as u32;
        let peer = pending.peer;
        let confirmed = pending.cancel.is_empty() || cancelled.is_some();
        out.push(Self::ack(
            peer,
            if confirmed {
                MavMissionResult::MAV_MISSION_ACCEPTED
            } else {
                MavMissionResult::MAV_MISSION_ERROR
            },
        ));
        let skipped: Vec<String> = pending.skipped.iter().map(|e| e.to_string()).collect();
        if skipped.len() > SUMMARY_OVER {
            let reasons: Vec<&str> = pending.skipped.iter().map(|e| e.reason.as_str()).collect();
            let text = format!(
                "{} items skipped: {}",
                skipped.len(),
                Self::tally(reasons.into_iter())
            );
            self.texts(&text, MavSeverity::MAV_SEVERITY_WARNING, out);
        } else {
            for t in &skipped {
                self.texts(t, MavSeverity::MAV_SEVERITY_WARNING, out);
            }
        }
        if !pending.cancel.is_empty() {
            let text = match &cancelled {
                Some(_) => format!(
                    "{} cancelled: {}",
                    pending.cancel.join(", "),
                    pending.cancel_reason
                ),
                None => format!(
                    "the executive did not confirm cancelling {}: they may still be held",
                    pending.cancel.join(", ")
                ),
            };
            let text = if text.len() > 150 {
                format!("{} goals {}", pending.cancel.len(), {
                    if cancelled.is_some() {
                        format!("cancelled: {}", pending.cancel_reason)
                    } else {
                        "not confirmed cancelled: they may still be held".to_string()
                    }
                })
            } else {
                text
            };
            self.texts(&text, MavSeverity::MAV_SEVERITY_INFO, out);
            if cancelled.is_some() {
                for n in &pending.cancel {
                    self.held.release(n);
                }
            }
        }
        let verdicts: Vec<GoalVerdict> = pending
            .goals
            .iter()
            .zip(
                verdicts
                    .iter()
                    .cloned()
                    .chain(std::iter::repeat(GoalVerdict::Inserting)),
            )
            .map(|(_, v)| v)
            .collect();
        if pending.goals.len() > SUMMARY_OVER {
            let lines: Vec<String> = verdicts
                .iter()
                .map(|v| match v {
                    GoalVerdict::Rejected(r) => format!("rejected: {r}"),
                    GoalVerdict::Accepted => "accepted".into(),
                    GoalVerdict::Inserting => "received, verdict to follow".into(),
                    GoalVerdict::Achieved => "achieved".into(),
                    GoalVerdict::Cancelled(r) => format!("cancelled: {r}"),
                })
                .collect();
            let text = format!(
                "{} goals ({}-{}): {}",
                pending.goals.len(),
                pending.goals.first().map_or("", |g| g.name.as_str()),
                pending.goals.last().map_or("", |g| g.name.as_str()),
                Self::tally(lines.iter().map(String::as_str))
            );
            self.texts(&text, MavSeverity::MAV_SEVERITY_INFO, out);
        } else {
            for (g, v) in pending.goals.iter().zip(&verdicts) {
                self.verdict(g, v, out);
            }
        }
        let mut held = pending.kept;
        held.extend(
            pending
                .new
                .into_iter()
                .zip(&verdicts)
                .filter(|(_, v)| matches!(v, GoalVerdict::Accepted | GoalVerdict::Inserting))
                .map(|(g, _)| g),
        );
        // A clear or a confirmed replacement: the station holds exactly this list now.
        if confirmed {
            self.held.set(peer, held);
        }
    }

    /// `n × reason; …`, the most frequent first.
    fn tally<'a>(lines: impl Iterator<Item = &'a str>) -> String {
        let mut c = counted(lines);
        c.sort_by_key(|x| std::cmp::Reverse(x.0));
        c.iter()
            .map(|(n, t)| format!("{n} x {t}"))
            .collect::<Vec<_>>()
            .join("; ")
    }

    /// The STATUSTEXT of one goal's verdict or end: in the answer, or later (a goal still being inserted
    /// into the plan when the upload was answered; achieved, rejected by a replanning, cancelled).
    pub fn verdict(
        &mut self,
        goal: &GoalRequest,
        verdict: &GoalVerdict,
        out: &mut Vec<MavMessage>,
    ) {
        let severity = match verdict {
            GoalVerdict::Accepted | GoalVerdict::Inserting | GoalVerdict::Achieved => {
                MavSeverity::MAV_SEVERITY_INFO
            }
            GoalVerdict::Rejected(_) | GoalVerdict::Cancelled(_) => {
                MavSeverity::MAV_SEVERITY_WARNING
            }
        };
        self.texts(&verdict_text(goal, verdict), severity, out);
    }

    /// A goal's later word: a goal achieved, rejected or cancelled is no longer held.
    pub fn settle(&mut self, goal: &GoalRequest, verdict: &GoalVerdict) {
        if matches!(
            verdict,
            GoalVerdict::Rejected(_) | GoalVerdict::Achieved | GoalVerdict::Cancelled(_)
        ) {
            self.held.release(&goal.name);
        }
    }

    /// The names `station` holds (what MISSION_REQUEST_LIST reads back).
    pub fn held_names(&self, station: Station) -> Vec<String> {
        self.held.names(station)
    }

    /// Re-requests on timeout; cancels an upload after its retries (each station's on its own).
    pub fn tick(&mut self, now: u64, out: &mut Vec<MavMessage>) {
        let mut expired = Vec::new();
        for (&peer, u) in self.uploads.iter_mut() {
            if now.saturating_sub(u.last_ms) < self.timeout_ms {
                continue;
            }
            if u.retries_left == 0 {
                expired.push((peer, u.items.len(), u.count));
                continue;
            }
            u.retries_left -= 1;
            u.last_ms = now;
            out.push(Self::request(peer, u.items.len() as u16));
        }
        for (peer, got, count) in expired {
            self.uploads.remove(&peer);
            let text = format!(
                "goal upload from system {} cancelled: no item {got} of {count} after {} requests",
                peer.0,
                self.retries + 1
            );
            self.refuse(
                peer,
                MavMissionResult::MAV_MISSION_OPERATION_CANCELLED,
                &text,
                out,
            );
        }
    }
}
