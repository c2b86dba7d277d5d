//! Endpoint strings as operators know them from mavlink-router and the `mavlink` crate:
//! `udpin:ADDR:PORT` (listen; peers are learned from what arrives), `udpout:ADDR:PORT` (send to a
//! fixed peer from an ephemeral port), `tcpin:ADDR:PORT` (accept clients), `tcpout:ADDR:PORT`
//! (connect), `serial:DEVICE:BAUD`. Also accepted: the `scheme://` form used by MAVSDK.

use std::fmt;
use std::net::{SocketAddr, ToSocketAddrs};

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Endpoint {
    UdpIn(SocketAddr),
    UdpOut(SocketAddr),
    TcpIn(SocketAddr),
    TcpOut(SocketAddr),
    Serial { device: String, baud: u32 },
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

/// Baud rates termios can set directly on Linux.
pub const SUPPORTED_BAUDS: &[u32] = &[
    9600, 19200, 38400, 57600, 115200, 230400, 460800, 500000, 576000, 921600, 1000000, 1500000,
    2000000,
];

impl std::str::FromStr for Endpoint {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let (scheme, rest) =
            s.split_once("://").or_else(|| s.split_once(':')).ok_or_else(|| {
                format!("endpoint `{s}`: expected SCHEME:ADDRESS, e.g. udpin:0.0.0.0:14550")
            })?;
        let addr = |rest: &str| -> Result<SocketAddr, String> {
            rest.to_socket_addrs()
                .map_err(|e| format!("endpoint `{s}`: bad address `{rest}` ({e})"))?
                .next()
                .ok_or_else(|| format!("endpoint `{s}`: address `{rest}` resolves to nothing"))
        };
        match scheme {
            "udpin" | "udp" => Ok(Endpoint::UdpIn(addr(rest)?)),
            "udpout" => Ok(Endpoint::UdpOut(addr(rest)?)),
            "tcpin" => Ok(Endpoint::TcpIn(addr(rest)?)),
            "tcpout" | "tcp" => Ok(Endpoint::TcpOut(addr(rest)?)),
            "serial" => {
                let (device, baud) = rest
                    .rsplit_once(':')
                    .ok_or_else(|| format!("endpoint `{s}`: expected serial:DEVICE:BAUD"))?;
                let baud: u32 = baud
                    .parse()
                    .map_err(|_| format!("endpoint `{s}`: baud `{baud}` is not a number"))?;
                if !SUPPORTED_BAUDS.contains(&baud) {
                    return Err(format!(
                        "endpoint `{s}`: baud {baud} not supported (one of {SUPPORTED_BAUDS:?})"
                    ));
                }
                if device.is_empty() {
                    return Err(format!("endpoint `{s}`: empty device path"));
                }
                Ok(Endpoint::Serial { device: device.to_string(), baud })
            }
            other => Err(format!(
                "endpoint `{s}`: unknown scheme `{other}` (udpin, udpout, tcpin, tcpout, serial)"
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_router_style_strings() {
        assert_eq!(
            "udpin:0.0.0.0:14550".parse(),
            Ok(Endpoint::UdpIn("0.0.0.0:14550".parse().unwrap()))
        );
        assert_eq!(
            "udpout:127.0.0.1:14555".parse(),
            Ok(Endpoint::UdpOut("127.0.0.1:14555".parse().unwrap()))
        );
        assert_eq!(
            "tcpout://127.0.0.1:5760".parse(),
            Ok(Endpoint::TcpOut("127.0.0.1:5760".parse().unwrap()))
        );
        assert_eq!(
            "serial:/dev/ttyUSB0:57600".parse(),
            Ok(Endpoint::Serial { device: "/dev/ttyUSB0".into(), baud: 57600 })
        );
        assert_eq!(
            "udpin:0.0.0.0:14550".parse::<Endpoint>().unwrap().to_string(),
            "udpin:0.0.0.0:14550"
        );
    }

    #[test]
    fn rejects_with_reason() {
        let e = "bogus:1.2.3.4:5".parse::<Endpoint>().unwrap_err();
        assert!(e.contains("unknown scheme"), "{e}");
        assert!("udpin:nohost".parse::<Endpoint>().unwrap_err().contains("bad address"));
        assert!("serial:/dev/ttyS0:1234"
            .parse::<Endpoint>()
            .unwrap_err()
            .contains("not supported"));
        assert!("14550".parse::<Endpoint>().is_err());
    }
}
