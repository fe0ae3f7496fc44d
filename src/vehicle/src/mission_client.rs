//! Mission protocol client (upload with re-requests and timeouts, download, clear). Answers both
//! MISSION_REQUEST_INT and the legacy MISSION_REQUEST (ArduPilot sends the latter) with MISSION_ITEM_INT.
//! Setting the current item goes through the command client (`MAV_CMD_DO_SET_MISSION_CURRENT`).

// The legacy MISSION_ITEM / MISSION_REQUEST must still be accepted (ArduPilot sends MISSION_REQUEST).
#![allow(deprecated)]

use mavlink::dialects::ardupilotmega::{
    MavMessage, MavMissionResult, MavMissionType, MISSION_ACK_DATA, MISSION_CLEAR_ALL_DATA,
    MISSION_COUNT_DATA, MISSION_REQUEST_INT_DATA, MISSION_REQUEST_LIST_DATA,
};

use super::commands::Token;
use super::items::MissionItem;

#[derive(Debug, Clone, PartialEq)]
pub enum MissionOutcome {
    Uploaded,
    Downloaded(Vec<MissionItem>),
    Cleared,
    Failed(String),
}

#[derive(Debug)]
enum Op {
    Upload {
        items: Vec<MissionItem>,
    },
    Download {
        count: Option<u16>,
        items: Vec<MissionItem>,
        /// The mission or the fence list.
        mission_type: MavMissionType,
    },
    Clear,
}

#[derive(Debug)]
struct Running {
    token: Token,
    op: Op,
    last_sent: MavMessage,
    last_ms: u64,
    /// The vehicle's clock when last sent: the timeout runs on either clock, as for commands.
    last_vms: u64,
    retries_left: u32,
}

#[derive(Debug)]
pub struct MissionClient {
    pub target: (u8, u8),
    pub timeout_ms: u64,
    pub retries: u32,
    running: Option<Running>,
    /// The vehicle's clock (ms since its boot, kept running across restarts), as telemetry last gave it.
    vnow: u64,
}

impl MissionClient {
    pub fn new(target: (u8, u8), timeout_ms: u64, retries: u32) -> Self {
        Self {
            target,
            timeout_ms,
            retries,
            running: None,
            vnow: 0,
        }
    }

    /// The vehicle's clock advanced.
    pub fn set_vehicle_time(&mut self, vnow: u64) {
        self.vnow = self.vnow.max(vnow);
    }

    pub fn busy(&self) -> bool {
        self.running.is_some()
    }

    fn begin(
        &mut self,
        token: Token,
        op: Op,
        first: MavMessage,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> bool {
        if self.running.is_some() {
            return false;
        }
        out.push(first.clone());
        self.running = Some(Running {
            token,
            op,
            last_sent: first,
            last_ms: now,
            last_vms: self.vnow,
            retries_left: self.retries,
        });
        true
    }

    /// Starts an upload; false when another transfer is running or the list is longer than 65,535 items.
    pub fn upload(
        &mut self,
        token: Token,
        items: Vec<MissionItem>,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> bool {
        // MISSION_COUNT's count is 16 bits: a longer list cannot be sent (a wrapped count would upload a
        // prefix and be acknowledged).
        let Ok(n) = u16::try_from(items.len()) else {
            tracing::warn!(
                items = items.len(),
                "mission upload refused: more items than MAVLink can count"
            );
            return false;
        };
        let count = MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
            count: n,
            target_system: self.target.0,
            target_component: self.target.1,
            mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
            opaque_id: 0,
        });
        self.begin(token, Op::Upload { items }, count, now, out)
    }

    pub fn download(&mut self, token: Token, now: u64, out: &mut Vec<MavMessage>) -> bool {
        self.download_of(MavMissionType::MAV_MISSION_TYPE_MISSION, token, now, out)
    }

