//! Transports for `udpin:`, `udpout:`, `tcpin:`, `tcpout:` and `serial:PORT:BAUD` addresses, as byte pipes (the
//! frame layer is ours, so the `.tlog` sees exact bytes and signing is checked in one place). A `tcpin` keeps
//! its listener across reconnections. Over UDP, [`Endpoint::recv_from`] / [`Endpoint::send_to`] name the
//! sender and the receiver (the link keeps one decoder per sender, see `super::peers`); the simple
//! [`Endpoint::recv`] / [`Endpoint::send`] of one-peer clients answer the last sender.

use std::io::{self, Read, Write};
use std::net::SocketAddr;
use std::sync::Arc;

use tokio::net::{TcpListener, TcpStream, UdpSocket};
use tokio::sync::mpsc;

pub use mavaddr::{Address, AddressError};

/// An address made ready to (re)connect: listeners and UDP sockets are bound once.
pub struct Transport {
    address: Address,
    listener: Option<TcpListener>,
    udp: Option<Arc<UdpSocket>>,
    udp_peer: Option<SocketAddr>,
    /// One connection already accepted (a ground station on a `tcpin:` port): opened once, never again.
    accepted: Option<TcpStream>,
    one_shot: bool,
}

impl Transport {
    /// Binds what must be bound (tcpin, udpin, udpout); connecting happens in [`Transport::open`].
    pub async fn bind(address: Address) -> io::Result<Self> {
        let mut t = Self {
            address: address.clone(),
            listener: None,
            udp: None,
            udp_peer: None,
            accepted: None,
            one_shot: false,
        };
        match &address {
            Address::TcpIn(a) => t.listener = Some(TcpListener::bind(a).await?),
            Address::UdpIn(a) => t.udp = Some(Arc::new(UdpSocket::bind(a).await?)),
            Address::UdpOut(a) => {
                let peer = tokio::net::lookup_host(a).await?.next().ok_or_else(|| {
                    io::Error::new(
                        io::ErrorKind::AddrNotAvailable,
                        format!("cannot resolve {a}"),
                    )
                })?;
                let local = if peer.is_ipv4() {
                    "0.0.0.0:0"
                } else {
                    "[::]:0"
                };
                t.udp = Some(Arc::new(UdpSocket::bind(local).await?));
                t.udp_peer = Some(peer);
            }
            _ => {}
        }
        Ok(t)
    }

    /// The bound local address (tcpin / udpin / udpout), e.g. to learn a port-0 choice.
    pub fn local_addr(&self) -> Option<SocketAddr> {
        if let Some(l) = &self.listener {
            return l.local_addr().ok();
        }
        self.udp.as_ref().and_then(|u| u.local_addr().ok())
    }

    pub fn is_datagram(&self) -> bool {
        self.udp.is_some()
    }

    /// A `tcpin:` transport: connections are accepted from its listener.
    pub fn is_listener(&self) -> bool {
        self.listener.is_some()
    }

    /// The next connection on a `tcpin:` listener.
    pub async fn accept(&mut self) -> io::Result<TcpStream> {
        let l = self
            .listener
            .as_ref()
            .ok_or_else(|| io::Error::other("not a listener"))?;
        let (s, from) = l.accept().await?;
        tracing::info!(%from, "tcp peer connected");
        s.set_nodelay(true)?;
        Ok(s)
    }

    /// A transport for one accepted connection (each ground station on a `tcpin:` port is served on its
    /// own): [`Transport::open`] hands it out once; once it closes, it is over ([`Transport::is_one_shot`]).
    pub fn accepted(address: Address, stream: TcpStream) -> Self {
        Self {
            address,
            listener: None,
            udp: None,
            udp_peer: None,
            accepted: Some(stream),
            one_shot: true,
        }
    }

    pub fn is_one_shot(&self) -> bool {
        self.one_shot
    }

    pub fn address(&self) -> &Address {
        &self.address
    }

    /// Connects (tcpout), accepts (tcpin), or hands out the bound socket (udp), or opens the serial port.
    pub async fn open(&mut self) -> io::Result<Endpoint> {
        if self.one_shot {
            return self
                .accepted
                .take()
                .map(Endpoint::Tcp)
                .ok_or_else(|| io::Error::other("connection closed"));
        }
        match &self.address {
            Address::TcpIn(_) => Ok(Endpoint::Tcp(self.accept().await?)),
            Address::TcpOut(a) => {
                let s = TcpStream::connect(a).await?;
                s.set_nodelay(true)?;
                Ok(Endpoint::Tcp(s))
            }
            Address::UdpIn(_) | Address::UdpOut(_) => {
                let socket = self
                    .udp
                    .clone()
                    .ok_or_else(|| io::Error::other("socket gone"))?;
                Ok(Endpoint::Udp {
                    socket,
                    peer: self.udp_peer,
                })
            }
            Address::Serial { port, baud } => open_serial(port, *baud),
        }
    }
}

