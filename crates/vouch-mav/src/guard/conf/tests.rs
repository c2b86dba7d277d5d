//! Configuration files as operators write them for mavlink-router, and what vouch adds.

use std::net::SocketAddr;

use super::*;
use crate::guard::filter::Filter;

fn parse(files: &[(&str, &str)]) -> Result<RouterFile, ConfError> {
    parse_sources(
        files.iter().map(|(n, t)| Source { name: n.to_string(), text: t.to_string() }).collect(),
    )
}

fn a(s: &str) -> SocketAddr {
    s.parse().unwrap()
}

/// A companion computer's main.conf as mavlink-router's documentation has them: the autopilot
/// on a UART, QGroundControl and a second GCS as UDP clients, a logger on a UDP server port.
const UART_MAIN_CONF: &str = "\
# /etc/mavlink-router/main.conf
[General]
TcpServerPort = 5760
ReportStats = false
MavlinkDialect = auto

[UartEndpoint autopilot]
Device = /dev/ttyS1
Baud = 921600

[UdpEndpoint qgc]
Mode = Normal
Address = 192.168.1.20
Port = 14550

[UdpEndpoint gcs2]
Mode = Normal
Address = 192.168.1.21

[UdpEndpoint companion]
Mode = Server
Address = 0.0.0.0
Port = 14540
BlockMsgIdOut = 30,31
";

#[test]
fn a_mavlink_router_main_conf_reads_unchanged() {
    let mut f = parse(&[("main.conf", UART_MAIN_CONF)]).unwrap();
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    assert_eq!(f.tcp_server_port, 5760);
    assert!(!f.report_stats);
    assign_sides(&mut f.endpoints).unwrap();
    let got: Vec<(&str, Side, Endpoint)> = f
        .endpoints
        .iter()
        .map(|e| (e.config.name.as_str(), e.config.side, e.config.link.clone()))
        .collect();
    assert_eq!(
        got,
        vec![
            (
                "autopilot",
                Side::Vehicle,
                Endpoint::Serial { device: "/dev/ttyS1".into(), baud: 921600 }
            ),
            ("qgc", Side::Gcs, Endpoint::UdpOut(a("192.168.1.20:14550"))),
            // no Port on a client: mavlink-router's 14550 (another address than qgc's)
            ("gcs2", Side::Gcs, Endpoint::UdpOut(a("192.168.1.21:14550"))),
            ("companion", Side::Gcs, Endpoint::UdpIn(a("0.0.0.0:14540"))),
        ]
    );
    let out = &f.endpoints[3].config.filters.outbound;
    assert_eq!(out, &Filter { block_msg: vec![30, 31], ..Filter::default() });
    let tcp = tcp_server(f.tcp_server_port).unwrap();
    assert_eq!(tcp.config.link, Endpoint::TcpIn(a("0.0.0.0:5760")));
}

#[test]
fn the_one_udp_server_is_the_vehicle_when_nothing_else_says() {
    let conf = "[UdpEndpoint fcu]\nMode = Server\nAddress = 0.0.0.0\nPort = 14555\n\
                [UdpEndpoint qgc]\nMode = Normal\nAddress = 127.0.0.1\nPort = 14550\n\
                [TcpEndpoint logger]\nAddress = 127.0.0.1\nPort = 25760\nRetryTimeout = 0\n\
                [UdpEndpoint gcs2]\nmode = normal\naddress = 127.0.0.1\n";
    let mut f = parse(&[("main.conf", conf)]).unwrap();
    assign_sides(&mut f.endpoints).unwrap();
    let sides: Vec<Side> = f.endpoints.iter().map(|e| e.config.side).collect();
    assert_eq!(sides, vec![Side::Vehicle, Side::Gcs, Side::Gcs, Side::Gcs]);
    assert_eq!(f.endpoints[2].config.retry, None, "RetryTimeout = 0: never reconnect");
    // the second client of 127.0.0.1 without Port gets the next port
    assert_eq!(f.endpoints[3].config.link, Endpoint::UdpOut(a("127.0.0.1:14551")));
}

