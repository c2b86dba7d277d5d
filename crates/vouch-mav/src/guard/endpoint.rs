//! Endpoint strings in the spellings operators already use, all mapped onto one [`Endpoint`]:
//!
//! | kind | MAVProxy / pymavlink, `mavlink` crate | mavlink-router | mavp2p | mavlink-server / MAVSDK |
//! | --- | --- | --- | --- | --- |
//! | UDP server (listen, peers learned) | `udpin:H:P`, `udp:H:P` | positional `H:P` | `udps:H:P` | `udpserver://H:P`, `udpin://H:P` |
//! | UDP client (send to a fixed peer) | `udpout:H:P` | `H:P` (`-e`) | `udpc:H:P` | `udpclient://H:P`, `udpout://H:P` |
//! | UDP broadcast client | `udpbcast:H:P` | `H:P` with a broadcast address | `udpb:H:P` | `udpbroadcast://H:P` |
//! | TCP server | `tcpin:H:P` | (`TcpServerPort`) | `tcps:H:P` | `tcpserver://H:P`, `tcpin://H:P` |
//! | TCP client (reconnects) | `tcp:H:P`, `tcpout:H:P` | `-p H:P` | `tcpc:H:P` | `tcpclient://H:P`, `tcpout://H:P` |
//! | serial port | `DEV,BAUD`, `serial:DEV:BAUD` | `/dev/ttyX[:BAUD]` | `serial:DEV:BAUD` | `serial://DEV:BAUD`, `serial:///DEV?baudrate=B` |
//!
//! `udp:` follows pymavlink's `mavlink_connection` (listen), as MAVProxy's `--master` does; a bare
//! `HOST:PORT` follows mavlink-router's `-e` (send to it). A wrong spelling is an
//! [`EndpointError`] that names the spellings expected.

use std::fmt;
use std::net::{IpAddr, SocketAddr, ToSocketAddrs};

/// One endpoint's connection.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Endpoint {
    /// Listen on a UDP address; peers are learned from what arrives (mavlink-router `Server`).
    UdpIn(SocketAddr),
    /// Send to a UDP peer from an ephemeral port (mavlink-router `Normal`). A broadcast or
    /// multicast address behaves as [`Endpoint::UdpBcast`].
    UdpOut(SocketAddr),
    /// Send to a broadcast address until a peer answers, then to that peer; back to broadcast
    /// after 5 s without a datagram from it.
    UdpBcast(SocketAddr),
    /// Accept TCP clients; each connection is routed on its own.
    TcpIn(SocketAddr),
    /// Connect to a TCP server, reconnecting after the endpoint's retry time when it drops.
    TcpOut(SocketAddr),
    /// A serial port at a baud rate.
    Serial {
        /// Device path, e.g. `/dev/ttyUSB0`.
        device: String,
        /// Baud rate, one of [`SUPPORTED_BAUDS`].
        baud: u32,
    },
}

impl Endpoint {
    /// Whether a UDP client sends to a broadcast or multicast address (and so learns its peer
    /// from the replies).
    pub fn is_broadcast(&self) -> bool {
        match self {
            Endpoint::UdpBcast(_) => true,
            Endpoint::UdpOut(a) => match a.ip() {
                IpAddr::V4(v4) => v4.is_broadcast() || v4.is_multicast() || v4.octets()[3] == 255,
                IpAddr::V6(v6) => v6.is_multicast(),
            },
            _ => false,
        }
    }

    /// The kind of connection, as in logs and statistics.
    pub fn kind(&self) -> &'static str {
        match self {
            Endpoint::UdpIn(_) => "udp server",
            Endpoint::UdpOut(_) | Endpoint::UdpBcast(_) => "udp client",
            Endpoint::TcpIn(_) => "tcp server",
            Endpoint::TcpOut(_) => "tcp client",
            Endpoint::Serial { .. } => "serial",
        }
    }
}

