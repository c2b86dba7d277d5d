//! `[UartEndpoint NAME]`, `[UdpEndpoint NAME]` and `[TcpEndpoint NAME]` sections: mavlink-router's
//! keys with its meanings, plus vouch's `Side`.

use std::net::{SocketAddr, ToSocketAddrs};
use std::time::Duration;

use super::FileEndpoint;
use super::error::{ConfError, ConfErrorKind};
use super::ini::{Entry, Section};
use super::values::Values;
use crate::guard::config::{DEFAULT_TCP_RETRY, EndpointConfig, parse_side};
use crate::guard::endpoint::{DEFAULT_BAUD, Endpoint, SUPPORTED_BAUDS};
use crate::guard::filter::Filters;
use crate::side::Side;

/// The three endpoint section types.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    Uart,
    Udp,
    Tcp,
}

impl Kind {
    pub fn of(section_type: &str) -> Option<Kind> {
        [("uartendpoint", Kind::Uart), ("udpendpoint", Kind::Udp), ("tcpendpoint", Kind::Tcp)]
            .into_iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(section_type))
            .map(|(_, k)| k)
    }

    fn keys(self) -> &'static [&'static str] {
        match self {
            Kind::Uart => &["Device", "Baud", "FlowControl"],
            Kind::Udp => &["Mode", "Address", "Port", "Filter"],
            Kind::Tcp => &["Address", "Port", "RetryTimeout"],
        }
    }
}

/// Keys every endpoint section has (filters and group as mavlink-router, `Side` from vouch).
const COMMON_KEYS: &[&str] = &[
    "AllowMsgIdOut",
    "BlockMsgIdOut",
    "AllowSrcCompOut",
    "BlockSrcCompOut",
    "AllowSrcSysOut",
    "BlockSrcSysOut",
    "AllowMsgIdIn",
    "BlockMsgIdIn",
    "AllowSrcCompIn",
    "BlockSrcCompIn",
    "AllowSrcSysIn",
    "BlockSrcSysIn",
    "Group",
    "Side",
];

/// An endpoint section's settings, read; the UDP client port may still be unset.
pub(super) struct Read {
    pub endpoint: FileEndpoint,
    /// A UDP client without `Port`: numbered from 14550 once all endpoints are known.
    pub needs_port: bool,
}

pub(super) fn read(
    v: &Values<'_>,
    kind: Kind,
    s: &Section,
    name: &str,
    warnings: &mut Vec<ConfError>,
) -> Result<Read, ConfError> {
    let mut filters = Filters::default();
    let (mut side, mut group) = (None, None);
    for e in &s.entries {
        let known = kind.keys().iter().chain(COMMON_KEYS).any(|k| k.eq_ignore_ascii_case(&e.key));
        if !known {
            let msg = format!("unknown key `{}` in [{} {name}]", e.key, s.kind);
            let keys: Vec<&str> = kind.keys().iter().chain(COMMON_KEYS).copied().collect();
            return Err(v
                .ini
                .err(ConfErrorKind::UnknownKey, e.key_at, msg)
                .with_help(format!("keys of this section: {}", keys.join(", "))));
        }
        filter_key(v, e, &mut filters)?;
        if e.key.eq_ignore_ascii_case("Side") {
            side = Some(parse_side(&e.value).ok_or_else(|| v.bad(e, "vehicle or ground"))?);
        } else if e.key.eq_ignore_ascii_case("Group") {
            group = Some(e.value.clone());
        }
    }
    let missing = |key: &str| {
        let msg = format!("[{} {name}] needs `{key}`", s.kind);
        v.ini.err(ConfErrorKind::MissingKey, s.at, msg)
    };
    let mut needs_port = false;
    let mut retry = Some(DEFAULT_TCP_RETRY);
    let mut flow_control = false;
    let mut udp_server = false;
    let link = match kind {
        Kind::Uart => {
            let device = s.get("Device").ok_or_else(|| missing("Device"))?;
            let baud = match s.get("Baud") {
                None => DEFAULT_BAUD,
                Some(e) => baud(v, e, warnings)?,
            };
            if let Some(e) = s.get("FlowControl") {
                flow_control = v.boolean(e)?;
            }
            Endpoint::Serial { device: device.value.clone(), baud }
        }
        Kind::Udp => {
            let mode = s.get("Mode").ok_or_else(|| missing("Mode"))?;
            // `eavesdropping` is the name mavlink-router used for `server` before 2021
            udp_server = v.choice(mode, &["normal", "server", "eavesdropping"])? > 0;
            let address = s.get("Address").ok_or_else(|| missing("Address"))?;
            if let Some(legacy) = s.get("Filter") {
                // the name of AllowMsgIdOut before mavlink-router had filters both ways
                filters.outbound.allow_msg.extend(v.msg_ids(legacy)?);
            }
            match (s.get("Port"), udp_server) {
                (Some(p), _) => {
                    let a = socket(v, address, v.number(p, 65535)? as u16)?;
                    if udp_server { Endpoint::UdpIn(a) } else { Endpoint::UdpOut(a) }
                }
                (None, true) => return Err(missing("Port")),
                (None, false) => {
                    needs_port = true;
                    Endpoint::UdpOut(socket(v, address, 0)?)
                }
            }
        }
        Kind::Tcp => {
            let address = s.get("Address").ok_or_else(|| missing("Address"))?;
            let port = s.get("Port").ok_or_else(|| missing("Port"))?;
            if let Some(e) = s.get("RetryTimeout") {
                let secs = v.signed(e)?;
                retry = (secs > 0).then(|| Duration::from_secs(secs as u64));
            }
            Endpoint::TcpOut(socket(v, address, v.number(port, 65535)? as u16)?)
        }
    };
    let side_given = side.is_some();
    let mut config = EndpointConfig::new(name, side.unwrap_or(Side::Gcs), link);
    (config.filters, config.group, config.retry, config.flow_control) =
        (filters, group, retry, flow_control);
    let endpoint = FileEndpoint { config, side_given, udp_server, uart: kind == Kind::Uart };
    Ok(Read { endpoint, needs_port })
}

