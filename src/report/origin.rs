//! Who may post to the live page: a request whose `Host` names the page itself (a loopback name or the
//! address it is bound to), and whose `Origin`, when a browser sends one, is that page too. A cross-origin
//! POST (a form on another site) and a rebound DNS name (`Host: evil.example` resolving to 127.0.0.1) are
//! refused: the goal form uploads to the vehicle.

use std::net::{IpAddr, SocketAddr};

/// Why a request was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum OriginError {
    #[error("missing Host header")]
    NoHost,
    #[error("Host {0:?} is not this page (loopback or {1})")]
    ForeignHost(String, SocketAddr),
    #[error("cross-origin request from {0:?} refused")]
    ForeignOrigin(String),
}

/// The host part of `authority` (`name:port`, `[v6]:port`, or a bare name), lower-cased.
fn host_of(authority: &str) -> String {
    let a = authority.trim();
    let host = if let Some(rest) = a.strip_prefix('[') {
        rest.split(']').next().unwrap_or("")
    } else {
        a.rsplit_once(':').map_or(a, |(h, _)| h)
    };
    host.to_ascii_lowercase()
}

/// Whether `host` names the page bound at `bound`: a loopback name or address, or `bound`'s own address.
fn is_own(host: &str, bound: SocketAddr) -> bool {
    if host == "localhost" {
        return true;
    }
    match host.parse::<IpAddr>() {
        Ok(ip) => ip.is_loopback() || (!bound.ip().is_unspecified() && ip == bound.ip()),
        Err(_) => false,
    }
}

/// Checks the `Host` and `Origin` headers of a request to the page bound at `bound`.
pub fn check(
    host: Option<&str>,
    origin: Option<&str>,
    bound: SocketAddr,
) -> Result<(), OriginError> {
    let host = host.ok_or(OriginError::NoHost)?;
    if !is_own(&host_of(host), bound) {
        return Err(OriginError::ForeignHost(host.into(), bound));
    }
    if let Some(o) = origin {
        let authority = o
            .strip_prefix("http://")
            .or_else(|| o.strip_prefix("https://"))
            .ok_or_else(|| OriginError::ForeignOrigin(o.into()))?;
        if !is_own(&host_of(authority), bound) {
            return Err(OriginError::ForeignOrigin(o.into()));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn local() -> SocketAddr {
        SocketAddr::from(([127, 0, 0, 1], 8080))
    }

    #[test]
    fn the_page_itself_may_post() {
        for host in [
            "127.0.0.1:8080",
            "localhost:8080",
            "LOCALHOST",
            "[::1]:8080",
        ] {
            assert_eq!(check(Some(host), None, local()), Ok(()), "{host}");
        }
        assert_eq!(
            check(
                Some("127.0.0.1:8080"),
                Some("http://127.0.0.1:8080"),
                local()
            ),
            Ok(())
        );
        let lan = SocketAddr::from(([192, 168, 1, 5], 8080));
        assert_eq!(
            check(
                Some("192.168.1.5:8080"),
                Some("http://192.168.1.5:8080"),
                lan
            ),
            Ok(())
        );
    }

    #[test]
    fn foreign_hosts_and_origins_are_refused() {
        assert!(matches!(
            check(Some("evil.example:8080"), None, local()),
            Err(OriginError::ForeignHost(..))
        ));
        assert!(matches!(
            check(Some("127.0.0.1:8080"), Some("http://evil.example"), local()),
            Err(OriginError::ForeignOrigin(_))
        ));
        assert!(matches!(
            check(Some("127.0.0.1:8080"), Some("null"), local()),
            Err(OriginError::ForeignOrigin(_))
        ));
        assert_eq!(check(None, None, local()), Err(OriginError::NoHost));
        // Bound to every interface: only loopback names count as the page itself.
        let any = SocketAddr::from(([0, 0, 0, 0], 8080));
        assert!(check(Some("0.0.0.0:8080"), None, any).is_err());
    }
}
