//! Goal intake and mission client talking in memory: upload, decision, ACK + STATUSTEXTs, download of the
//! accepted list, clear, and re-requests after a lost item.

use mavlink::dialects::ardupilotmega::*;
use mavlink::MavHeader;
use mavtempo_vehicle::geo::Home;
use mavtempo_vehicle::goals::KnownLocations;
use mavtempo_vehicle::intake::GoalIntake;
use mavtempo_vehicle::items::MissionItem;
use mavtempo_vehicle::mission_client::{MissionClient, MissionOutcome};
use mavtempo_vehicle::GoalVerdict;

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
    let mut asm = mavtempo_vehicle::goal_client::TextAssembler::default();
    let mut outcome = None;
    for _ in 0..1000 {
        let mut to_gcs = Vec::new();
        for m in to_intake.drain(..) {
            if let Some(p) = i.handle(GCS, &m, None, SYS, now, &mut to_gcs) {
                let cancelled = Some(p.cancel.clone());
                i.decided(p, verdicts, cancelled, &mut to_gcs);
            }
        }
        if to_gcs.is_empty() {
            break;
        }
        for m in to_gcs {
            if let MavMessage::STATUSTEXT(s) = &m {
                texts.extend(asm.push(s.id, &s.text[..]));
            }
            if let Some((_, o)) = c.handle(&m, now, &mut to_intake) {
                outcome = Some(o);
            }
        }
    }
    (outcome, texts)
}

/// The list read back holds exactly the goals held: not the rejected one.
#[test]
fn upload_decide_then_download_the_goals_held() {
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
    assert_eq!(got.len(), 1, "the rejected g2 is not held: {got:?}");
    assert!(
        (got[0].x - 43.5601).abs() < 1e-7 && (got[0].y - 1.4801).abs() < 1e-7,
        "{:?}",
        got[0]
    );

    let mut out = Vec::new();
    assert!(c.clear(2, 20, &mut out));
    let (outcome, texts) = converse(&mut i, &mut c, out, 20, &[]);
    assert_eq!(outcome, Some(MissionOutcome::Cleared));
    assert!(
        texts.iter().any(|t| t.starts_with("g1 cancelled: cleared")),
        "{texts:?}"
    );
    assert!(i.held_names((255, 190)).is_empty());
}

/// A new list from the same station replaces its last one: the goal left out is cancelled, the goal
/// uploaded again is kept (not inserted twice), a new one is requested.
#[test]
fn a_new_list_replaces_the_station_s_last_one() {
    let (mut i, mut c) = (intake(), MissionClient::new((SYS, 191), 1500, 3));
    let mut out = Vec::new();
    assert!(c.upload(0, items(), 0, &mut out));
    converse(
        &mut i,
        &mut c,
        out,
        0,
        &[GoalVerdict::Accepted, GoalVerdict::Accepted],
    );
    assert_eq!(i.held_names((255, 190)), ["g1", "g2"]);
    let mut out = Vec::new();
    let list = vec![
        items()[1].clone(),
        MissionItem::waypoint(43.5603, 1.4803, 0.0),
    ];
    assert!(c.upload(1, list, 10, &mut out));
    let (outcome, texts) = converse(&mut i, &mut c, out, 10, &[GoalVerdict::Accepted]);
    assert_eq!(outcome, Some(MissionOutcome::Uploaded));
    assert!(
        texts
            .iter()
            .any(|t| t.starts_with("g1 cancelled: left out")),
        "{texts:?}"
    );
    assert!(
        texts.iter().any(|t| t == "g3 accepted: at(g3_loc)"),
        "{texts:?}"
    );
    assert_eq!(i.held_names((255, 190)), ["g2", "g3"]);
}

