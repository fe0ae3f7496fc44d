//! Goals withdrawn over real UDP sockets (issue 30 item 3) and no heartbeat amplification (issue 31 item 5):
//! a ground station uploads to component 191, MISSION_CLEAR_ALL reaches the executive as a cancel and is
//! answered ACCEPTED only once the executive confirms, MISSION_REQUEST_LIST then reads back exactly the goals
//! held; a flood of HEARTBEATs gets the companion's at its own rate.

use crate::support::gcs_config;

use std::net::{SocketAddr, UdpSocket};
use std::time::{Duration, Instant};

use mavlink::dialects::ardupilotmega::*;
use mavtempo_vehicle::frame::{Encoder, FrameDecoder};
use mavtempo_vehicle::goal_client::TextAssembler;
use mavtempo_vehicle::items::MissionItem;
use mavtempo_vehicle::link::{Decider, LinkOptions, MavlinkVehicle};
use mavtempo_vehicle::mission_client::{MissionClient, MissionOutcome};
use mavtempo_vehicle::{GoalVerdict, Vehicle, VehicleEvent};

fn companion() -> (MavlinkVehicle, SocketAddr) {
    companion_answering_within(Duration::from_secs(20))
}

/// A companion whose uploads are answered within `timeout` whatever the executive has decided by then.
fn companion_answering_within(timeout: Duration) -> (MavlinkVehicle, SocketAddr) {
    let cfg = gcs_config::config("");
    let opts = LinkOptions {
        gcs: Some("udpin:127.0.0.1:0".into()),
        decider: Decider::Executive { timeout },
        ..LinkOptions::default()
    };
    let v = MavlinkVehicle::connect_blocking(cfg, opts).expect("link");
    let gcs = v.gcs_addr().expect("gcs bound");
    (v, gcs)
}

/// A ground station on its own UDP socket.
struct Station {
    s: UdpSocket,
    enc: Encoder,
    dec: FrameDecoder,
    texts: TextAssembler,
}

impl Station {
    fn new(to: SocketAddr) -> Self {
        let s = UdpSocket::bind("127.0.0.1:0").expect("bind");
        s.connect(to).expect("connect");
        s.set_read_timeout(Some(Duration::from_millis(20)))
            .expect("timeout");
        Self {
            s,
            enc: Encoder::new(255, 190, None),
            dec: FrameDecoder::default(),
            texts: TextAssembler::default(),
        }
    }

    fn send(&mut self, msgs: Vec<MavMessage>) {
        for m in msgs {
            self.s.send(&self.enc.encode(&m, false)).expect("send");
        }
    }

    /// Messages received now (waiting at most the read timeout).
    fn receive(&mut self) -> Vec<MavMessage> {
        let mut buf = [0u8; 2048];
        if let Ok(n) = self.s.recv(&mut buf) {
            self.dec.push(&buf[..n]);
        }
        let mut out = Vec::new();
        while let Some(f) = self.dec.next_frame() {
            out.extend(f.parse());
        }
        out
    }

    /// Drives `c` until its operation ends, playing the executive with `exec` meanwhile; the outcome and
    /// the texts received.
    fn run(
        &mut self,
        c: &mut MissionClient,
        first: Vec<MavMessage>,
        v: &mut MavlinkVehicle,
        exec: &mut dyn FnMut(VehicleEvent),
    ) -> (MissionOutcome, Vec<String>) {
        let start = Instant::now();
        let now = || start.elapsed().as_millis() as u64;
        self.send(first);
        let mut texts = Vec::new();
        loop {
            assert!(start.elapsed() < Duration::from_secs(20), "no outcome");
            while let Some(e) = v.try_event() {
                exec(e);
            }
            let mut out = Vec::new();
            let mut outcome = c.tick(now(), &mut out).map(|(_, o)| o);
            for m in self.receive() {
                if let MavMessage::STATUSTEXT(s) = &m {
                    texts.extend(self.texts.push(s.id, &s.text[..]));
                }
                if let Some((_, o)) = c.handle(&m, now(), &mut out) {
                    outcome = Some(o);
                }
            }
            self.send(out);
            if let Some(o) = outcome {
                // The texts sent with the answer.
                for _ in 0..5 {
                    for m in self.receive() {
                        if let MavMessage::STATUSTEXT(s) = &m {
                            texts.extend(self.texts.push(s.id, &s.text[..]));
                        }
                    }
                }
                return (o, texts);
            }
        }
    }
}

