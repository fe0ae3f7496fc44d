//! MAVLink framing: raw frames out of a byte stream or datagrams (MAVLink 1 and 2, CRC checked), signature
//! verification, and encoding of outgoing messages (MAVLink 2, signed when a key is set, or MAVLink 1 for a
//! MAVLink 1 peer). Raw bytes are kept so the `.tlog` records exactly what crossed the wire.

use mavlink::dialects::ardupilotmega::{
    MavAutopilot, MavMessage, MavModeFlag, MavState, MavType, HEARTBEAT_DATA,
};
use mavlink::{
    MAVLinkV1MessageRaw, MAVLinkV2MessageRaw, MavHeader, MavlinkVersion, Message, SigningConfig,
    SigningData,
};

const STX_V1: u8 = 0xFE;
const STX_V2: u8 = 0xFD;
const IFLAG_SIGNED: u8 = 0x01;
const SIGNATURE_LEN: usize = 13;

/// One CRC-valid frame as received.
#[derive(Debug, Clone)]
pub struct RawFrame {
    pub bytes: Vec<u8>,
    pub version: MavlinkVersion,
    pub signed: bool,
    pub system_id: u8,
    pub component_id: u8,
    pub sequence: u8,
    pub message_id: u32,
}

impl RawFrame {
    /// The payload as sent (MAVLink 2 may have trimmed its trailing zeros).
    pub fn payload(&self) -> &[u8] {
        match self.version {
            MavlinkVersion::V1 => &self.bytes[6..self.bytes.len() - 2],
            MavlinkVersion::V2 => {
                let len = usize::from(self.bytes[1]);
                &self.bytes[10..10 + len]
            }
        }
    }

    pub fn header(&self) -> MavHeader {
        MavHeader {
            system_id: u32::from(self.system_id),
            component_id: self.component_id,
            sequence: self.sequence,
        }
    }

    /// Decodes the message; `None` for messages the dialect does not know or cannot parse.
    pub fn parse(&self) -> Option<MavMessage> {
        MavMessage::parse(self.version, self.message_id, self.payload()).ok()
    }
}

/// Splits bytes into frames, resynchronising on garbage and bad CRCs.
#[derive(Debug, Default)]
pub struct FrameDecoder {
    buf: Vec<u8>,
    start: usize,
    /// Frames dropped for a bad CRC (or an unknown message id, whose CRC cannot be checked).
    pub crc_errors: u64,
}

impl FrameDecoder {
    pub fn push(&mut self, bytes: &[u8]) {
        if self.start > 0 && self.start == self.buf.len() {
            self.buf.clear();
            self.start = 0;
        } else if self.start > 4096 {
            self.buf.drain(..self.start);
            self.start = 0;
        }
        self.buf.extend_from_slice(bytes);
    }

    /// The end of a datagram: what is left is the start of no frame (MAVLink over UDP never splits a frame
    /// across datagrams), so a false start inside a corrupted frame cannot hold the next datagram's frames.
    pub fn end_datagram(&mut self) {
        self.buf.clear();
        self.start = 0;
    }

    pub fn next_frame(&mut self) -> Option<RawFrame> {
        loop {
            let data = &self.buf[self.start..];
            let Some(stx) = data.iter().position(|&b| b == STX_V1 || b == STX_V2) else {
                // No frame can start in what is left: drop it (kept, garbage without a start byte grew
                // the buffer without bound).
                self.start = self.buf.len();
                return None;
            };
            self.start += stx;
            let data = &self.buf[self.start..];
            if data.len() < 2 {
                return None;
            }
            let len = usize::from(data[1]);
            let (version, header_len) = if data[0] == STX_V1 {
                (MavlinkVersion::V1, 6)
            } else {
                (MavlinkVersion::V2, 10)
            };
            if data.len() < header_len {
                return None;
            }
            let signed = version == MavlinkVersion::V2 && data[2] & IFLAG_SIGNED != 0;
            let total = header_len + len + 2 + if signed { SIGNATURE_LEN } else { 0 };
            if data.len() < total {
                return None;
            }
            let message_id = match version {
                MavlinkVersion::V1 => u32::from(data[5]),
                MavlinkVersion::V2 => u32::from_le_bytes([data[7], data[8], data[9], 0]),
            };
            let crc_end = header_len + len;
            let crc = u16::from_le_bytes([data[crc_end], data[crc_end + 1]]);
            let extra = MavMessage::extra_crc(message_id);
            if mavlink::calculate_crc(&data[1..crc_end], extra) != crc {
                self.crc_errors += 1;
                self.start += 1;
                continue;
            }
            let (sequence, system_id, component_id) = match version {
                MavlinkVersion::V1 => (data[2], data[3], data[4]),
                MavlinkVersion::V2 => (data[4], data[5], data[6]),
            };
            let frame = RawFrame {
                bytes: data[..total].to_vec(),
                version,
                signed,
                system_id,
                component_id,
                sequence,
                message_id,
            };
            self.start += total;
            return Some(frame);
        }
    }
}

