//! Endpoint strings as operators know them from mavlink-router and the `mavlink` crate:
//! `udpin:ADDR:PORT` (listen; peers are learned from what arrives), `udpout:ADDR:PORT` (send to a
//! fixed peer from an ephemeral port), `tcpin:ADDR:PORT` (accept clients), `tcpout:ADDR:PORT`
//! (connect), `serial:DEVICE:BAUD`. Also accepted: the `scheme://` form used by MAVSDK.

use std::fmt;
use std::net::{SocketAddr, ToSocketAddrs};

/// One side's connection.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Endpoint {
    /// Listen on a UDP address; peers are learned from what arrives.
    UdpIn(SocketAddr),
    /// Send to a fixed UDP peer from an ephemeral port.
    UdpOut(SocketAddr),
    /// Accept TCP clients.
    TcpIn(SocketAddr),
    /// Connect to a TCP server.
    TcpOut(SocketAddr),
    /// A serial port at a baud rate.
    Serial {
        /// Device path, e.g. `/dev/ttyUSB0`.
        device: String,
        /// Baud rate, one of [`SUPPORTED_BAUDS`].
        baud: u32,
    },
}

impl fmt::Display for Endpoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Endpoint::UdpIn(a) => write!(f, "udpin:{a}"),
            Endpoint::UdpOut(a) => write!(f, "udpout:{a}"),
            Endpoint::TcpIn(a) => write!(f, "tcpin:{a}"),
            Endpoint::TcpOut(a) => write!(f, "tcpout:{a}"),
            Endpoint::Serial { device, baud } => write!(f, "serial:{device}:{baud}"),
        }
    }
}

/// Baud rates the serial setup can set directly (termios on Linux).
pub const SUPPORTED_BAUDS: &[u32] = &[
    9600, 19200, 38400, 57600, 115200, 230400, 460800, 500000, 576000, 921600, 1000000, 1500000,
    2000000,
];

/// Why an endpoint string was not understood.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum EndpointError {
    /// No `SCHEME:` prefix.
    #[error("endpoint `{spec}`: expected SCHEME:ADDRESS, e.g. udpin:0.0.0.0:14550")]
    #[diagnostic(code(mav::E001))]
    NoScheme {
        /// What was given.
        spec: String,
    },
    /// A scheme other than udpin, udpout, tcpin, tcpout, serial.
    #[error("endpoint `{spec}`: unknown scheme `{scheme}` (udpin, udpout, tcpin, tcpout, serial)")]
    #[diagnostic(code(mav::E002))]
    UnknownScheme {
        /// What was given.
        spec: String,
        /// The scheme.
        scheme: String,
    },
    /// An address that does not resolve.
    #[error("endpoint `{spec}`: bad address `{addr}` ({reason})")]
    #[diagnostic(code(mav::E003))]
    BadAddress {
        /// What was given.
        spec: String,
        /// The address part.
        addr: String,
        /// Why it does not resolve.
        reason: String,
    },
    /// A serial endpoint that is not `serial:DEVICE:BAUD` with a supported baud rate.
    #[error("endpoint `{spec}`: {problem}")]
    #[diagnostic(code(mav::E004), help("serial:DEVICE:BAUD with BAUD one of {SUPPORTED_BAUDS:?}"))]
    BadSerial {
        /// What was given.
        spec: String,
        /// What is wrong with it.
        problem: String,
    },
}

impl std::str::FromStr for Endpoint {
    type Err = EndpointError;

    fn from_str(s: &str) -> Result<Self, EndpointError> {
        let spec = || s.to_string();
        let (scheme, rest) = s
            .split_once("://")
            .or_else(|| s.split_once(':'))
            .ok_or_else(|| EndpointError::NoScheme { spec: spec() })?;
        let addr = |rest: &str| -> Result<SocketAddr, EndpointError> {
            let bad = |reason: String| EndpointError::BadAddress {
                spec: spec(),
                addr: rest.to_string(),
                reason,
            };
            rest.to_socket_addrs()
                .map_err(|e| bad(e.to_string()))?
                .next()
                .ok_or_else(|| bad("resolves to nothing".into()))
        };
        let serial = |problem: String| EndpointError::BadSerial { spec: spec(), problem };
        match scheme {
            "udpin" | "udp" => Ok(Endpoint::UdpIn(addr(rest)?)),
            "udpout" => Ok(Endpoint::UdpOut(addr(rest)?)),
            "tcpin" => Ok(Endpoint::TcpIn(addr(rest)?)),
            "tcpout" | "tcp" => Ok(Endpoint::TcpOut(addr(rest)?)),
            "serial" => {
                let (device, baud) = rest
                    .rsplit_once(':')
                    .ok_or_else(|| serial("expected serial:DEVICE:BAUD".into()))?;
                let baud: u32 =
                    baud.parse().map_err(|_| serial(format!("baud `{baud}` is not a number")))?;
                if !SUPPORTED_BAUDS.contains(&baud) {
                    return Err(serial(format!("baud {baud} not supported")));
                }
                if device.is_empty() {
                    return Err(serial("empty device path".into()));
                }
                Ok(Endpoint::Serial { device: device.to_string(), baud })
            }
            other => Err(EndpointError::UnknownScheme { spec: spec(), scheme: other.to_string() }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_router_style_strings() {
        assert_eq!(
            "udpin:0.0.0.0:14550".parse::<Endpoint>().unwrap(),
            Endpoint::UdpIn("0.0.0.0:14550".parse().unwrap())
        );
        assert_eq!(
            "udpout:127.0.0.1:14555".parse::<Endpoint>().unwrap(),
            Endpoint::UdpOut("127.0.0.1:14555".parse().unwrap())
        );
        assert_eq!(
            "tcpout://127.0.0.1:5760".parse::<Endpoint>().unwrap(),
            Endpoint::TcpOut("127.0.0.1:5760".parse().unwrap())
        );
        assert_eq!(
            "serial:/dev/ttyUSB0:57600".parse::<Endpoint>().unwrap(),
            Endpoint::Serial { device: "/dev/ttyUSB0".into(), baud: 57600 }
        );
        assert_eq!(
            "udpin:0.0.0.0:14550".parse::<Endpoint>().unwrap().to_string(),
            "udpin:0.0.0.0:14550"
        );
    }

    #[test]
    fn rejects_with_reason() {
        let e = "bogus:1.2.3.4:5".parse::<Endpoint>().unwrap_err().to_string();
        assert!(e.contains("unknown scheme"), "{e}");
        let e = "udpin:nohost".parse::<Endpoint>().unwrap_err().to_string();
        assert!(e.contains("bad address"), "{e}");
        let e = "serial:/dev/ttyS0:1234".parse::<Endpoint>().unwrap_err().to_string();
        assert!(e.contains("not supported"), "{e}");
        assert!("14550".parse::<Endpoint>().is_err());
    }
}