/// The filter keys (`Allow…`/`Block…`, `…In`/`…Out`).
fn filter_key(v: &Values<'_>, e: &Entry, f: &mut Filters) -> Result<(), ConfError> {
    let k = e.key.to_ascii_lowercase();
    let Some(rest) = k.strip_prefix("allow").or_else(|| k.strip_prefix("block")) else {
        return Ok(());
    };
    let allow = k.starts_with("allow");
    let (what, dir) = match rest.strip_suffix("in") {
        Some(w) => (w, &mut f.inbound),
        None => (rest.trim_end_matches("out"), &mut f.outbound),
    };
    match (what, allow) {
        ("msgid", true) => dir.allow_msg = v.msg_ids(e)?,
        ("msgid", false) => dir.block_msg = v.msg_ids(e)?,
        ("srccomp", true) => dir.allow_src_comp = v.ids(e)?,
        ("srccomp", false) => dir.block_src_comp = v.ids(e)?,
        ("srcsys", true) => dir.allow_src_sys = v.ids(e)?,
        ("srcsys", false) => dir.block_src_sys = v.ids(e)?,
        _ => {}
    }
    Ok(())
}

/// `Baud`: mavlink-router cycles through a list until MAVLink arrives; vouch uses the first.
fn baud(v: &Values<'_>, e: &Entry, warnings: &mut Vec<ConfError>) -> Result<u32, ConfError> {
    let list = v.list(e, u64::from(u32::MAX))?;
    let Some(&first) = list.first() else { return Err(v.bad(e, "a baud rate")) };
    let first = first as u32;
    if !SUPPORTED_BAUDS.contains(&first) {
        return Err(v.bad(e, &format!("one of the baud rates {SUPPORTED_BAUDS:?}")));
    }
    if list.len() > 1 {
        let msg = format!("several baud rates: vouch uses the first ({first}) and does not cycle");
        warnings.push(v.ini.err(ConfErrorKind::NotImplemented, e.value_at, msg));
    }
    Ok(first)
}

/// `Address` (IPv4, `[IPv6]` or a host name) with a port.
fn socket(v: &Values<'_>, address: &Entry, port: u16) -> Result<SocketAddr, ConfError> {
    format!("{}:{port}", address.value)
        .to_socket_addrs()
        .ok()
        .and_then(|mut a| a.next())
        .ok_or_else(|| {
            v.bad(address, "an IPv4 address, an IPv6 address in brackets, or a host name")
        })
}

/// mavlink-router's port for a UDP client without `Port`: 14550, or the next one when another
/// UDP endpoint of the same address has it.
pub(super) fn next_udp_port(address: std::net::IpAddr, taken: &[(std::net::IpAddr, u16)]) -> u16 {
    let mut port = 14550;
    while taken.iter().any(|(a, p)| *a == address && *p == port) {
        port += 1;
    }
    port
}
