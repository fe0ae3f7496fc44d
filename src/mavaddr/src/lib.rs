//! MAVLink link addresses as mavproxy and ArduPilot write them: `udpin:HOST:PORT`, `udpout:HOST:PORT`,
//! `tcpin:HOST:PORT`, `tcpout:HOST:PORT`, `serial:PORT:BAUD`. One parser for the vehicle layer and the SITL,
//! so that both accept and refuse the same strings with the same reasons.

use thiserror::Error;

/// A parsed address; the `HOST:PORT` part is kept as written (it is resolved when bound or connected).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Address {
    TcpIn(String),
    TcpOut(String),
    UdpIn(String),
    UdpOut(String),
    Serial { port: String, baud: u32 },
}

/// Why a string is no address; each message names the string.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum AddressError {
    #[error(
        "`{addr}`: expected KIND:ADDRESS with KIND one of udpin, udpout, tcpin, tcpout, serial"
    )]
    NoKind { addr: String },
    #[error("`{addr}`: expected HOST:PORT after `{kind}:`")]
    NoPort { addr: String, kind: String },
    #[error("`{addr}`: `{port}` is not a port number")]
    BadPort { addr: String, port: String },
    #[error("`{addr}`: expected serial:PORT:BAUD")]
    NoBaud { addr: String },
    #[error("`{addr}`: `{baud}` is not a baud rate")]
    BadBaud { addr: String, baud: String },
    #[error("`{addr}`: unknown link kind `{kind}` (udpin, udpout, tcpin, tcpout, serial)")]
    UnknownKind { addr: String, kind: String },
}

impl Address {
    pub fn parse(s: &str) -> Result<Self, AddressError> {
        let addr = || s.to_string();
        let (kind, rest) = s
            .split_once(':')
            .ok_or_else(|| AddressError::NoKind { addr: addr() })?;
        let host_port = |r: &str| -> Result<String, AddressError> {
            let (_, port) = r.rsplit_once(':').ok_or_else(|| AddressError::NoPort {
                addr: addr(),
                kind: kind.to_string(),
            })?;
            port.parse::<u16>().map_err(|_| AddressError::BadPort {
                addr: addr(),
                port: port.to_string(),
            })?;
            Ok(r.to_string())
        };
        match kind {
            "tcpin" => Ok(Address::TcpIn(host_port(rest)?)),
            "tcpout" => Ok(Address::TcpOut(host_port(rest)?)),
            "udpin" => Ok(Address::UdpIn(host_port(rest)?)),
            "udpout" => Ok(Address::UdpOut(host_port(rest)?)),
            "serial" => {
                let (port, baud) = rest
                    .rsplit_once(':')
                    .ok_or_else(|| AddressError::NoBaud { addr: addr() })?;
                let baud = baud.parse().map_err(|_| AddressError::BadBaud {
                    addr: addr(),
                    baud: baud.to_string(),
                })?;
                Ok(Address::Serial {
                    port: port.to_string(),
                    baud,
                })
            }
            other => Err(AddressError::UnknownKind {
                addr: addr(),
                kind: other.to_string(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_parses() {
        assert_eq!(
            Address::parse("tcpin:127.0.0.1:5760"),
            Ok(Address::TcpIn("127.0.0.1:5760".into()))
        );
        assert_eq!(
            Address::parse("udpout:[::1]:14550"),
            Ok(Address::UdpOut("[::1]:14550".into()))
        );
        assert_eq!(
            Address::parse("serial:/dev/ttyUSB0:57600"),
            Ok(Address::Serial {
                port: "/dev/ttyUSB0".into(),
                baud: 57600
            })
        );
    }

    /// Whether an error is the refusal expected.
    type Reason = fn(&AddressError) -> bool;

    #[test]
    fn each_refusal_says_why() {
        let refusals: [(&str, Reason); 5] = [
            ("localhost", |e| matches!(e, AddressError::NoKind { .. })),
            ("udpin:localhost", |e| {
                matches!(e, AddressError::NoPort { .. })
            }),
            ("tcpout:host:99999", |e| {
                matches!(e, AddressError::BadPort { .. })
            }),
            ("serial:/dev/ttyS0", |e| {
                matches!(e, AddressError::NoBaud { .. })
            }),
            ("serial:/dev/ttyS0:fast", |e| {
                matches!(e, AddressError::BadBaud { .. })
            }),
        ];
        for (addr, why) in refusals {
            let e = Address::parse(addr).unwrap_err();
            assert!(why(&e), "`{addr}` refused for the wrong reason: {e}");
            assert!(e.to_string().contains(addr), "{e} names `{addr}`");
        }
        let e = Address::parse("ws:host:1").unwrap_err();
        assert_eq!(
            e.to_string(),
            "`ws:host:1`: unknown link kind `ws` (udpin, udpout, tcpin, tcpout, serial)"
        );
    }
}