impl fmt::Display for Endpoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Endpoint::UdpIn(a) => write!(f, "udpin:{a}"),
            Endpoint::UdpOut(a) => write!(f, "udpout:{a}"),
            Endpoint::UdpBcast(a) => write!(f, "udpbcast:{a}"),
            Endpoint::TcpIn(a) => write!(f, "tcpin:{a}"),
            Endpoint::TcpOut(a) => write!(f, "tcpout:{a}"),
            Endpoint::Serial { device, baud } => write!(f, "serial:{device}:{baud}"),
        }
    }
}

/// Baud rates the serial setup can set directly (termios on Linux).
pub const SUPPORTED_BAUDS: &[u32] = &[
    1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200, 230400, 460800, 500000, 576000, 921600,
    1000000, 1152000, 1500000, 2000000, 2500000, 3000000, 3500000, 4000000,
];

/// mavlink-router's baud rate when a UART endpoint names none.
pub const DEFAULT_BAUD: u32 = 115200;

/// The spellings a message about a wrong endpoint lists.
pub const EXPECTED: &str = "udpin:|udp:|udpout:|udpbcast:|tcpin:|tcp:|tcpout:HOST:PORT \
     (MAVProxy), udps:|udpc:|udpb:|tcps:|tcpc:HOST:PORT (mavp2p), udpserver://|udpclient://|\
     tcpserver://|tcpclient://HOST:PORT, HOST:PORT (UDP client, mavlink-router -e), \
     /dev/ttyX[:BAUD], DEVICE,BAUD or serial:DEVICE:BAUD";

/// Why an endpoint string was not understood.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum EndpointError {
    /// Neither a scheme nor an address nor a device.
    #[error("endpoint `{spec}`: expected one of {EXPECTED}")]
    #[diagnostic(code(mav::E001))]
    NoScheme {
        /// What was given.
        spec: String,
    },
    /// A scheme no tool uses.
    #[error("endpoint `{spec}`: unknown scheme `{scheme}`; expected one of {EXPECTED}")]
    #[diagnostic(code(mav::E002))]
    UnknownScheme {
        /// What was given.
        spec: String,
        /// The scheme.
        scheme: String,
    },
    /// An address that does not resolve.
    #[error(
        "endpoint `{spec}`: bad address `{addr}` ({reason}); expected HOST:PORT, e.g. 127.0.0.1:14550 or [::1]:14550"
    )]
    #[diagnostic(code(mav::E003))]
    BadAddress {
        /// What was given.
        spec: String,
        /// The address part.
        addr: String,
        /// Why it does not resolve.
        reason: String,
    },
    /// A serial endpoint without a usable device or baud rate.
    #[error("endpoint `{spec}`: {problem}")]
    #[diagnostic(
        code(mav::E004),
        help(
            "DEVICE,BAUD, /dev/ttyX:BAUD or serial:DEVICE:BAUD with BAUD one of {SUPPORTED_BAUDS:?}"
        )
    )]
    BadSerial {
        /// What was given.
        spec: String,
        /// What is wrong with it.
        problem: String,
    },
    /// `SIDE:URL` without a known side.
    #[error(
        "endpoint `{spec}`: expected SIDE:URL with SIDE `vehicle` or `ground` (or `gcs`), e.g. vehicle:serial:/dev/ttyACM0:115200"
    )]
    #[diagnostic(code(mav::E005))]
    NoSide {
        /// What was given.
        spec: String,
    },
}

fn resolve(spec: &str, rest: &str) -> Result<SocketAddr, EndpointError> {
    let bad = |reason: String| EndpointError::BadAddress {
        spec: spec.to_string(),
        addr: rest.to_string(),
        reason,
    };
    rest.to_socket_addrs()
        .map_err(|e| bad(e.to_string()))?
        .next()
        .ok_or_else(|| bad("resolves to nothing".into()))
}