#[test]
fn side_keys_and_no_vehicle() {
    let two_servers = "[UdpEndpoint a]\nMode = Server\nAddress = 0.0.0.0\nPort = 1\n\
                       [UdpEndpoint b]\nMode = Server\nAddress = 0.0.0.0\nPort = 2\n";
    let mut f = parse(&[("m.conf", two_servers)]).unwrap();
    let e = assign_sides(&mut f.endpoints).unwrap_err();
    assert!(e.contains("Side = vehicle"), "{e}");
    let with_side = format!("{two_servers}[UdpEndpoint b]\nSide = vehicle\n");
    let mut f = parse(&[("m.conf", &with_side)]).unwrap();
    assign_sides(&mut f.endpoints).unwrap();
    assert_eq!(f.endpoints[1].config.side, Side::Vehicle);
    assert_eq!(f.endpoints[0].config.side, Side::Gcs);
}

#[test]
fn unknown_keys_and_sections_are_located_errors() {
    for (text, kind, line, col, what) in [
        (
            "[General]\nTcpServerPort = 5760\nReportStat = true\n",
            ConfErrorKind::UnknownKey,
            3,
            1,
            "ReportStat",
        ),
        (
            "[UdpEndpoint x]\nMode = Normal\nAdress = 1.2.3.4\n",
            ConfErrorKind::UnknownKey,
            3,
            1,
            "Adress",
        ),
        (
            "[UartEndpoint x]\nDevice = /dev/ttyS0\nRetryTimeout = 5\n",
            ConfErrorKind::UnknownKey,
            3,
            1,
            "RetryTimeout",
        ),
        ("\n[SerialEndpoint x]\n", ConfErrorKind::UnknownSection, 2, 1, "SerialEndpoint"),
        ("[Guard]\nEnforce = yes\n", ConfErrorKind::BadValue, 2, 11, "true, false"),
        (
            "[UdpEndpoint x]\nMode = Client\nAddress = 1.2.3.4\n",
            ConfErrorKind::BadValue,
            2,
            8,
            "normal, server",
        ),
        (
            "[UdpEndpoint x]\nMode = Server\nAddress = 0.0.0.0\n",
            ConfErrorKind::MissingKey,
            1,
            1,
            "needs `Port`",
        ),
        ("[TcpEndpoint x]\nAddress = 1.2.3.4\n", ConfErrorKind::MissingKey, 1, 1, "needs `Port`"),
        (
            "[UartEndpoint x]\nDevice = /dev/ttyS0\nBaud = 52000\n",
            ConfErrorKind::BadValue,
            3,
            8,
            "baud rates",
        ),
        (
            "[UdpEndpoint x]\nMode = Normal\nAddress = 1.2.3.4\nSide = air\n",
            ConfErrorKind::BadValue,
            4,
            8,
            "vehicle or ground",
        ),
        ("[UdpEndpoint]\nMode = Normal\n", ConfErrorKind::Syntax, 1, 1, "needs a name"),
        (
            "[UdpEndpoint x]\nMode=Normal\nAddress=1.2.3.4\n[TcpEndpoint X]\nAddress=1.2.3.4\nPort=1\n",
            ConfErrorKind::Conflict,
            4,
            1,
            "second endpoint",
        ),
    ] {
        let e = parse(&[("main.conf", text)]).unwrap_err();
        assert_eq!((e.kind, e.line_col()), (kind, (line, col)), "{text:?}: {e}");
        assert!(e.to_string().contains(what), "{text:?}: {e}");
        assert_eq!(e.src.name(), "main.conf");
    }
}

