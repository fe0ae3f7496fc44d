//! The MAVLink goal intake under arbitrary frames: an input is a list of records `[op, len, payload...]`;
//! most ops give a message id whose payload is decoded by the dialect as the link decodes a CRC-valid
//! frame (undecodable items go to `unparsable_item`, as on the link), others feed the bytes to the frame
//! decoder as a stream, decide a pending upload or move the clock. Seeds are well-formed uploads.

use mavlink::dialects::ardupilotmega::*;
use mavlink::{MavHeader, MavlinkVersion, Message};
use rand::Rng;
use rand_chacha::ChaCha8Rng;

use crate::vehicle::driver::COMPANION_COMPONENT;
use crate::vehicle::frame::FrameDecoder;
use crate::vehicle::geo::Home;
use crate::vehicle::goals::KnownLocations;
use crate::vehicle::intake::GoalIntake;
use crate::vehicle::items::MissionItem;
use crate::vehicle::{Enu, GoalVerdict};

const SYS: u8 = 1;
/// The message ids the ops name (op % 16 below 11), the mission protocol first.
const IDS: [u32; 11] = [44, 73, 39, 43, 51, 40, 47, 45, 0, 76, 253];

fn intake() -> GoalIntake {
    let mut known = KnownLocations::new(Home {
        lat: 43.5615,
        lon: 1.4778,
        alt: 0.0,
    });
    known.objects.push(("p1".into(), Enu::new(10.0, 5.0, 0.0)));
    GoalIntake::new(known, 1).allowing(None)
}

/// One record: the op, the sender's system id and the payload.
fn record(op: u8, msg: &MavMessage) -> Vec<u8> {
    let mut payload = [0u8; 255];
    let n = msg.ser(MavlinkVersion::V2, &mut payload);
    let mut v = vec![op, n as u8];
    v.extend_from_slice(&payload[..n]);
    v
}

/// Seeds: uploads of 1 to 3 goals (waypoints, a picture, return home), cleared, downloaded, re-requested.
pub fn corpus() -> Vec<Vec<u8>> {
    let target = (SYS, COMPANION_COMPONENT);
    let count = |n: u16| {
        MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
            count: n,
            target_system: SYS,
            target_component: COMPANION_COMPONENT,
            mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
            opaque_id: 0,
        })
    };
    let mut picture = MissionItem::waypoint(43.5616, 1.4779, 0.0);
    picture.command = 2000; // IMAGE_START_CAPTURE
    let items = [
        MissionItem::waypoint(43.5616, 1.4779, 0.0),
        picture,
        MissionItem::waypoint(43.5617, 1.4781, 5.0),
    ];
    let mut out = Vec::new();
    for n in 1..=items.len() {
        let mut seed = record(0, &count(n as u16));
        for (seq, it) in items[..n].iter().enumerate() {
            if let Some(d) = it.to_int(seq as u16, target, MavMissionType::MAV_MISSION_TYPE_MISSION)
            {
                seed.extend(record(1, &MavMessage::MISSION_ITEM_INT(d)));
            }
        }
        seed.extend([DECIDE, 0]);
        seed.extend(record(
            3,
            &MavMessage::MISSION_REQUEST_LIST(MISSION_REQUEST_LIST_DATA {
                target_system: SYS,
                target_component: COMPANION_COMPONENT,
                mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
            }),
        ));
        seed.extend([TICK, 2, 0xdc, 0x05]);
        out.push(seed);
    }
    out
}