/// MAVLink 2 signing for one link: signs what we send, and (since a key is set) accepts only
/// correctly signed frames.
pub struct Signer {
    data: SigningData,
}

impl Signer {
    pub fn new(key: [u8; 32], link_id: u8) -> Self {
        Self {
            data: SigningData::from_config(SigningConfig::new(key, link_id, true, false)),
        }
    }

    /// True when the frame carries a valid signature with a fresh timestamp; MAVLink 1 and unsigned
    /// MAVLink 2 frames are rejected.
    pub fn accepts(&self, frame: &RawFrame) -> bool {
        if frame.version != MavlinkVersion::V2 || !frame.signed {
            return false;
        }
        let mut raw = MAVLinkV2MessageRaw::new();
        let n = frame.bytes.len().min(raw.as_slice().len());
        raw.as_mut_slice()[..n].copy_from_slice(&frame.bytes[..n]);
        self.data.verify_signature(&raw)
    }
}

/// Parses a signing key given as 64 hex digits. Any text is answered with a reason (the key comes from a
/// config file): characters are counted and checked as characters, never sliced as bytes.
pub fn parse_key(hex: &str) -> Result<[u8; 32], String> {
    let hex = hex.trim();
    if let Some((i, c)) = hex
        .chars()
        .enumerate()
        .find(|(_, c)| !c.is_ascii_hexdigit())
    {
        return Err(format!("not a hex digit at position {i}: `{c}`"));
    }
    // Only ASCII hex digits from here: bytes and characters are the same.
    if hex.len() != 64 {
        return Err(format!(
            "expected 64 hex digits, found {} characters",
            hex.len()
        ));
    }
    let mut key = [0u8; 32];
    for (byte, pair) in key.iter_mut().zip(hex.as_bytes().chunks(2)) {
        let digit = |b: u8| (b as char).to_digit(16).unwrap_or(0) as u8;
        *byte = (digit(pair[0]) << 4) | digit(pair[1]);
    }
    Ok(key)
}

/// Encodes outgoing messages with our identity and a running sequence number.
pub struct Encoder {
    pub system_id: u8,
    pub component_id: u8,
    sequence: u8,
    signer: Option<Signer>,
}

impl Encoder {
    pub fn new(system_id: u8, component_id: u8, signer: Option<Signer>) -> Self {
        Self {
            system_id,
            component_id,
            sequence: 0,
            signer,
        }
    }

    pub fn signer(&self) -> Option<&Signer> {
        self.signer.as_ref()
    }

    /// The wire bytes of `msg`: MAVLink 1 when asked (peer speaks 1, message fits, no signing), else 2.
    pub fn encode(&mut self, msg: &MavMessage, v1: bool) -> Vec<u8> {
        let header = MavHeader {
            system_id: u32::from(self.system_id),
            component_id: self.component_id,
            sequence: self.sequence,
        };
        self.sequence = self.sequence.wrapping_add(1);
        if v1 && self.signer.is_none() && msg.message_id() < 256 {
            let mut raw = MAVLinkV1MessageRaw::new();
            raw.serialize_message(header, msg);
            return raw.raw_bytes().to_vec();
        }
        let mut raw = MAVLinkV2MessageRaw::new();
        match &self.signer {
            Some(s) => {
                raw.serialize_message_for_signing(header, msg);
                s.data.sign_message(&mut raw);
            }
            None => raw.serialize_message(header, msg),
        }
        raw.raw_bytes().to_vec()
    }
}

