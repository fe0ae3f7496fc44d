//! A small ground-station client (`mavtempo goal send`): uploads a goal list to component 191 with the mission
//! protocol and collects the MISSION_ACK outcome and the per-goal STATUSTEXTs.

use std::time::{Duration, Instant};

use mavlink::dialects::ardupilotmega::{
    MavAutopilot, MavMessage, MavModeFlag, MavState, MavType, HEARTBEAT_DATA,
};

use super::driver::COMPANION_COMPONENT;
use super::endpoint::{Address, Transport};
use super::frame::{Encoder, FrameDecoder, Signer};
use super::goals::{is_final_verdict_text, summary_finals, GOAL_ATTRIBUTES_CMD, INSERTING};
use super::items::MissionItem;
use super::mission_client::{MissionClient, MissionOutcome};

#[derive(Debug, thiserror::Error)]
pub enum GoalSendError {
    #[error("bad address: {0}")]
    Address(#[from] super::endpoint::AddressError),
    #[error("{0}")]
    Io(#[from] std::io::Error),
    #[error("no heartbeat from a companion (component 191) within {0:?}")]
    NoCompanion(Duration),
    #[error("{0} items: a MAVLink mission transfer carries at most {max} (its count is 16 bits)", max = MAX_ITEMS)]
    TooManyItems(usize),
}

/// The most items one mission transfer can carry: MISSION_COUNT's count is a `u16`.
pub const MAX_ITEMS: usize = u16::MAX as usize;

#[derive(Debug, Clone, PartialEq)]
pub struct GoalSendReport {
    /// `None` when the upload was accepted, else why not.
    pub failure: Option<String>,
    pub texts: Vec<String>,
}

/// Reassembles STATUSTEXT chunks (same non-zero id; a chunk shorter than 50 bytes ends the text).
#[derive(Default)]
pub struct TextAssembler {
    partial: Option<(u16, Vec<u8>)>,
}

impl TextAssembler {
    pub fn push(&mut self, id: u16, chunk: &[u8]) -> Option<String> {
        let len = chunk.iter().position(|&b| b == 0).unwrap_or(chunk.len());
        let part = &chunk[..len];
        if id == 0 {
            return Some(String::from_utf8_lossy(part).into_owned());
        }
        let buf = match &mut self.partial {
            Some((pid, buf)) if *pid == id => buf,
            _ => {
                self.partial = Some((id, Vec::new()));
                &mut self.partial.as_mut()?.1
            }
        };
        buf.extend_from_slice(part);
        if len < chunk.len() {
            let (_, buf) = self.partial.take()?;
            return Some(String::from_utf8_lossy(&buf).into_owned());
        }
        None
    }
}

/// Goals answered "received … verdict to follow" whose final verdict has not come yet.
fn awaiting_verdicts(texts: &[String]) -> usize {
    let name = |t: &str| t.split(' ').next().unwrap_or("").to_string();
    texts
        .iter()
        .filter(|t| t.ends_with(INSERTING))
        .filter(|t| {
            let n = name(t);
            !texts
                .iter()
                .any(|f| is_final_verdict_text(f) && name(f) == n)
        })
        .count()
}

pub fn gcs_heartbeat() -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode: 0,
        mavtype: MavType::MAV_TYPE_GCS,
        autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
        base_mode: MavModeFlag::empty(),
        system_status: MavState::MAV_STATE_ACTIVE,
        mavlink_version: 3,
    })
}

/// The system id a ground station uses (MAVLink's convention for a GCS).
pub const GCS_SYSTEM_ID: u8 = 255;

/// Adds `items` to the goals this station holds on the companion at `address` (it reads them back and uploads
/// them with `items`: an upload replaces a station's list) and waits for the ACK and each new goal's final
/// verdict (a goal the companion is still inserting into its plan when it answers gets its verdict in a
/// later STATUSTEXT).
pub async fn send_goals(
    address: &str,
    items: Vec<MissionItem>,
    timeout: Duration,
) -> Result<GoalSendReport, GoalSendError> {
    send_goals_as(GCS_SYSTEM_ID, address, items, timeout).await
}

/// [`send_goals`] as the ground station of system `system_id`.
pub async fn send_goals_as(
    system_id: u8,
    address: &str,
    items: Vec<MissionItem>,
    timeout: Duration,
) -> Result<GoalSendReport, GoalSendError> {
    send_goals_signed(system_id, None, address, items, timeout).await
}

/// [`send_goals_as`] signing every frame with `signing` (key, link id; MAVLink2 signing) when given: a
/// companion whose config has a signing key ignores unsigned stations.
pub async fn send_goals_signed(
    system_id: u8,
    signing: Option<([u8; 32], u8)>,
    address: &str,
    items: Vec<MissionItem>,
    timeout: Duration,
) -> Result<GoalSendReport, GoalSendError> {
    let station = (system_id, GCS_COMPONENT);
    transfer(station, signing, address, Transfer::Add(items), timeout).await
}

/// Uploads `items` as the whole list of ground station `station` (system, component): the goals it held
/// and left out are cancelled (the mission protocol's list replacement). Waits for the ACK and for the
/// verdict of the goal `withdrawn` names.
pub async fn replace_goals(
    station: (u8, u8),
    signing: Option<([u8; 32], u8)>,
    address: &str,
    items: Vec<MissionItem>,
    timeout: Duration,
) -> Result<GoalSendReport, GoalSendError> {
    transfer(station, signing, address, Transfer::Replace(items), timeout).await
}

/// The component id `goal send` and the page's form use (QGroundControl's).
pub const GCS_COMPONENT: u8 = 190;