fn open_serial(port: &str, baud: u32) -> io::Result<Endpoint> {
    let writer = serialport::new(port, baud)
        .timeout(std::time::Duration::from_millis(100))
        .open()
        .map_err(|e| io::Error::other(format!("serial {port}: {e}")))?;
    let mut reader = writer
        .try_clone()
        .map_err(|e| io::Error::other(format!("serial {port}: {e}")))?;
    let (tx, rx) = mpsc::channel(64);
    // serialport is blocking: a reader thread feeds the async side.
    std::thread::spawn(move || {
        let mut buf = [0u8; 1024];
        loop {
            match reader.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => {
                    if tx.blocking_send(Ok(buf[..n].to_vec())).is_err() {
                        break;
                    }
                }
                Err(e) if e.kind() == io::ErrorKind::TimedOut => {}
                Err(e) => {
                    let _ = tx.blocking_send(Err(e));
                    break;
                }
            }
        }
    });
    Ok(Endpoint::Serial { writer, rx })
}

pub enum Endpoint {
    Tcp(TcpStream),
    Udp {
        socket: Arc<UdpSocket>,
        peer: Option<SocketAddr>,
    },
    Serial {
        writer: Box<dyn serialport::SerialPort>,
        rx: mpsc::Receiver<io::Result<Vec<u8>>>,
    },
}

impl Endpoint {
    /// Reads some bytes into `buf`; `Ok(0)` means the peer closed (TCP, serial).
    pub async fn recv(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        use tokio::io::AsyncReadExt;
        match self {
            Endpoint::Tcp(s) => s.read(buf).await,
            Endpoint::Udp { socket, peer } => loop {
                let (n, from) = socket.recv_from(buf).await?;
                // udpin answers the last sender.
                *peer = Some(from);
                // An empty datagram is no close: UDP has none.
                if n > 0 {
                    break Ok(n);
                }
            },
            Endpoint::Serial { rx, .. } => match rx.recv().await {
                Some(Ok(bytes)) => {
                    let n = bytes.len().min(buf.len());
                    buf[..n].copy_from_slice(&bytes[..n]);
                    Ok(n)
                }
                Some(Err(e)) => Err(e),
                None => Ok(0),
            },
        }
    }

    /// Reads some bytes into `buf` and who sent them (UDP; `None` on a stream). `Ok((0, _))` means the
    /// peer closed (TCP, serial).
    pub async fn recv_from(&mut self, buf: &mut [u8]) -> io::Result<(usize, Option<SocketAddr>)> {
        match self {
            Endpoint::Udp { socket, .. } => loop {
                let (n, from) = socket.recv_from(buf).await?;
                // An empty datagram is no close: UDP has none.
                if n > 0 {
                    break Ok((n, Some(from)));
                }
            },
            _ => Ok((self.recv(buf).await?, None)),
        }
    }

    /// The remote a `udpout:` address names (sent to before it is heard from); `None` otherwise.
    pub fn fixed_peer(&self) -> Option<SocketAddr> {
        match self {
            Endpoint::Udp { peer, .. } => *peer,
            _ => None,
        }
    }

    /// Sends one frame to `to` over UDP; on a stream `to` is `None` and the frame goes down the stream.
    pub async fn send_to(&mut self, bytes: &[u8], to: Option<SocketAddr>) -> io::Result<()> {
        match (&*self, to) {
            (Endpoint::Udp { socket, .. }, Some(addr)) => {
                socket.send_to(bytes, addr).await.map(|_| ())
            }
            _ => self.send(bytes).await,
        }
    }

    /// Sends one frame; UDP before any peer is known drops it (nobody to send to yet).
    pub async fn send(&mut self, bytes: &[u8]) -> io::Result<()> {
        use tokio::io::AsyncWriteExt;
        match self {
            Endpoint::Tcp(s) => s.write_all(bytes).await,
            Endpoint::Udp { socket, peer } => {
                if let Some(p) = peer {
                    socket.send_to(bytes, *p).await?;
                }
                Ok(())
            }
            Endpoint::Serial { writer, .. } => writer.write_all(bytes),
        }
    }
}