    /// Downloads the list of `mission_type` (the mission, the fence).
    pub fn download_of(
        &mut self,
        mission_type: MavMissionType,
        token: Token,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> bool {
        let list = MavMessage::MISSION_REQUEST_LIST(MISSION_REQUEST_LIST_DATA {
            target_system: self.target.0,
            target_component: self.target.1,
            mission_type,
        });
        self.begin(
            token,
            Op::Download {
                count: None,
                items: Vec::new(),
                mission_type,
            },
            list,
            now,
            out,
        )
    }

    pub fn clear(&mut self, token: Token, now: u64, out: &mut Vec<MavMessage>) -> bool {
        let clear = MavMessage::MISSION_CLEAR_ALL(MISSION_CLEAR_ALL_DATA {
            target_system: self.target.0,
            target_component: self.target.1,
            mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
        });
        self.begin(token, Op::Clear, clear, now, out)
    }

    fn send(&mut self, msg: MavMessage, now: u64, out: &mut Vec<MavMessage>) {
        if let Some(r) = &mut self.running {
            out.push(msg.clone());
            r.last_sent = msg;
            r.last_ms = now;
            r.last_vms = self.vnow;
            r.retries_left = self.retries;
        }
    }

    fn finish(&mut self, outcome: MissionOutcome) -> Option<(Token, MissionOutcome)> {
        self.running.take().map(|r| (r.token, outcome))
    }

    fn request(&self, seq: u16, mission_type: MavMissionType) -> MavMessage {
        MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
            seq,
            target_system: self.target.0,
            target_component: self.target.1,
            mission_type,
        })
    }

    /// Feeds a message from the target component.
    pub fn handle(
        &mut self,
        msg: &MavMessage,
        now: u64,
        out: &mut Vec<MavMessage>,
    ) -> Option<(Token, MissionOutcome)> {
        let running = self.running.as_mut()?;
        let op = &mut running.op;
        match (op, msg) {
            (
                Op::Upload { items },
                MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
                    seq, mission_type, ..
                }),
            )
            | (
                Op::Upload { items },
                MavMessage::MISSION_REQUEST(
                    mavlink::dialects::ardupilotmega::MISSION_REQUEST_DATA {
                        seq,
                        mission_type,
                        ..
                    },
                ),
            ) if *mission_type == MavMissionType::MAV_MISSION_TYPE_MISSION => {
                let (seq, n) = (*seq, items.len());
                let wire = items.get(usize::from(seq)).map(|item| {
                    (
                        item.to_int(seq, self.target, MavMissionType::MAV_MISSION_TYPE_MISSION),
                        item.command,
                        item.frame,
                    )
                });
                match wire {
                    None => self.finish(MissionOutcome::Failed(format!(
                        "vehicle requested item {seq} of {n}"
                    ))),
                    Some((Some(w), _, _)) => {
                        self.send(MavMessage::MISSION_ITEM_INT(w), now, out);
                        None
                    }
                    Some((None, command, frame)) => self.finish(MissionOutcome::Failed(format!(
                        "item {seq}: command {command} or frame {frame} unknown to the dialect"
                    ))),
                }
            }
            (Op::Upload { .. }, MavMessage::MISSION_ACK(a))
                if a.mission_type == MavMissionType::MAV_MISSION_TYPE_MISSION =>
            {
                if a.mavtype == MavMissionResult::MAV_MISSION_ACCEPTED {
                    self.finish(MissionOutcome::Uploaded)
                } else if a.mavtype == MavMissionResult::MAV_MISSION_INVALID_SEQUENCE {
                    // ArduPilot keeps the upload open after a wrong sequence: wait for its next request.
                    None
                } else {
                    self.finish(MissionOutcome::Failed(format!(
                        "upload refused: {:?}",
                        a.mavtype
                    )))
                }
            }
            (
                Op::Download {
                    count,
                    items,
                    mission_type,
                },
                MavMessage::MISSION_COUNT(c),
            ) if count.is_none() && c.mission_type == *mission_type => {
                *count = Some(c.count);
                items.clear();
                let mt = *mission_type;
                if c.count == 0 {
                    return self.finish_download(now, out);
                }
                let req = self.request(0, mt);
                self.send(req, now, out);
                None
            }
            (
                Op::Download {
                    count: Some(n),
                    items,
                    mission_type,
                },
                MavMessage::MISSION_ITEM_INT(_) | MavMessage::MISSION_ITEM(_),
            ) => {
                let mt = *mission_type;
                let item = match msg {
                    MavMessage::MISSION_ITEM_INT(it) => (it.seq, MissionItem::from_int(it)),
                    MavMessage::MISSION_ITEM(it) => (it.seq, MissionItem::from_float(it)),
                    _ => return None,
                };
                if usize::from(item.0) == items.len() {
                    items.push(item.1);
                }
                let (got, n) = (items.len(), *n);
                if got == usize::from(n) {
                    self.finish_download(now, out)
                } else {
                    let req = self.request(got as u16, mt);
                    self.send(req, now, out);
                    None
                }
            }
            // A list the autopilot does not keep (a fence on a firmware without one).
            (Op::Download { mission_type, .. }, MavMessage::MISSION_ACK(a))
                if a.mission_type == *mission_type
                    && a.mavtype != MavMissionResult::MAV_MISSION_ACCEPTED =>
            {
                self.finish(MissionOutcome::Failed(format!(
                    "download refused: {}",
                    format!("{:?}", a.mavtype).trim_start_matches("MAV_MISSION_")
                )))
            }
            (Op::Clear, MavMessage::MISSION_ACK(a)) => {
                if a.mavtype == MavMissionResult::MAV_MISSION_ACCEPTED {
                    self.finish(MissionOutcome::Cleared)
                } else {
                    self.finish(MissionOutcome::Failed(format!(
                        "clear refused: {:?}",
                        a.mavtype
                    )))
                }
            }
            _ => None,
        }
    }

    fn finish_download(
        &mut self,
        _now: u64,
        out: &mut Vec<MavMessage>,
    ) -> Option<(Token, MissionOutcome)> {
        let mission_type = match &self.running.as_ref()?.op {
            Op::Download { mission_type, .. } => *mission_type,
            _ => MavMissionType::MAV_MISSION_TYPE_MISSION,
        };
        out.push(MavMessage::MISSION_ACK(MISSION_ACK_DATA {
            target_system: self.target.0,
            target_component: self.target.1,
            mavtype: MavMissionResult::MAV_MISSION_ACCEPTED,
            mission_type,
            opaque_id: 0,
        }));
        let r = self.running.take()?;
        match r.op {
            Op::Download { items, .. } => Some((r.token, MissionOutcome::Downloaded(items))),
            _ => None,
        }
    }

    /// Re-sends the last message on timeout; fails the transfer after the retries.
    pub fn tick(&mut self, now: u64, out: &mut Vec<MavMessage>) -> Option<(Token, MissionOutcome)> {
        let r = self.running.as_mut()?;
        let waited = now
            .saturating_sub(r.last_ms)
            .max(self.vnow.saturating_sub(r.last_vms));
        if waited < self.timeout_ms {
            return None;
        }
        if r.retries_left == 0 {
            let what = match r.op {
                Op::Upload { .. } => "upload",
                Op::Download { .. } => "download",
                Op::Clear => "clear",
            };
            return self.finish(MissionOutcome::Failed(format!(
                "mission {what} timed out after {} retries",
                self.retries
            )));
        }
        r.retries_left -= 1;
        r.last_ms = now;
        r.last_vms = self.vnow;
        out.push(r.last_sent.clone());
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unanswered_upload_is_re_sent_on_the_vehicle_clock_then_fails() {
        let mut c = MissionClient::new((1, 1), 3_000, 1);
        let mut out = Vec::new();
        c.set_vehicle_time(1_000);
        assert!(c.upload(9, vec![MissionItem::waypoint(43.0, 1.0, 0.0)], 0, &mut out));
        c.set_vehicle_time(3_999);
        assert_eq!(c.tick(10, &mut out), None);
        assert_eq!(out.len(), 1);
        // 3 s of vehicle time in 20 ms of wall time (a simulator at 150x): MISSION_COUNT again.
        c.set_vehicle_time(4_000);
        assert_eq!(c.tick(20, &mut out), None);
        assert!(matches!(
            out.as_slice(),
            [MavMessage::MISSION_COUNT(_), MavMessage::MISSION_COUNT(_)]
        ));
        c.set_vehicle_time(7_000);
        assert!(matches!(
            c.tick(30, &mut out),
            Some((9, MissionOutcome::Failed(r))) if r.contains("upload timed out")
        ));
    }
}