#[test]
fn clear_all_cancels_through_the_executive_and_the_list_reads_back_what_is_held() {
    let (mut v, gcs) = companion();
    let mut st = Station::new(gcs);
    // The companion learns the station from its heartbeat.
    st.send(vec![mavtempo_vehicle::goal_client::gcs_heartbeat()]);
    let mut c = MissionClient::new((1, 191), 1500, 5);
    let items = vec![
        MissionItem::waypoint(43.5615, 1.4778, 0.0),
        MissionItem::waypoint(43.5616, 1.4779, 0.0),
    ];
    let mut out = Vec::new();
    assert!(c.upload(0, items, 0, &mut out));
    let mut cancels: Vec<Vec<String>> = Vec::new();
    let mut exec = |e: VehicleEvent| match e {
        VehicleEvent::Goals(b) => b.answer(vec![
            GoalVerdict::Accepted,
            GoalVerdict::Rejected("needs 280 % of the battery".into()),
        ]),
        VehicleEvent::Cancel(k) => {
            cancels.push(k.names.clone());
            let names = k.names.clone();
            k.answer(names);
        }
        _ => {}
    };
    let (o, texts) = st.run(&mut c, out, &mut v, &mut exec);
    assert_eq!(o, MissionOutcome::Uploaded, "{texts:?}");
    assert_eq!(
        texts,
        [
            "g1 accepted: at(g1_loc)",
            "g2 rejected: needs 280 % of the battery"
        ]
    );
    // Read back: only g1 is held.
    let mut out = Vec::new();
    assert!(c.download(1, 0, &mut out));
    let (o, _) = st.run(&mut c, out, &mut v, &mut exec);
    let MissionOutcome::Downloaded(got) = o else {
        panic!("{o:?}")
    };
    assert_eq!(got.len(), 1);
    assert!((got[0].x - 43.5615).abs() < 1e-7, "{got:?}");
    // Clear: the executive is asked to cancel g1, then the station gets ACCEPTED.
    let mut out = Vec::new();
    assert!(c.clear(2, 0, &mut out));
    let (o, texts) = st.run(&mut c, out, &mut v, &mut exec);
    assert_eq!(o, MissionOutcome::Cleared);
    assert!(
        texts.iter().any(|t| t.starts_with("g1 cancelled: cleared")),
        "{texts:?}"
    );
    let mut out = Vec::new();
    assert!(c.download(3, 0, &mut out));
    let (o, _) = st.run(&mut c, out, &mut v, &mut exec);
    assert_eq!(o, MissionOutcome::Downloaded(Vec::new()));
    assert_eq!(cancels, [vec!["g1".to_string()]]);
}

#[test]
fn a_heartbeat_flood_gets_heartbeats_at_their_own_rate() {
    let (_v, gcs) = companion();
    let mut st = Station::new(gcs);
    let start = Instant::now();
    let mut heard = 0usize;
    for _ in 0..2_000 {
        st.send(vec![mavtempo_vehicle::goal_client::gcs_heartbeat()]);
    }
    // Everything the companion sent meanwhile (and a little after).
    for _ in 0..20 {
        heard += st
            .receive()
            .iter()
            .filter(|m| matches!(m, MavMessage::HEARTBEAT(_)))
            .count();
    }
    let secs = start.elapsed().as_secs() as usize;
    assert!(
        heard <= secs + 2,
        "{heard} heartbeats in {secs} s for 2000 received"
    );
    assert!(heard >= 1, "the station hears the companion");
}

/// An executive that has not decided yet (e.g. still waiting for the vehicle to be ready) never has a goal
/// answered "accepted" for it: past the answer's deadline the goal is "received; verdict to follow", and the
/// verdict follows when the executive gives it.
#[test]
fn no_accepted_before_the_executive_s_verdict() {
    let (mut v, gcs) = companion_answering_within(Duration::from_millis(200));
    let mut st = Station::new(gcs);
    st.send(vec![mavtempo_vehicle::goal_client::gcs_heartbeat()]);
    let mut c = MissionClient::new((1, 191), 1500, 5);
    let mut out = Vec::new();
    assert!(c.upload(
        0,
        vec![MissionItem::waypoint(43.5615, 1.4778, 0.0)],
        0,
        &mut out
    ));
    let mut held = None;
    let (o, texts) = st.run(&mut c, out, &mut v, &mut |e| {
        if let VehicleEvent::Goals(b) = e {
            held = Some(b);
        }
    });
    assert_eq!(o, MissionOutcome::Uploaded);
    assert_eq!(
        texts,
        ["g1 received: at(g1_loc); inserting it into the plan, verdict to follow"]
    );
    held.expect("the batch reached the executive")
        .answer(vec![GoalVerdict::Accepted]);
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut later = Vec::new();
    while later.is_empty() {
        assert!(Instant::now() < deadline, "no verdict followed");
        for m in st.receive() {
            if let MavMessage::STATUSTEXT(s) = &m {
                later.extend(st.texts.push(s.id, &s.text[..]));
            }
        }
    }
    assert_eq!(later, ["g1 accepted: at(g1_loc)"]);
}
