//! Real sockets: TCP server/client and UDP server/client. Frames of either MAVLink version are
//! read; each peer is answered in the version it last used (MAVLink 2 until it speaks).

use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::{Arc, Mutex, MutexGuard};

use mavlink::dialects::ardupilotmega::MavMessage;
use mavlink::{MavHeader, MavlinkVersion, Message};
use tokio::io::AsyncWriteExt;
use tokio::net::{TcpListener, TcpStream, UdpSocket};
use tokio::sync::mpsc;

use mavaddr::Address;

use crate::error::SimError;

pub type PeerId = u64;

/// One decoded frame from a peer.
#[derive(Debug, Clone)]
pub struct Inbound {
    pub peer: PeerId,
    pub header: MavHeader,
    pub msg: MavMessage,
}

enum Sink {
    Tcp(mpsc::Sender<Vec<u8>>),
    Udp(Arc<UdpSocket>, SocketAddr),
}

struct Peer {
    sink: Sink,
    version: MavlinkVersion,
    seq: u8,
}

/// Every connected peer, shared by the socket tasks (which add/remove peers and note their
/// MAVLink version) and the simulator core (which writes).
#[derive(Clone, Default)]
pub struct Peers(Arc<Mutex<HashMap<PeerId, Peer>>>);

impl Peers {
    fn lock(&self) -> MutexGuard<'_, HashMap<PeerId, Peer>> {
        // A panicked socket task cannot leave the map inconsistent: recover it.
        self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn add(&self, id: PeerId, sink: Sink) {
        self.lock().insert(
            id,
            Peer {
                sink,
                version: MavlinkVersion::V2,
                seq: 0,
            },
        );
    }

    fn remove(&self, id: PeerId) {
        self.lock().remove(&id);
    }

    fn note_version(&self, id: PeerId, v: MavlinkVersion) {
        if let Some(p) = self.lock().get_mut(&id) {
            p.version = v;
        }
    }

    pub fn ids(&self) -> Vec<PeerId> {
        let mut ids: Vec<PeerId> = self.lock().keys().copied().collect();
        ids.sort_unstable();
        ids
    }

    /// Queues encoded bytes without waiting: a full queue drops the frame, as a saturated radio
    /// would. Returns false if dropped.
    pub fn send_bytes(&self, peer: PeerId, bytes: Vec<u8>) -> bool {
        let mut peers = self.lock();
        match peers.get_mut(&peer) {
            Some(p) => self.send_raw_locked(p, bytes),
            None => false,
        }
    }

    /// Encodes `msg` for `peer`: its MAVLink version, its sequence numbers.
    pub fn encode(&self, peer: PeerId, system_id: u8, msg: &MavMessage) -> Option<Vec<u8>> {
        let mut peers = self.lock();
        let p = peers.get_mut(&peer)?;
        if p.version == MavlinkVersion::V1 && msg.message_id() > 255 {
            return None;
        }
        let header = MavHeader {
            system_id: u32::from(system_id),
            component_id: 1,
            sequence: p.seq,
        };
        p.seq = p.seq.wrapping_add(1);
        let mut buf = Vec::with_capacity(64);
        mavlink::write_versioned_msg(&mut buf, p.version, header, msg).ok()?;
        Some(buf)
    }

    fn send_raw_locked(&self, p: &mut Peer, bytes: Vec<u8>) -> bool {
        match &p.sink {
            Sink::Tcp(tx) => tx.try_send(bytes).is_ok(),
            Sink::Udp(sock, addr) => sock.try_send_to(&bytes, *addr).is_ok(),
        }
    }
}

/// The open transport.
pub struct Link {
    pub local_addr: SocketAddr,
    pub peers: Peers,
    tasks: Vec<tokio::task::JoinHandle<()>>,
}

impl Drop for Link {
    fn drop(&mut self) {
        for t in &self.tasks {
            t.abort();
        }
    }
}

/// Decodes a frame of either version, notes the peer's version and hands the message to the core.
/// Returns false once the core has stopped. Frames of unknown messages are skipped.
async fn forward(
    raw: &mavlink::MAVLinkMessageRaw,
    peer: PeerId,
    peers: &Peers,
    inbound: &mpsc::Sender<Inbound>,
) -> bool {
    let Ok(msg) = MavMessage::parse(raw.version(), raw.message_id(), raw.payload()) else {
        return true;
    };
    peers.note_version(peer, raw.version());
    let header = MavHeader {
        system_id: raw.system_id(),
        component_id: raw.component_id(),
        sequence: raw.sequence(),
    };
    inbound.send(Inbound { peer, header, msg }).await.is_ok()
}