/// A serial port `DEVICE` + `BAUD` text (`None` = mavlink-router's default).
pub fn serial(spec: &str, device: &str, baud: Option<&str>) -> Result<Endpoint, EndpointError> {
    let bad = |problem: String| EndpointError::BadSerial { spec: spec.to_string(), problem };
    if device.is_empty() {
        return Err(bad("empty device path".into()));
    }
    let baud = match baud {
        None => DEFAULT_BAUD,
        Some(b) => b.trim().parse().map_err(|_| bad(format!("baud `{b}` is not a number")))?,
    };
    if !SUPPORTED_BAUDS.contains(&baud) {
        return Err(bad(format!("baud {baud} not supported")));
    }
    Ok(Endpoint::Serial { device: device.to_string(), baud })
}

/// `serial:///dev/ttyACM0?baudrate=115200` (mavlink-server) or `DEV:BAUD`.
fn serial_url(spec: &str, rest: &str) -> Result<Endpoint, EndpointError> {
    if let Some((device, query)) = rest.split_once('?') {
        let baud = query.split('&').find_map(|kv| kv.strip_prefix("baudrate="));
        return serial(spec, device, baud);
    }
    match rest.rsplit_once(':') {
        Some((device, baud)) => serial(spec, device, Some(baud)),
        None => Err(EndpointError::BadSerial {
            spec: spec.to_string(),
            problem: "expected serial:DEVICE:BAUD".into(),
        }),
    }
}

/// A device path (`/dev/…`, `COM3`) as mavlink-router and MAVProxy write it.
fn looks_like_device(s: &str) -> bool {
    s.starts_with('/') || s.to_ascii_uppercase().starts_with("COM")
}

impl std::str::FromStr for Endpoint {
    type Err = EndpointError;

