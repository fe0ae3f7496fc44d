//! Goal intake and mission client talking in memory: upload, decision, ACK + STATUSTEXTs, download of the
//! accepted list, clear, and re-requests after a lost item.

use mavlink::dialects::ardupilotmega::*;
use mavlink::MavHeader;
use mavtempo::vehicle::geo::Home;
use mavtempo::vehicle::goals::KnownLocations;
use mavtempo::vehicle::intake::GoalIntake;
use mavtempo::vehicle::items::MissionItem;
use mavtempo::vehicle::mission_client::{MissionClient, MissionOutcome};
use mavtempo::vehicle::GoalVerdict;

const GCS: MavHeader = MavHeader {
    system_id: 255,
    component_id: 190,
    sequence: 0,
};
const SYS: u8 = 1;

fn intake() -> GoalIntake {
    GoalIntake::new(
        KnownLocations::new(Home {
            lat: 43.56,
            lon: 1.48,
            alt: 0.0,
        }),
        1,
    )
}

/// MISSION_COUNT of `n` goal items to the companion.
fn mission_count(n: u16) -> MavMessage {
    MavMessage::MISSION_COUNT(MISSION_COUNT_DATA {
        count: n,
        target_system: SYS,
        target_component: 191,
        mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
        opaque_id: 0,
    })
}

fn items() -> Vec<MissionItem> {
    vec![
        MissionItem::waypoint(43.5601, 1.4801, 0.0),
        MissionItem::waypoint(43.5602, 1.4802, 0.0),
    ]
}

/// Runs the conversation to quiescence, dropping the companion→GCS messages `drop` selects once.
fn converse(
    i: &mut GoalIntake,
    c: &mut MissionClient,
    mut to_intake: Vec<MavMessage>,
    now: u64,
    verdicts: &[GoalVerdict],
) -> (Option<MissionOutcome>, Vec<String>) {
    let mut texts = Vec::new();
    let mut outcome = None;
    for _ in 0..100 {
        let mut to_gcs = Vec::new();
        for m in to_intake.drain(..) {
            if let Some(p) = i.handle(GCS, &m, SYS, now, &mut to_gcs) {
                i.decided(p, verdicts, &mut to_gcs);
            }
        }
        if to_gcs.is_empty() {
            break;
        }
        for m in to_gcs {
            if let MavMessage::STATUSTEXT(s) = &m {
                texts.push(
                    s.text
                        .to_str()
                        .unwrap_or("")
                        .trim_end_matches('\0')
                        .to_string(),
                );
            }
            if let Some((_, o)) = c.handle(&m, now, &mut to_intake) {
                outcome = Some(o);
            }
        }
    }
    (outcome, texts)
}

#[test]
fn upload_decide_then_download_the_accepted_list() {
    let (mut i, mut c) = (intake(), MissionClient::new((SYS, 191), 1500, 3));
    let mut out = Vec::new();
    assert!(c.upload(0, items(), 0, &mut out));
    let verdicts = [
        GoalVerdict::Accepted,
        GoalVerdict::Rejected("too far".into()),
    ];
    let (outcome, texts) = converse(&mut i, &mut c, out, 0, &verdicts);
    assert_eq!(outcome, Some(MissionOutcome::Uploaded));
    assert_eq!(
        texts,
        vec![
            "g1 accepted: at(g1_loc)".to_string(),
            "g2 rejected: too far".to_string()
        ]
    );

    let mut out = Vec::new();
    assert!(c.download(1, 10, &mut out));
    let (outcome, _) = converse(&mut i, &mut c, out, 10, &[]);
    let Some(MissionOutcome::Downloaded(got)) = outcome else {
        panic!("{outcome:?}")
    };
    assert_eq!(got.len(), 2);
    assert!(
        (got[1].x - 43.5602).abs() < 1e-7 && (got[1].y - 1.4802).abs() < 1e-7,
        "{:?}",
        got[1]
    );

    let mut out = Vec::new();
    assert!(c.clear(2, 20, &mut out));
    let (outcome, _) = converse(&mut i, &mut c, out, 20, &[]);
    assert_eq!(outcome, Some(MissionOutcome::Cleared));
}

#[test]
fn goal_numbers_continue_across_uploads() {
    let (mut i, mut c) = (intake(), MissionClient::new((SYS, 191), 1500, 3));
    for (n, expected) in [(0u64, "g1"), (1, "g3")] {
        let mut out = Vec::new();
        assert!(c.upload(n, items(), 0, &mut out));
        let (_, texts) = converse(
            &mut i,
            &mut c,
            out,
            0,
            &[GoalVerdict::Accepted, GoalVerdict::Accepted],
        );
        assert!(texts[0].starts_with(expected), "{texts:?}");
    }
}

#[test]
fn requests_from_someone_not_downloading_are_not_answered() {
    let mut i = intake();
    let mut out = Vec::new();
    let req = MavMessage::MISSION_REQUEST_INT(MISSION_REQUEST_INT_DATA {
        seq: 0,
        target_system: SYS,
        target_component: 191,
        mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
    });
    assert!(i.handle(GCS, &req, SYS, 0, &mut out).is_none());
    assert!(out.is_empty(), "{out:?}");
}