/// An upload built field by field, in the wire layout of MISSION_COUNT and MISSION_ITEM_INT, with edge
/// values (NaN, ±inf, latitude 214°, unknown commands and frames, wrong targets, sequence gaps) and the
/// other ops interleaved.
pub fn generate(rng: &mut ChaCha8Rng) -> Vec<u8> {
    const FLOATS: [f32; 9] = [
        0.0,
        1.0,
        -1.0,
        600.0,
        f32::NAN,
        f32::INFINITY,
        f32::NEG_INFINITY,
        3.4e38,
        1e-40,
    ];
    const COORDS: [i32; 7] = [
        435_616_000,
        14_779_000,
        0,
        2_140_000_000,
        i32::MIN,
        i32::MAX,
        -900_000_001,
    ];
    const COMMANDS: [u16; 9] = [16, 20, 21, 2000, 183, 31_000, 31_011, 0, 65_535];
    // Mostly sane values, so that a good share of uploads reaches the decider; edge values now and then.
    let pick_f = |rng: &mut ChaCha8Rng| {
        if rng.gen_bool(0.1) {
            FLOATS[rng.gen_range(0..FLOATS.len())]
        } else {
            rng.gen_range(0f32..10.0)
        }
    };
    let target = |rng: &mut ChaCha8Rng| {
        if rng.gen_bool(0.97) {
            [SYS, COMPANION_COMPONENT]
        } else {
            [rng.gen_range(0..3), rng.gen()]
        }
    };
    let mut out = Vec::new();
    let n: u16 = if rng.gen_bool(0.9) {
        rng.gen_range(1..6)
    } else {
        rng.gen()
    };
    let mut count = n.to_le_bytes().to_vec();
    count.extend(target(rng));
    count.push(if rng.gen_bool(0.97) { 0 } else { rng.gen() });
    out.extend([0, count.len() as u8]);
    out.extend(count);
    for seq in 0..n.min(8) {
        let mut item = Vec::with_capacity(38);
        for _ in 0..4 {
            item.extend(pick_f(rng).to_le_bytes());
        }
        for near in [435_616_000, 14_779_000] {
            let c = match rng.gen_range(0..10) {
                0 => COORDS[rng.gen_range(0..COORDS.len())],
                1 => rng.gen(),
                _ => near + rng.gen_range(-3_000..3_000),
            };
            item.extend(c.to_le_bytes());
        }
        item.extend(pick_f(rng).to_le_bytes());
        let seq = if rng.gen_bool(0.95) {
            seq
        } else {
            rng.gen_range(0..10)
        };
        item.extend(seq.to_le_bytes());
        let command = match rng.gen_range(0..10) {
            0 => COMMANDS[rng.gen_range(0..COMMANDS.len())],
            1 => rng.gen(),
            2..=4 => 2000,
            _ => 16,
        };
        item.extend(command.to_le_bytes());
        item.extend(target(rng));
        item.push(if rng.gen_bool(0.9) {
            3
        } else {
            [0, 6, 10, 11, 255][rng.gen_range(0..5)]
        });
        item.extend([
            rng.gen_range(0..2),
            rng.gen_range(0..2),
            if rng.gen_bool(0.95) { 0 } else { rng.gen() },
        ]);
        // MAVLink 2 trims trailing zeros: sometimes a shorter payload.
        if rng.gen_bool(0.05) {
            item.truncate(rng.gen_range(20..=item.len()));
        }
        out.extend([1, item.len() as u8]);
        out.extend(item);
        if rng.gen_bool(0.1) {
            out.extend([TICK, 2, rng.gen(), rng.gen()]);
        }
        if rng.gen_bool(0.05) {
            let op: u8 = rng.gen_range(0..16) | (rng.gen_range(0..4) << 6);
            let len = rng.gen_range(0..40u8);
            out.extend([op, len]);
            out.extend((0..len).map(|_| rng.gen::<u8>()));
        }
    }
    out.extend([DECIDE, 1, rng.gen()]);
    out
}

const DECIDE: u8 = 11;
const TICK: u8 = 12;
const STREAM: u8 = 13;

/// Runs one input through the intake; a panic is the only failure.
pub fn run(bytes: &[u8]) -> Result<(), super::targets::Oops> {
    decisions(bytes);
    Ok(())
}

/// Runs one input through the intake: how many uploads were completed and put to the decider.
pub fn decisions(bytes: &[u8]) -> usize {
    let mut decided = 0;
    let mut intake = intake();
    let mut decoder = FrameDecoder::default();
    let mut out = Vec::new();
    let mut pending: Option<crate::vehicle::intake::PendingDecision> = None;
    let mut now = 0u64;
    let mut rest = bytes;
    while let [op, len, tail @ ..] = rest {
        let n = usize::from(*len).min(tail.len());
        let (payload, next) = tail.split_at(n);
        rest = next;
        // The high bits pick the sender: mostly the ground station, sometimes another system.
        let header = MavHeader {
            system_id: [255, 255, 255, 7][usize::from(op >> 6)],
            component_id: 190,
            sequence: 0,
        };
        match op & 0x0f {
            DECIDE => {
                if let Some(p) = pending.take() {
                    decided += 1;
                    let verdicts = match payload.first().map(|b| b % 3) {
                        Some(0) | None => vec![GoalVerdict::Accepted],
                        Some(1) => vec![GoalVerdict::Rejected("no".into())],
                        Some(_) => vec![GoalVerdict::Inserting; 4],
                    };
                    let cancelled = Some(p.cancel.clone());
                    intake.decided(p, &verdicts, cancelled, &mut out);
                }
            }
            TICK => {
                let dt = payload.iter().fold(0u64, |a, b| (a << 8) | u64::from(*b));
                now = now.saturating_add(dt);
                intake.tick(now, &mut out);
            }
            STREAM => {
                decoder.push(payload);
                while let Some(frame) = decoder.next_frame() {
                    feed(
                        &mut intake,
                        frame.header(),
                        frame.message_id,
                        frame.payload(),
                        now,
                        &mut out,
                        &mut pending,
                    );
                }
            }
            k => {
                let id = IDS[usize::from(k) % IDS.len()];
                feed(
                    &mut intake,
                    header,
                    id,
                    payload,
                    now,
                    &mut out,
                    &mut pending,
                );
            }
        }
        out.clear();
    }
    decided
}

/// A frame's payload as the link handles it: decoded and handled, or an undecodable item answered.
fn feed(
    intake: &mut GoalIntake,
    header: MavHeader,
    id: u32,
    payload: &[u8],
    now: u64,
    out: &mut Vec<MavMessage>,
    pending: &mut Option<crate::vehicle::intake::PendingDecision>,
) {
    match MavMessage::parse(MavlinkVersion::V2, id, payload) {
        Ok(msg) => {
            if let Some(p) = intake.handle(header, &msg, None, SYS, now, out) {
                *pending = Some(p);
            }
        }
        Err(_) => {
            if let Some(p) = intake.unparsable_item(header, id, payload, SYS, now, out) {
                *pending = Some(p);
            }
        }
    }
}