    fn from_str(s: &str) -> Result<Self, EndpointError> {
        let s = s.trim();
        // MAVProxy's DEVICE,BAUD
        if let Some((device, baud)) = s.split_once(',') {
            return serial(s, device, Some(baud));
        }
        // mavlink-router's /dev/ttyX[:BAUD]
        if looks_like_device(s) && !s.contains("://") {
            return match s.rsplit_once(':') {
                Some((device, baud)) => serial(s, device, Some(baud)),
                None => serial(s, s, None),
            };
        }
        let (scheme, rest) = match s.split_once("://") {
            Some(x) => x,
            None => s.split_once(':').ok_or_else(|| EndpointError::NoScheme { spec: s.into() })?,
        };
        let addr = |rest: &str| resolve(s, rest);
        Ok(match scheme.to_ascii_lowercase().as_str() {
            "udpin" | "udp" | "udps" | "udpserver" => Endpoint::UdpIn(addr(rest)?),
            "udpout" | "udpc" | "udpclient" => Endpoint::UdpOut(addr(rest)?),
            "udpbcast" | "udpb" | "udpbroadcast" => Endpoint::UdpBcast(addr(rest)?),
            "tcpin" | "tcps" | "tcpserver" => Endpoint::TcpIn(addr(rest)?),
            "tcpout" | "tcp" | "tcpc" | "tcpclient" => Endpoint::TcpOut(addr(rest)?),
            "serial" => serial_url(s, rest)?,
            // mavlink-router's -e HOST:PORT: a UDP client
            _ if rest.parse::<u16>().is_ok() => Endpoint::UdpOut(addr(s)?),
            _ if s.starts_with('[') => Endpoint::UdpOut(addr(s)?),
            other => {
                return Err(EndpointError::UnknownScheme { spec: s.into(), scheme: other.into() });
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ep(s: &str) -> Endpoint {
        s.parse().unwrap_or_else(|e| panic!("{s}: {e}"))
    }
    fn a(s: &str) -> SocketAddr {
        s.parse().unwrap()
    }

    #[test]
    fn every_tools_spelling() {
        let udp_in = Endpoint::UdpIn(a("0.0.0.0:14550"));
        for s in ["udpin:0.0.0.0:14550", "udp:0.0.0.0:14550", "udps:0.0.0.0:14550"] {
            assert_eq!(ep(s), udp_in, "{s}");
        }
        assert_eq!(ep("udpserver://0.0.0.0:14550"), udp_in);
        assert_eq!(ep("udpin://0.0.0.0:14550"), udp_in);
        let udp_out = Endpoint::UdpOut(a("127.0.0.1:14550"));
        for s in ["udpout:127.0.0.1:14550", "udpc:127.0.0.1:14550", "127.0.0.1:14550"] {
            assert_eq!(ep(s), udp_out, "{s}");
        }
        assert_eq!(ep("udpclient://127.0.0.1:14550"), udp_out);
        assert_eq!(ep("[::1]:14550"), Endpoint::UdpOut(a("[::1]:14550")));
        let bcast = Endpoint::UdpBcast(a("192.168.1.255:14550"));
        assert_eq!(ep("udpbcast:192.168.1.255:14550"), bcast);
        assert_eq!(ep("udpb:192.168.1.255:14550"), bcast);
        assert!(bcast.is_broadcast() && ep("192.168.1.255:14550").is_broadcast());
        assert!(!udp_out.is_broadcast());
        let tcp_in = Endpoint::TcpIn(a("0.0.0.0:5760"));
        assert_eq!(ep("tcpin:0.0.0.0:5760"), tcp_in);
        assert_eq!(ep("tcps:0.0.0.0:5760"), tcp_in);
        assert_eq!(ep("tcpserver://0.0.0.0:5760"), tcp_in);
        let tcp_out = Endpoint::TcpOut(a("127.0.0.1:5760"));
        for s in ["tcp:127.0.0.1:5760", "tcpout:127.0.0.1:5760", "tcpc:127.0.0.1:5760"] {
            assert_eq!(ep(s), tcp_out, "{s}");
        }
        assert_eq!(ep("tcpout://127.0.0.1:5760"), tcp_out);
        let usb = Endpoint::Serial { device: "/dev/ttyUSB0".into(), baud: 57600 };
        for s in ["/dev/ttyUSB0,57600", "/dev/ttyUSB0:57600", "serial:/dev/ttyUSB0:57600"] {
            assert_eq!(ep(s), usb, "{s}");
        }
        assert_eq!(ep("serial:///dev/ttyUSB0?baudrate=57600"), usb);
        assert_eq!(ep("serial:///dev/ttyUSB0:57600"), usb);
        assert_eq!(
            ep("/dev/ttyS1"),
            Endpoint::Serial { device: "/dev/ttyS1".into(), baud: 115200 }
        );
        assert_eq!(ep("COM3,115200"), Endpoint::Serial { device: "COM3".into(), baud: 115200 });
    }

    #[test]
    fn displays_in_the_canonical_spelling() {
        for s in [
            "udpin:0.0.0.0:14550",
            "udpout:127.0.0.1:14555",
            "udpbcast:10.0.0.255:14550",
            "tcpin:0.0.0.0:5760",
            "tcpout:127.0.0.1:5760",
            "serial:/dev/ttyUSB0:57600",
        ] {
            assert_eq!(ep(s).to_string(), s);
        }
    }

    #[test]
    fn wrong_spellings_name_what_was_expected() {
        let e = "bogus:1.2.3.4:5".parse::<Endpoint>().unwrap_err().to_string();
        assert!(
            e.contains("unknown scheme `bogus`") && e.contains("udpin:") && e.contains("udps:")
        );
        let e = "udpin:nohost".parse::<Endpoint>().unwrap_err().to_string();
        assert!(e.contains("bad address") && e.contains("HOST:PORT"), "{e}");
        let e = "serial:/dev/ttyS0:1234".parse::<Endpoint>().unwrap_err().to_string();
        assert!(e.contains("not supported"), "{e}");
        let e = "/dev/ttyS0,fast".parse::<Endpoint>().unwrap_err().to_string();
        assert!(e.contains("not a number"), "{e}");
        let e = "14550".parse::<Endpoint>().unwrap_err().to_string();
        assert!(e.contains("expected one of"), "{e}");
        assert!("udpin:127.0.0.1".parse::<Endpoint>().is_err());
        assert!(",57600".parse::<Endpoint>().is_err());
    }
}