#[test]
fn a_lost_item_is_requested_again_and_a_silent_uploader_is_cancelled() {
    let mut i = intake();
    let mut out = Vec::new();
    let count = mission_count(2);
    i.handle(GCS, &count, SYS, 0, &mut out);
    assert!(matches!(out.as_slice(), [MavMessage::MISSION_REQUEST_INT(r)] if r.seq == 0));
    out.clear();
    // Item 1 before item 0: item 0 is asked again.
    let item1 = MavMessage::MISSION_ITEM_INT(
        items()[1]
            .to_int(1, (SYS, 191), MavMissionType::MAV_MISSION_TYPE_MISSION)
            .expect("wire"),
    );
    i.handle(GCS, &item1, SYS, 10, &mut out);
    assert!(matches!(out.as_slice(), [MavMessage::MISSION_REQUEST_INT(r)] if r.seq == 0));
    out.clear();
    i.tick(1509, &mut out);
    assert!(out.is_empty());
    i.tick(1510, &mut out);
    assert!(
        matches!(out.as_slice(), [MavMessage::MISSION_REQUEST_INT(r)] if r.seq == 0),
        "re-request on timeout"
    );
    out.clear();
    for k in 2..=6 {
        i.tick(1510 * k, &mut out);
    }
    assert!(
        out.iter().any(|m| matches!(m, MavMessage::MISSION_ACK(a) if a.mavtype == MavMissionResult::MAV_MISSION_OPERATION_CANCELLED)),
        "{out:?}"
    );
}

/// An item whose command id the dialect does not know cannot be parsed: it is answered with MISSION_ACK
/// UNSUPPORTED and a reason at once, and the intake is free for the next uploader (it used to be dropped
/// silently, leaving the upload locked while others were DENIED).
#[test]
fn an_item_with_an_unknown_command_is_refused_at_once() {
    use mavlink::Message;
    let mut i = intake();
    let mut out = Vec::new();
    let count = mission_count(2);
    assert!(i.handle(GCS, &count, SYS, 0, &mut out).is_none());
    assert!(matches!(out.as_slice(), [MavMessage::MISSION_REQUEST_INT(r)] if r.seq == 0));
    // MISSION_ITEM_INT's wire payload: seq 0, command 48879 (no such MAV_CMD), to (SYS, 191).
    let mut payload = vec![0u8; 38];
    payload[30..32].copy_from_slice(&48_879u16.to_le_bytes());
    payload[32] = SYS;
    payload[33] = 191;
    assert!(
        MavMessage::parse(mavlink::MavlinkVersion::V2, 73, &payload).is_err(),
        "the dialect should not read it"
    );
    let mut out = Vec::new();
    i.unparsable_item(GCS, 73, &payload, SYS, &mut out);
    assert!(
        out.iter().any(|m| matches!(m, MavMessage::MISSION_ACK(a)
            if a.mavtype == MavMissionResult::MAV_MISSION_UNSUPPORTED && a.target_system == 255)),
        "{out:?}"
    );
    let texts: String = out
        .iter()
        .filter_map(|m| match m {
            MavMessage::STATUSTEXT(s) => s
                .text
                .to_str()
                .ok()
                .map(|t| t.trim_end_matches('\0').to_string()),
            _ => None,
        })
        .collect();
    assert!(texts.contains("command 48879"), "{texts}");
    // Another station can upload right away.
    let other = MavHeader {
        system_id: 254,
        component_id: 190,
        sequence: 0,
    };
    let mut out = Vec::new();
    i.handle(other, &count, SYS, 10, &mut out);
    assert!(
        matches!(out.as_slice(), [MavMessage::MISSION_REQUEST_INT(r)] if r.seq == 0 && r.target_system == 254),
        "{out:?}"
    );
    // Someone else's unparsable traffic (another target) is not ours to answer.
    let mut foreign = payload.clone();
    foreign[33] = 1;
    let mut out = Vec::new();
    i.unparsable_item(GCS, 73, &foreign, SYS, &mut out);
    assert!(out.is_empty());
}

/// A chunked STATUSTEXT is complete at its first chunk shorter than 50 bytes: a text of exactly 100 bytes
/// (a goal's final verdict can be) ends with an empty chunk, or the ground station would wait for more.
#[test]
fn a_text_whose_length_is_a_multiple_of_50_ends_with_an_empty_chunk() {
    use mavtempo::vehicle::goal_client::TextAssembler;
    use mavtempo::vehicle::intake::statustext;
    for len in [49, 50, 51, 100, 149, 150] {
        let text: String = "x".repeat(len);
        let msgs = statustext(&text, MavSeverity::MAV_SEVERITY_INFO, 7);
        let mut asm = TextAssembler::default();
        let got: Vec<String> = msgs
            .iter()
            .filter_map(|m| match m {
                MavMessage::STATUSTEXT(s) => asm.push(s.id, &s.text[..]),
                _ => None,
            })
            .collect();
        assert_eq!(got, vec![text], "{len} bytes");
    }
}