#[test]
fn goal_numbers_continue_across_uploads() {
    let (mut i, mut c) = (intake(), MissionClient::new((SYS, 191), 1500, 3));
    let second = vec![
        MissionItem::waypoint(43.5611, 1.4811, 0.0),
        MissionItem::waypoint(43.5612, 1.4812, 0.0),
    ];
    for (n, expected, list) in [(0u64, "g1", items()), (1, "g3", second)] {
        let mut out = Vec::new();
        assert!(c.upload(n, list, 0, &mut out));
        let (_, texts) = converse(
            &mut i,
            &mut c,
            out,
            0,
            &[GoalVerdict::Accepted, GoalVerdict::Accepted],
        );
        assert!(texts.iter().any(|t| t.starts_with(expected)), "{texts:?}");
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
    assert!(i.handle(GCS, &req, None, SYS, 0, &mut out).is_none());
    assert!(out.is_empty(), "{out:?}");
}

#[test]
fn a_lost_item_is_requested_again_and_a_silent_uploader_is_cancelled() {
    let mut i = intake();
    let mut out = Vec::new();
    let count = mission_count(2);
    i.handle(GCS, &count, None, SYS, 0, &mut out);
    assert!(matches!(out.as_slice(), [MavMessage::MISSION_REQUEST_INT(r)] if r.seq == 0));
    out.clear();
    // Item 1 before item 0: item 0 is asked again.
    let item1 = MavMessage::MISSION_ITEM_INT(
        items()[1]
            .to_int(1, (SYS, 191), MavMissionType::MAV_MISSION_TYPE_MISSION)
            .expect("wire"),
    );
    i.handle(GCS, &item1, None, SYS, 10, &mut out);
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

/// An item whose command id the dialect does not know cannot be parsed: it is kept as an item no goal is
/// made of, and the list's answer names it in a warning (the whole list used to be refused); someone
/// else's unparsable traffic is not ours to answer.
#[test]
fn an_item_with_an_unknown_command_is_skipped_with_a_warning() {
    use mavlink::Message;
    let mut i = intake();
    let mut out = Vec::new();
    let count = mission_count(2);
    assert!(i.handle(GCS, &count, None, SYS, 0, &mut out).is_none());
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
    // Someone else's unparsable traffic (another target) is not ours to answer.
    let mut foreign = payload.clone();
    foreign[33] = 1;
    let mut out = Vec::new();
    assert!(i
        .unparsable_item(GCS, 73, &foreign, SYS, 5, &mut out)
        .is_none());
    assert!(out.is_empty());
    assert!(i
        .unparsable_item(GCS, 73, &payload, SYS, 5, &mut out)
        .is_none());
    assert!(matches!(out.as_slice(), [MavMessage::MISSION_REQUEST_INT(r)] if r.seq == 1));
    let item1 = MavMessage::MISSION_ITEM_INT(
        items()[1]
            .to_int(1, (SYS, 191), MavMissionType::MAV_MISSION_TYPE_MISSION)
            .expect("wire"),
    );
    let mut out = Vec::new();
    let p = i
        .handle(GCS, &item1, None, SYS, 10, &mut out)
        .expect("complete");
    assert_eq!(p.goals.len(), 1);
    i.decided(p, &[GoalVerdict::Accepted], Some(Vec::new()), &mut out);
    let texts = texts(&out);
    assert!(
        out.iter().any(|m| matches!(m, MavMessage::MISSION_ACK(a)
            if a.mavtype == MavMissionResult::MAV_MISSION_ACCEPTED && a.target_system == 255)),
        "{out:?}"
    );
    assert!(
        texts.iter().any(|t| t.starts_with("item 0: command 48879")),
        "{texts:?}"
    );
    assert!(
        texts.iter().any(|t| t == "g1 accepted: at(g1_loc)"),
        "{texts:?}"
    );
}

fn texts(out: &[MavMessage]) -> Vec<String> {
    let mut asm = mavtempo_vehicle::goal_client::TextAssembler::default();
    out.iter()
        .filter_map(|m| match m {
            MavMessage::STATUSTEXT(s) => asm.push(s.id, &s.text[..]),
            _ => None,
        })
        .collect()
}

fn acks(out: &[MavMessage]) -> Vec<MavMissionResult> {
    out.iter()
        .filter_map(|m| match m {
            MavMessage::MISSION_ACK(a) => Some(a.mavtype),
            _ => None,
        })
        .collect()
}

/// A declared count past the limit is refused at once with why; one station's stalled upload never
/// blocks another's; a station speaking with the same ids from another address is refused, not mixed in.
#[test]
fn nobody_can_jam_the_intake() {
    use mavtempo_vehicle::intake::MAX_GOAL_ITEMS;
    let mut i = intake();
    let mut out = Vec::new();
    i.handle(
        GCS,
        &mission_count(MAX_GOAL_ITEMS + 1),
        None,
        SYS,
        0,
        &mut out,
    );
    assert_eq!(acks(&out), [MavMissionResult::MAV_MISSION_NO_SPACE]);
    assert!(texts(&out)[0].contains("at most 256"), "{:?}", texts(&out));
    let a: std::net::SocketAddr = "127.0.0.1:1000".parse().expect("addr");
    let b: std::net::SocketAddr = "127.0.0.1:2000".parse().expect("addr");
    let mut out = Vec::new();
    i.handle(
        GCS,
        &mission_count(MAX_GOAL_ITEMS),
        Some(a),
        SYS,
        0,
        &mut out,
    );
    assert!(matches!(out.as_slice(), [MavMessage::MISSION_REQUEST_INT(r)] if r.seq == 0));
    // The same ids from another address: refused with why, the first upload goes on.
    let mut out = Vec::new();
    i.handle(GCS, &mission_count(1), Some(b), SYS, 1, &mut out);
    assert_eq!(acks(&out), [MavMissionResult::MAV_MISSION_DENIED]);
    assert!(
        texts(&out)[0].contains("share these ids"),
        "{:?}",
        texts(&out)
    );
    let item0 = MavMessage::MISSION_ITEM_INT(
        items()[0]
            .to_int(0, (SYS, 191), MavMissionType::MAV_MISSION_TYPE_MISSION)
            .expect("wire"),
    );
    let mut out = Vec::new();
    i.handle(GCS, &item0, Some(b), SYS, 2, &mut out);
    assert!(
        out.is_empty(),
        "an item from the other address is not mixed in: {out:?}"
    );
    // Another station uploads while the first stalls.
    let other = MavHeader {
        system_id: 254,
        component_id: 190,
        sequence: 0,
    };
    let mut out = Vec::new();
    i.handle(other, &mission_count(1), None, SYS, 3, &mut out);
    let mut out = Vec::new();
    let p = i.handle(other, &item0, None, SYS, 4, &mut out);
    assert_eq!(p.map(|p| p.goals.len()), Some(1));
}

/// A large list is answered with counts by reason, not one text per item.
#[test]
fn a_large_upload_is_answered_with_counts() {
    let (mut i, mut c) = (intake(), MissionClient::new((SYS, 191), 1500, 3));
    let mut list = Vec::new();
    for k in 0..100 {
        list.push(MissionItem::waypoint(
            43.5601 + f64::from(k) * 1e-5,
            1.4801,
            0.0,
        ));
        let mut speed = MissionItem::waypoint(0.0, 0.0, 0.0);
        speed.command = 178; // DO_CHANGE_SPEED: no goal
        list.push(speed);
    }
    let mut out = Vec::new();
    assert!(c.upload(0, list, 0, &mut out));
    let verdicts: Vec<GoalVerdict> = (0..100)
        .map(|k| {
            if k % 4 == 0 {
                GoalVerdict::Rejected("too far".into())
            } else {
                GoalVerdict::Accepted
            }
        })
        .collect();
    let (outcome, texts) = converse(&mut i, &mut c, out, 0, &verdicts);
    assert_eq!(outcome, Some(MissionOutcome::Uploaded));
    assert_eq!(texts.len(), 2, "{texts:?}");
    assert!(
        texts[0].starts_with("100 items skipped: 100 x command 178"),
        "{texts:?}"
    );
    assert_eq!(
        texts[1],
        "100 goals (g1-g100): 75 x accepted; 25 x rejected: too far"
    );
}

/// Home as item 0 (pymavlink's mavwp, MAVProxy's `wp load`: a waypoint in the absolute global frame) is
/// not a goal; the answer says so.
#[test]
fn home_as_item_0_is_skipped() {
    let (mut i, mut c) = (intake(), MissionClient::new((SYS, 191), 1500, 3));
    let mut home = MissionItem::waypoint(43.56, 1.48, 0.0);
    home.frame = 0;
    let mut list = vec![home];
    list.extend(items());
    let mut out = Vec::new();
    assert!(c.upload(0, list, 0, &mut out));
    let (_, texts) = converse(
        &mut i,
        &mut c,
        out,
        0,
        &[GoalVerdict::Accepted, GoalVerdict::Accepted],
    );
    assert!(
        texts[0].starts_with("item 0: the home position"),
        "{texts:?}"
    );
    assert_eq!(texts[1], "g1 accepted: at(g1_loc)");
    assert_eq!(i.held_names((255, 190)), ["g1", "g2"]);
}

/// A chunked STATUSTEXT is complete at its first chunk shorter than 50 bytes: a text of exactly 100 bytes
/// (a goal's final verdict can be) ends with an empty chunk, or the ground station would wait for more.
#[test]
fn a_text_whose_length_is_a_multiple_of_50_ends_with_an_empty_chunk() {
    use mavtempo_vehicle::goal_client::TextAssembler;
    use mavtempo_vehicle::intake::statustext;
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