/// What an upload does to the station's list.
enum Transfer {
    /// Adds these items to the goals the station holds (read back first).
    Add(Vec<MissionItem>),
    /// Replaces its list by these items: one goal left out, its verdict (cancelled) awaited.
    Replace(Vec<MissionItem>),
}

async fn transfer(
    (system_id, component_id): (u8, u8),
    signing: Option<([u8; 32], u8)>,
    address: &str,
    transfer: Transfer,
    timeout: Duration,
) -> Result<GoalSendReport, GoalSendError> {
    let (items, replace) = match transfer {
        Transfer::Add(items) => (items, false),
        Transfer::Replace(items) => (items, true),
    };
    // Refused before any traffic: a count that wrapped would upload a prefix and look accepted.
    if items.len() > MAX_ITEMS {
        return Err(GoalSendError::TooManyItems(items.len()));
    }
    let expected_texts = if replace {
        1
    } else {
        items
            .iter()
            .filter(|i| i.command != GOAL_ATTRIBUTES_CMD)
            .count()
    };
    let mut transport =
        Transport::bind(Address::parse(address).map_err(GoalSendError::Address)?).await?;
    let mut ep = transport.open().await?;
    let mut enc = Encoder::new(
        system_id,
        component_id,
        signing.map(|(k, l)| Signer::new(k, l)),
    );
    let mut dec = FrameDecoder::default();
    let mut texts = TextAssembler::default();
    let start = Instant::now();
    let now = || start.elapsed().as_millis() as u64;
    let mut client: Option<MissionClient> = None;
    let mut failure: Option<Option<String>> = None;
    let mut collected: Vec<String> = Vec::new();
    let mut last_heartbeat = None::<u64>;
    let mut buf = vec![0u8; 65536];
    let mut pending_items = Some(items);
    let mut quiet_since = Instant::now();
    loop {
        let mut out = Vec::new();
        if last_heartbeat.is_none_or(|t| now().saturating_sub(t) >= 1000) {
            last_heartbeat = Some(now());
            out.push(gcs_heartbeat());
        }
        if let Some(c) = &mut client {
            if let Some((_, outcome)) = c.tick(now(), &mut out) {
                failure = Some(Some(match outcome {
                    MissionOutcome::Failed(r) => r,
                    other => format!("{other:?}"),
                }));
            }
        }
        for m in out.drain(..) {
            ep.send(&enc.encode(&m, false)).await?;
        }
        // A goal answered "received … verdict to follow" is still being inserted into the plan: its final
        // verdict comes later (bounded by the executive's insertion cycles), so the quiet wait does not end it.
        let finals = collected
            .iter()
            .filter(|t| is_final_verdict_text(t))
            .count()
            + collected
                .iter()
                .filter_map(|t| summary_finals(t))
                .sum::<usize>();
        let done_texts = finals >= expected_texts
            || (awaiting_verdicts(&collected) == 0
                && quiet_since.elapsed() > Duration::from_millis(1500))
            || start.elapsed() > timeout * 4;
        match &failure {
            Some(None) if done_texts => break,
            Some(Some(_)) if quiet_since.elapsed() > Duration::from_millis(500) => break,
            _ => {}
        }
        if client.is_none() && start.elapsed() > timeout {
            return Err(GoalSendError::NoCompanion(timeout));
        }
        if failure.is_none() && start.elapsed() > timeout * 4 {
            failure = Some(Some("no answer from the companion".into()));
            continue;
        }
        let n = match tokio::time::timeout(Duration::from_millis(50), ep.recv(&mut buf)).await {
            Ok(r) => r?,
            Err(_) => continue,
        };
        if n == 0 {
            return Err(GoalSendError::Io(std::io::Error::other(
                "connection closed",
            )));
        }
        dec.push(&buf[..n]);
        while let Some(f) = dec.next_frame() {
            if f.component_id != COMPANION_COMPONENT {
                continue;
            }
            let Some(msg) = f.parse() else { continue };
            match (&msg, &mut client) {
                (MavMessage::HEARTBEAT(_), None) => {
                    // An upload replaces this station's list (the mission protocol's meaning): to add
                    // goals, read back the goals it holds first and upload them with the new ones (the
                    // same items: kept, not inserted again).
                    let mut c = MissionClient::new((f.system_id, COMPANION_COMPONENT), 1500, 5);
                    if replace {
                        c.upload(1, pending_items.take().unwrap_or_default(), now(), &mut out);
                    } else {
                        c.download(0, now(), &mut out);
                    }
                    client = Some(c);
                }
                (MavMessage::STATUSTEXT(s), _) => {
                    if let Some(t) = texts.push(s.id, &s.text[..]) {
                        collected.push(t);
                        quiet_since = Instant::now();
                    }
                }
                (_, Some(c)) => {
                    if let Some((_, outcome)) = c.handle(&msg, now(), &mut out) {
                        quiet_since = Instant::now();
                        if let MissionOutcome::Downloaded(mut held) = outcome {
                            held.extend(pending_items.take().unwrap_or_default());
                            if held.len() > MAX_ITEMS {
                                return Err(GoalSendError::TooManyItems(held.len()));
                            }
                            c.upload(1, held, now(), &mut out);
                            continue;
                        }
                        failure = Some(match outcome {
                            MissionOutcome::Uploaded => None,
                            MissionOutcome::Failed(r) => Some(r),
                            other => Some(format!("{other:?}")),
                        });
                    }
                }
                _ => {}
            }
        }
        for m in out.drain(..) {
            ep.send(&enc.encode(&m, false)).await?;
        }
    }
    Ok(GoalSendReport {
        failure: failure.flatten(),
        texts: collected,
    })
}