impl Link {
    pub async fn open(addr: &str, inbound: mpsc::Sender<Inbound>) -> Result<Self, SimError> {
        let io = |source| SimError::Io {
            addr: addr.to_string(),
            source,
        };
        let peers = Peers::default();
        let mut tasks = Vec::new();
        let local_addr = match Address::parse(addr)? {
            Address::TcpIn(hp) => {
                let listener = TcpListener::bind(&hp).await.map_err(io)?;
                let local = listener.local_addr().map_err(io)?;
                let peers2 = peers.clone();
                tasks.push(tokio::spawn(async move {
                    let mut next_id: PeerId = 1;
                    loop {
                        match listener.accept().await {
                            Ok((stream, from)) => {
                                tracing::info!(%from, "sitl: client connected");
                                serve_tcp(stream, next_id, peers2.clone(), inbound.clone());
                                next_id += 1;
                            }
                            Err(e) => {
                                tracing::warn!("sitl: accept failed: {e}");
                                tokio::time::sleep(std::time::Duration::from_millis(50)).await;
                            }
                        }
                    }
                }));
                local
            }
            Address::TcpOut(hp) => {
                let stream = TcpStream::connect(&hp).await.map_err(io)?;
                let local = stream.local_addr().map_err(io)?;
                serve_tcp(stream, 1, peers.clone(), inbound);
                local
            }
            Address::UdpIn(hp) => {
                let sock = Arc::new(UdpSocket::bind(&hp).await.map_err(io)?);
                let local = sock.local_addr().map_err(io)?;
                tasks.push(tokio::spawn(serve_udp(sock, None, peers.clone(), inbound)));
                local
            }
            Address::UdpOut(hp) => {
                let target: SocketAddr = tokio::net::lookup_host(&hp)
                    .await
                    .map_err(io)?
                    .next()
                    .ok_or_else(|| SimError::BadAddress {
                        addr: addr.to_string(),
                        reason: "host does not resolve".into(),
                    })?;
                let bind = if target.is_ipv4() {
                    "0.0.0.0:0"
                } else {
                    "[::]:0"
                };
                let sock = Arc::new(UdpSocket::bind(bind).await.map_err(io)?);
                let local = sock.local_addr().map_err(io)?;
                tasks.push(tokio::spawn(serve_udp(
                    sock,
                    Some(target),
                    peers.clone(),
                    inbound,
                )));
                local
            }
            Address::Serial { .. } => {
                return Err(SimError::BadAddress {
                    addr: addr.to_string(),
                    reason: "a serial port is not simulated".into(),
                })
            }
        };
        Ok(Self {
            local_addr,
            peers,
            tasks,
        })
    }
}

fn serve_tcp(stream: TcpStream, id: PeerId, peers: Peers, inbound: mpsc::Sender<Inbound>) {
    let _ = stream.set_nodelay(true);
    let (rd, mut wr) = stream.into_split();
    let (tx, mut rx) = mpsc::channel::<Vec<u8>>(4096);
    peers.add(id, Sink::Tcp(tx));
    tokio::spawn(async move {
        while let Some(bytes) = rx.recv().await {
            if wr.write_all(&bytes).await.is_err() {
                break;
            }
        }
    });
    tokio::spawn(async move {
        let mut reader = mavlink::AsyncMavlinkReader::new(rd);
        loop {
            match reader.read_any_raw_message::<MavMessage>().await {
                Ok(raw) => {
                    if !forward(&raw, id, &peers, &inbound).await {
                        break;
                    }
                }
                Err(mavlink::error::MessageReadError::Parse(_)) => continue,
                Err(mavlink::error::MessageReadError::Io(_)) => break,
            }
        }
        tracing::info!(peer = id, "sitl: client disconnected");
        peers.remove(id);
    });
}

async fn serve_udp(
    sock: Arc<UdpSocket>,
    fixed: Option<SocketAddr>,
    peers: Peers,
    inbound: mpsc::Sender<Inbound>,
) {
    let mut ids: HashMap<SocketAddr, PeerId> = HashMap::new();
    if let Some(target) = fixed {
        ids.insert(target, 1);
        peers.add(1, Sink::Udp(sock.clone(), target));
    }
    let mut buf = vec![0u8; 65_536];
    loop {
        let (n, from) = match sock.recv_from(&mut buf).await {
            Ok(x) => x,
            // ICMP port unreachable and the like: keep serving.
            Err(_) => continue,
        };
        let next = ids.len() as PeerId + 1;
        let id = *ids.entry(from).or_insert_with(|| {
            peers.add(next, Sink::Udp(sock.clone(), from));
            next
        });
        let mut reader = mavlink::MavlinkReader::new(&buf[..n]);
        loop {
            match reader.read_any_raw_message::<MavMessage>() {
                Ok(raw) => {
                    if !forward(&raw, id, &peers, &inbound).await {
                        return;
                    }
                }
                Err(mavlink::error::MessageReadError::Parse(_)) => continue,
                Err(_) => break,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn only_sockets_open() {
        let (tx, _rx) = mpsc::channel(1);
        let serial = Link::open("serial:/dev/ttyS0:57600", tx.clone()).await;
        assert!(matches!(serial, Err(SimError::BadAddress { .. })));
        let no_port = Link::open("udpin:localhost", tx).await;
        assert!(matches!(no_port, Err(SimError::Address(_))));
    }
}