#[test]
fn a_conf_directory_adds_and_overrides_in_name_order() {
    let dir = std::env::temp_dir().join(format!("vouch-conf-dir-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let main = dir.join("main.conf");
    std::fs::write(&main, UART_MAIN_CONF).unwrap();
    let d = dir.join("config.d");
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("20-late.conf"), "[UdpEndpoint qgc]\nPort = 14560\n").unwrap();
    std::fs::write(
        d.join("10-early.conf"),
        "[UdpEndpoint qgc]\nPort = 14999\n[General]\nTcpServerPort = 0\n",
    )
    .unwrap();
    let f = load(Some(&main), Some(&d)).unwrap();
    assert_eq!(
        f.endpoints[1].config.link,
        Endpoint::UdpOut(a("192.168.1.20:14560")),
        "20- read after 10-"
    );
    assert_eq!(f.tcp_server_port, 0);
    assert!(tcp_server(0).is_none());
    // an error in a later file names that file
    std::fs::write(d.join("30-bad.conf"), "[General]\nBogus = 1\n").unwrap();
    let e = load(Some(&main), Some(&d)).unwrap_err();
    assert!(e.src.name().ends_with("30-bad.conf"), "{}", e.src.name());
    assert_eq!(e.line_col(), (2, 1));
    let e = load(Some(&dir.join("missing.conf")), None).unwrap_err();
    assert_eq!(e.kind, ConfErrorKind::Io);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn vouch_keys_and_mavlink_router_keys_it_does_not_act_on() {
    let conf = "[General]\nLog = /var/log/mav\nLogTelemetry = true\nMaxLogFiles = 10\nLogMode = while-armed\n\
                DeduplicationPeriod = 100\nSnifferSysid = 254\nDebugLogLevel = debug\n\
                [Guard]\nEnforce = true\nAlertGcs = 1\nProtocols = p/mission.vproto, /abs/x.vproto\n\
                Set = CHUTE_MAX_CLIMB=0.5\nSigningKey = passphrase:secret\nSignToVehicle = true\n\
                ViolationLog = v.jsonl\n\
                [UartEndpoint fc]\nDevice = /dev/ttyACM0\nBaud = 57600,115200\nFlowControl = true\n\
                AllowMsgIdIn = 0,1\nBlockSrcSysIn = 9\nGroup = radio\n";
    let f = parse(&[("/etc/vouch/guard.conf", conf)]).unwrap();
    assert_eq!(f.log_dir.as_deref(), Some(Path::new("/var/log/mav")));
    assert!(f.log_telemetry);
    assert_eq!(f.max_log_files, 10);
    assert_eq!(f.dedup_period, Some(Duration::from_millis(100)));
    assert_eq!(f.sniffer_sysid, Some(254));
    assert_eq!(f.log_level, Some(LogLevel::Debug));
    let g = &f.guard;
    assert_eq!((g.enforce, g.alert_gcs, g.sign_to_vehicle), (Some(true), Some(true), Some(true)));
    assert_eq!(
        g.protocols,
        vec![PathBuf::from("/etc/vouch/p/mission.vproto"), PathBuf::from("/abs/x.vproto")],
        "relative to the configuration file"
    );
    assert_eq!(g.set, vec![("CHUTE_MAX_CLIMB".to_string(), 0.5)]);
    assert!(g.signing_key.is_some());
    assert_eq!(g.violation_log.as_deref(), Some(Path::new("/etc/vouch/v.jsonl")));
    let fc = &f.endpoints[0].config;
    assert_eq!(fc.link, Endpoint::Serial { device: "/dev/ttyACM0".into(), baud: 57600 });
    assert!(fc.flow_control);
    assert_eq!(fc.group.as_deref(), Some("radio"));
    assert_eq!(
        fc.filters.inbound,
        Filter { allow_msg: vec![0, 1], block_src_sys: vec![9], ..Filter::default() }
    );
    // Log (no flight-stack logs), LogMode while-armed, the second baud rate: located warnings
    let warned: Vec<(usize, usize)> = f.warnings.iter().map(|w| w.line_col()).collect();
    assert_eq!(warned, vec![(2, 1), (5, 1), (19, 8)], "{:?}", f.warnings);
    assert!(f.warnings.iter().all(|w| w.kind == ConfErrorKind::NotImplemented));
}