/// A disarmed ArduPilot Rover's HEARTBEAT in mode `custom_mode` (4: HOLD): the autopilot's side of a
/// link, for the decoder's tests and the link bench, which run without an autopilot.
pub fn rover_heartbeat(custom_mode: u32) -> MavMessage {
    MavMessage::HEARTBEAT(HEARTBEAT_DATA {
        custom_mode,
        mavtype: MavType::MAV_TYPE_GROUND_ROVER,
        autopilot: MavAutopilot::MAV_AUTOPILOT_ARDUPILOTMEGA,
        base_mode: MavModeFlag::empty(),
        system_status: MavState::MAV_STATE_ACTIVE,
        mavlink_version: 3,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn heartbeat() -> MavMessage {
        rover_heartbeat(4)
    }

    #[test]
    fn decodes_v1_and_v2_split_across_pushes_and_skips_garbage() {
        let mut enc = Encoder::new(5, 1, None);
        let mut bytes = vec![0x00, 0xFD, 0x13];
        bytes.extend(enc.encode(&heartbeat(), true));
        bytes.extend(enc.encode(&heartbeat(), false));
        let mut dec = FrameDecoder::default();
        let mut frames = Vec::new();
        for chunk in bytes.chunks(5) {
            dec.push(chunk);
            while let Some(f) = dec.next_frame() {
                frames.push(f);
            }
        }
        assert_eq!(frames.len(), 2);
        assert_eq!(frames[0].version, MavlinkVersion::V1);
        assert_eq!(frames[1].version, MavlinkVersion::V2);
        assert_eq!(frames[1].sequence, 1);
        assert_eq!(frames[0].parse(), Some(heartbeat()));
        assert_eq!(frames[1].parse(), Some(heartbeat()));
    }

    #[test]
    fn garbage_without_a_start_byte_is_not_kept() {
        let mut dec = FrameDecoder::default();
        for _ in 0..1000 {
            dec.push(&[0x13; 1400]);
            assert!(dec.next_frame().is_none());
        }
        assert!(dec.buf.len() <= 1400, "{} bytes kept", dec.buf.len());
        dec.push(&Encoder::new(5, 1, None).encode(&heartbeat(), false));
        assert_eq!(dec.next_frame().and_then(|f| f.parse()), Some(heartbeat()));
    }

    #[test]
    fn corrupted_frame_is_dropped() {
        let mut enc = Encoder::new(5, 1, None);
        let mut bytes = enc.encode(&heartbeat(), false);
        bytes[12] ^= 0xFF;
        let mut dec = FrameDecoder::default();
        dec.push(&bytes);
        assert!(dec.next_frame().is_none());
        assert!(dec.crc_errors >= 1);
    }

    #[test]
    fn signed_frames_verify_and_others_do_not() {
        let key = [7u8; 32];
        let mut signed = Encoder::new(1, 1, Some(Signer::new(key, 0)));
        let mut plain = Encoder::new(1, 1, None);
        let mut wrong = Encoder::new(1, 1, Some(Signer::new([8u8; 32], 0)));
        let receiver = Signer::new(key, 1);
        let frame = |bytes: Vec<u8>| {
            let mut d = FrameDecoder::default();
            d.push(&bytes);
            d.next_frame()
        };
        let good = frame(signed.encode(&heartbeat(), false)).expect("frame");
        assert!(good.signed && receiver.accepts(&good));
        let unsigned = frame(plain.encode(&heartbeat(), false)).expect("frame");
        assert!(!receiver.accepts(&unsigned));
        let forged = frame(wrong.encode(&heartbeat(), false)).expect("frame");
        assert!(!receiver.accepts(&forged));
        // A replay of an accepted frame has a stale timestamp.
        assert!(!receiver.accepts(&good));
    }

    #[test]
    fn key_parse_errors_are_clear() {
        let key = parse_key(&format!("0aF1{}", "00".repeat(30))).expect("valid key");
        assert_eq!(&key[..3], &[0x0a, 0xf1, 0x00]);
        assert!(parse_key("abc").unwrap_err().contains("64 hex digits"));
        assert!(parse_key(&format!("zz{}", "00".repeat(31)))
            .unwrap_err()
            .contains("position 0: `z`"));
    }

    #[test]
    fn a_non_ascii_key_is_an_error_not_a_panic() {
        // 64 bytes, but a two-byte character across a digit-pair boundary (it used to panic on slicing).
        let text = format!("0é{}", "0".repeat(61));
        assert_eq!(text.len(), 64);
        let e = parse_key(&text).unwrap_err();
        assert!(e.contains("position 1: `é`"), "{e}");
        let text = format!("{}é", "0".repeat(62));
        assert_eq!(text.len(), 64);
        assert!(parse_key(&text).unwrap_err().contains("position 62"));
    }
}
