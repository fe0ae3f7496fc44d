//! The peers of one transport. A stream (TCP, serial) has one; a UDP socket has as many as send to it, and
//! each gets its own frame decoder: garbage from one sender (a false frame start waiting for bytes) never
//! holds back another sender's frames, and each datagram is decoded on its own (a false start inside a
//! corrupted frame never holds the next datagram's frames). Replies go to the peer they answer (by the MAVLink system and
//! component heard from each address), broadcasts to every peer that has sent a valid frame: a sender of
//! garbage only is sent nothing.

use std::net::SocketAddr;

use mavlink::dialects::ardupilotmega::MavMessage;
use mavlink::{MavlinkVersion, Message};

use super::frame::{FrameDecoder, RawFrame};

/// UDP peers remembered at most: past it, the one heard from least recently is forgotten (one that never
/// sent a valid frame first), so a flood from many addresses costs bounded memory.
pub const MAX_UDP_PEERS: usize = 64;

/// Where one encoded message goes: a UDP peer (`Some`) or the stream (`None`), and whether as MAVLink 1.
pub type Destination = (Option<SocketAddr>, bool);

struct UdpPeer {
    addr: SocketAddr,
    decoder: FrameDecoder,
    /// It sent a frame that passed the checks (CRC, signing): only such peers are sent to.
    valid: bool,
    /// The remote of a `udpout:` address: sent to before it is heard from, never forgotten.
    fixed: bool,
    v1: bool,
    /// (system, component) pairs heard from this address.
    ids: Vec<(u8, u8)>,
    /// When it was last heard from (a counter, not a clock).
    heard: u64,
}

impl UdpPeer {
    fn new(addr: SocketAddr) -> Self {
        UdpPeer {
            addr,
            decoder: FrameDecoder::default(),
            valid: false,
            fixed: false,
            v1: false,
            ids: Vec::new(),
            heard: 0,
        }
    }

    fn serves(&self, system: u8, component: u8) -> bool {
        self.ids
            .iter()
            .any(|&(s, c)| s == system && (component == 0 || c == component))
    }
}

/// The peers of one opened endpoint.
#[derive(Default)]
pub struct Peers {
    stream: FrameDecoder,
    stream_v1: bool,
    udp: Vec<UdpPeer>,
    clock: u64,
}

impl Peers {
    /// `fixed`: the remote of a `udpout:` address, sent to before it is heard from.
    pub fn new(fixed: Option<SocketAddr>) -> Self {
        let mut p = Peers::default();
        if let Some(addr) = fixed {
            let mut peer = UdpPeer::new(addr);
            peer.valid = true;
            peer.fixed = true;
            p.udp.push(peer);
        }
        p
    }

    /// Decodes bytes from `from` (`None`: the stream) with that sender's own decoder: the frames, and how
    /// many corrupted frames were dropped on the way.
    pub fn decode(&mut self, from: Option<SocketAddr>, bytes: &[u8]) -> (Vec<RawFrame>, u64) {
        let decoder = match from {
            None => &mut self.stream,
            Some(addr) => {
                self.clock += 1;
                let i = self.udp_index(addr);
                self.udp[i].heard = self.clock;
                &mut self.udp[i].decoder
            }
        };
        let before = decoder.crc_errors;
        decoder.push(bytes);
        let mut frames = Vec::new();
        while let Some(f) = decoder.next_frame() {
            frames.push(f);
        }
        if from.is_some() {
            decoder.end_datagram();
        }
        (frames, decoder.crc_errors - before)
    }

    /// A frame from `from` passed the checks: that sender is a peer to answer, as the system and component
    /// the frame carries, in its MAVLink version.
    pub fn heard(&mut self, from: Option<SocketAddr>, frame: &RawFrame) {
        let v1 = frame.version == MavlinkVersion::V1;
        let Some(addr) = from else {
            self.stream_v1 = v1;
            return;
        };
        let i = self.udp_index(addr);
        let p = &mut self.udp[i];
        p.valid = true;
        p.v1 = v1;
        let id = (frame.system_id, frame.component_id);
        if !p.ids.contains(&id) {
            p.ids.push(id);
        }
    }

    /// Where `msg` goes. On a stream: the stream. On UDP: a message for one system (and component) to the
    /// peers it was heard from, or to every valid peer while none is known; anything else to every valid
    /// peer. Before any peer is known (a `udpin:` nobody has written to), nowhere.
    pub fn destinations(&self, msg: &MavMessage, datagram: bool) -> Vec<Destination> {
        if !datagram {
            return vec![(None, self.stream_v1)];
        }
        let valid = self.udp.iter().filter(|p| p.valid);
        let target = msg
            .target_system_id()
            .filter(|&s| s != 0)
            .map(|s| (s, msg.target_component_id().unwrap_or(0)));
        let addressed: Vec<Destination> = match target {
            Some((s, c)) => valid
                .clone()
                .filter(|p| p.serves(s, c))
                .map(|p| (Some(p.addr), p.v1))
                .collect(),
            None => Vec::new(),
        };
        if !addressed.is_empty() {
            return addressed;
        }
        valid.map(|p| (Some(p.addr), p.v1)).collect()
    }

    /// How many UDP senders are remembered.
    pub fn udp_count(&self) -> usize {
        self.udp.len()
    }

    /// The index of `addr`'s entry, made (and room made for it) when new.
    fn udp_index(&mut self, addr: SocketAddr) -> usize {
        if let Some(i) = self.udp.iter().position(|p| p.addr == addr) {
            return i;
        }
        if self.udp.len() >= MAX_UDP_PEERS {
            // Forget the stalest non-fixed peer, one that never sent a valid frame first.
            let victim = self
                .udp
                .iter()
                .enumerate()
                .filter(|(_, p)| !p.fixed)
                .min_by_key(|(_, p)| (p.valid, p.heard))
                .map(|(i, _)| i);
            if let Some(i) = victim {
                self.udp.swap_remove(i);
            }
        }
        let mut peer = UdpPeer::new(addr);
        peer.heard = self.clock;
        self.udp.push(peer);
        self.udp.len() - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Encoder;
    use mavlink::dialects::ardupilotmega::{MavMissionResult, MavMissionType, MISSION_ACK_DATA};

    fn heartbeat() -> MavMessage {
        crate::goal_client::gcs_heartbeat()
    }

    fn ack_to(system: u8) -> MavMessage {
        MavMessage::MISSION_ACK(MISSION_ACK_DATA {
            target_system: system,
            target_component: 190,
            mavtype: MavMissionResult::MAV_MISSION_ACCEPTED,
            mission_type: MavMissionType::MAV_MISSION_TYPE_MISSION,
            opaque_id: 0,
        })
    }

    fn addr(port: u16) -> Option<SocketAddr> {
        Some(SocketAddr::from(([127, 0, 0, 1], port)))
    }

    /// A heard frame from `from` as system `system`.
    fn hear(p: &mut Peers, from: Option<SocketAddr>, system: u8) {
        let bytes = Encoder::new(system, 190, None).encode(&heartbeat(), false);
        let (frames, _) = p.decode(from, &bytes);
        for f in &frames {
            p.heard(from, f);
        }
        assert_eq!(frames.len(), 1);
    }

    #[test]
    fn a_partial_frame_from_one_sender_does_not_hold_another_s_frames() {
        let mut p = Peers::new(None);
        // A false frame start announcing 255 bytes, from sender 1.
        let (frames, _) = p.decode(addr(1), &[0x00, 0xFD, 0xFF, 0x00, 0x00]);
        assert!(frames.is_empty());
        let bytes = Encoder::new(255, 190, None).encode(&heartbeat(), false);
        let (frames, _) = p.decode(addr(2), &bytes);
        assert_eq!(frames.len(), 1, "sender 2's frame is decoded at once");
    }

    /// A corrupted frame holding a false start (0xFD announcing 255 bytes) in its payload: the next datagrams'
    /// frames are decoded at once, none swallowed (they used to wait for the false frame's bytes).
    #[test]
    fn after_a_crc_error_the_next_datagrams_are_decoded_at_once() {
        let mut p = Peers::new(None);
        let mut bad = Encoder::new(255, 190, None).encode(&heartbeat(), false);
        let n = bad.len();
        bad[n - 6] = 0xFD;
        bad[n - 5] = 0xFF;
        let (frames, crc) = p.decode(addr(1), &bad);
        assert!(frames.is_empty());
        assert_eq!(crc, 1);
        for k in 0..5 {
            let good = Encoder::new(255, 190, None).encode(&heartbeat(), false);
            let (frames, _) = p.decode(addr(1), &good);
            assert_eq!(frames.len(), 1, "retransmission {k} decoded at once");
        }
    }

    #[test]
    fn replies_go_to_the_peer_they_answer_and_broadcasts_to_valid_peers_only() {
        let mut p = Peers::new(None);
        assert!(p.destinations(&heartbeat(), true).is_empty());
        hear(&mut p, addr(1), 255);
        hear(&mut p, addr(2), 42);
        let _ = p.decode(addr(3), &[0x13; 100]); // garbage only
        assert_eq!(p.destinations(&ack_to(42), true), vec![(addr(2), false)]);
        assert_eq!(p.destinations(&ack_to(255), true), vec![(addr(1), false)]);
        let mut all = p.destinations(&heartbeat(), true);
        all.sort();
        assert_eq!(all, vec![(addr(1), false), (addr(2), false)]);
        // A system nobody spoke as: every valid peer.
        assert_eq!(p.destinations(&ack_to(7), true).len(), 2);
        assert_eq!(p.destinations(&heartbeat(), false), vec![(None, false)]);
    }

    #[test]
    fn a_flood_from_many_addresses_is_bounded_and_keeps_the_valid_peers() {
        let mut p = Peers::new(addr(9));
        hear(&mut p, addr(1), 255);
        for port in 100..1100 {
            let _ = p.decode(addr(port), &[0xFD, 0xFF, 0x01]);
        }
        assert_eq!(p.udp_count(), MAX_UDP_PEERS);
        let mut all = p.destinations(&heartbeat(), true);
        all.sort();
        assert_eq!(all, vec![(addr(1), false), (addr(9), false)]);
    }
}
