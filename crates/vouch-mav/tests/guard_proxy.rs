//! The proxy on loopback with scripted peers: byte-exact forwarding both ways, several GCS
//! clients on one UDP port, TCP reassembly, enforce mode with answers, alerts, signing, counters.

mod guard_support;

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::time::Duration;

use guard_support::*;
use vouch_mav::Side;
use vouch_mav::codec::{FrameRef, InvalidKind};
use vouch_mav::guard::messages::{STATUSTEXT_ID, command_ack};
use vouch_mav::guard::{
    DATAGRAM_LIMIT, Endpoint, GuardConfig, Inspector, PassThrough, SigningConfig, start,
};
use vouch_mav::monitor::{Verdict, Violation, ViolationKind};
use vouch_mav::signing::SigningKey;

const WAIT: Duration = Duration::from_millis(600);

fn config(gcs: &str, vehicle: &str) -> GuardConfig {
    GuardConfig::new(gcs.parse().expect("gcs endpoint"), vehicle.parse().expect("vehicle endpoint"))
}

/// Flags every COMMAND_LONG DO_PARACHUTE and answers it with COMMAND_ACK DENIED from the vehicle.
struct DenyParachute;

impl Inspector for DenyParachute {
    fn inspect(&mut self, from: Side, f: FrameRef<'_>) -> Result<Verdict, InvalidKind> {
        let p = f.payload();
        if from == Side::Gcs
            && f.msgid() == 76
            && p.len() >= 30
            && u16::from_le_bytes([p[28], p[29]]) == 208
        {
            return Ok(Verdict::Violation(Box::new(Violation {
                kind: ViolationKind::Refinement,
                protocol: "test.parachute".into(),
                session: "no session".into(),
                message: format!("COMMAND_LONG from {}/{}", f.sysid(), f.compid()),
                step: String::new(),
                expected: vec![],
                predicate: Some("DO_PARACHUTE outside its precondition".into()),
                values: vec![],
                reason: "parachute release refused by the test inspector".into(),
                time_us: 0,
                reply: Some(command_ack(Side::Gcs, 1, 1, (f.sysid(), f.compid()), 208, 2)),
                more_replies: vec![],
                others: vec![],
            })));
        }
        Ok(Verdict::Accept)
    }
}

#[test]
fn forwards_bytes_unchanged_both_ways_to_several_gcs() {
    let vehicle = udp();
    let v_addr = vehicle.local_addr().unwrap();
    let g = start(config("udpin:127.0.0.1:0", &format!("udpout:{v_addr}")), Box::new(PassThrough))
        .expect("guard");
    let gcs_addr = g.gcs_addr.expect("bound");
    let (gcs1, gcs2) = (udp(), udp());
    let hb = hex(GCS_HEARTBEAT);
    gcs1.send_to(&hb, gcs_addr).unwrap();
    gcs2.send_to(&hb, gcs_addr).unwrap();
    // a datagram carrying two frames and trailing junk passes whole in monitor mode
    let mut multi = hex(GCS_HEARTBEAT);
    multi.extend(hex(PARACHUTE_RELEASE));
    multi.extend([0x55, 0xAA]);
    gcs1.send_to(&multi, gcs_addr).unwrap();
    let got = drain(&vehicle, WAIT);
    // datagrams received in one batch may leave together (at most DATAGRAM_LIMIT bytes); the
    // bytes and their order are unchanged
    assert!(got.iter().all(|d| d.len() <= DATAGRAM_LIMIT), "{got:?}");
    assert_eq!(got.concat(), [hb.clone(), hb.clone(), multi.clone()].concat());

    // vehicle answers to the guard's udpout port; both GCS clients get the exact bytes
    let guard_v = loopback(g.vehicle_addr.expect("udpout bound"));
    let vhb = hex(VEHICLE_HEARTBEAT);
    vehicle.send_to(&vhb, guard_v).unwrap();
    assert_eq!(recv_one(&gcs1, WAIT), Some(vhb.clone()));
    assert_eq!(recv_one(&gcs2, WAIT), Some(vhb.clone()));

    let c = g.stop();
    assert_eq!((c.frames_from_gcs, c.frames_from_vehicle), (4, 1));
    assert_eq!((c.forwarded_to_vehicle, c.forwarded_to_gcs), (4, 1));
    assert_eq!(c.junk_bytes, 2);
    assert_eq!(c.violations, 0);
}

#[test]
fn monitor_mode_reports_but_forwards() {
    let vehicle = udp();
    let dir = std::env::temp_dir().join(format!("vouch-guard-monitor-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut cfg = config("udpin:127.0.0.1:0", &format!("udpout:{}", vehicle.local_addr().unwrap()));
    cfg.log_path = Some(dir.join("violations.jsonl"));
    cfg.tlog_path = Some(dir.join("traffic.tlog"));
    cfg.alert_gcs = true;
    let g = start(cfg, Box::new(DenyParachute)).expect("guard");
    let gcs = udp();
    let chute = hex(PARACHUTE_RELEASE);
    gcs.send_to(&chute, g.gcs_addr.unwrap()).unwrap();
    assert_eq!(
        recv_one(&vehicle, WAIT),
        Some(chute.clone()),
        "monitor mode forwards the violating frame"
    );
    let alert = recv_one(&gcs, WAIT).expect("STATUSTEXT alert");
    let fr = FrameRef::new(&alert).expect("one frame");
    assert_eq!(fr.msgid(), STATUSTEXT_ID);
    assert!(String::from_utf8_lossy(fr.payload()).contains("DO_PARACHUTE"));
    let c = g.stop();
    assert_eq!((c.violations, c.dropped_violations, c.alerts_sent, c.replies_sent), (1, 0, 1, 0));
    let log = std::fs::read_to_string(dir.join("violations.jsonl")).unwrap();
    let line: serde_json::Value =
        serde_json::from_str(log.lines().next().expect("one line")).unwrap();
    assert_eq!(line["action"], "forwarded");
    assert_eq!(line["violation"]["protocol"], "test.parachute");
    let tlog = std::fs::read(dir.join("traffic.tlog")).unwrap();
    assert_eq!(&tlog[8..], &chute[..], "tlog = 8-byte timestamp + the frame");
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn enforce_mode_drops_and_answers_the_sender() {
    let vehicle = udp();
    let mut cfg = config("udpin:127.0.0.1:0", &format!("udpout:{}", vehicle.local_addr().unwrap()));
    cfg.enforce = true;
    let g = start(cfg, Box::new(DenyParachute)).expect("guard");
    let (gcs, bystander) = (udp(), udp());
    let hb = hex(GCS_HEARTBEAT);
    bystander.send_to(&hb, g.gcs_addr.unwrap()).unwrap();
    assert_eq!(recv_one(&vehicle, WAIT), Some(hb.clone()));
    // heartbeat + parachute + junk in one datagram: only the heartbeat reaches the vehicle
    let mut d = hex(GCS_HEARTBEAT);
    d.extend(hex(PARACHUTE_RELEASE));
    d.extend([1, 2, 3]);
    gcs.send_to(&d, g.gcs_addr.unwrap()).unwrap();
    assert_eq!(drain(&vehicle, WAIT), vec![hb.clone()]);
    let ack = recv_one(&gcs, WAIT).expect("COMMAND_ACK answer");
    // COMMAND_ACK{command 208, result DENIED 2, target 255/230} from 1/1
    let fr = FrameRef::new(&ack).expect("frame");
    assert_eq!((fr.msgid(), fr.sysid(), fr.compid()), (77, 1, 1));
    assert_eq!(&fr.payload()[..3], &[208, 0, 2]);
    assert_eq!(&fr.payload()[8..10], &[255, 230]);
    assert!(
        drain(&bystander, Duration::from_millis(200)).is_empty(),
        "answer goes only to the sender"
    );
    let c = g.stop();
    assert_eq!((c.violations, c.dropped_violations, c.replies_sent), (1, 1, 1));
}

#[test]
fn signing_keeps_outsiders_out() {
    let vehicle = udp();
    let mut cfg = config("udpin:127.0.0.1:0", &format!("udpout:{}", vehicle.local_addr().unwrap()));
    cfg.signing = Some(SigningConfig {
        key: SigningKey(key_0_to_31()),
        sign_to_vehicle: false,
        link_id: 0,
        state_file: None,
    });
    let g = start(cfg, Box::new(PassThrough)).expect("guard");
    let gcs = udp();
    let to = g.gcs_addr.unwrap();
    // pymavlink-signed frames carry a 2019 timestamp: more than a minute old for a new stream
    gcs.send_to(&hex(SIGNED_MISSION_COUNT), to).unwrap();
    gcs.send_to(&hex(GCS_HEARTBEAT), to).unwrap(); // unsigned
    let mut forged = hex(SIGNED_HEARTBEAT);
    forged[12] ^= 0x40;
    gcs.send_to(&forged, to).unwrap();
    assert!(drain(&vehicle, WAIT).is_empty());
    let c = g.stop();
    assert_eq!(c.signing_rejected, 3);
    assert_eq!(c.forwarded_to_vehicle, 0);
}

#[test]
fn signing_admits_fresh_rejects_replay_and_signs_toward_vehicle() {
    use vouch_mav::signing::{Signer, Verifier, timestamp_now};
    let vehicle = udp();
    let mut cfg = config("udpin:127.0.0.1:0", &format!("udpout:{}", vehicle.local_addr().unwrap()));
    cfg.signing = Some(SigningConfig {
        key: SigningKey(key_0_to_31()),
        sign_to_vehicle: true,
        link_id: 9,
        state_file: None,
    });
    let g = start(cfg, Box::new(PassThrough)).expect("guard");
    let gcs = udp();
    let to = g.gcs_addr.unwrap();
    let mut signer = Signer::new(SigningKey(key_0_to_31()), 3);
    let mut fresh = vec![];
    assert!(signer.sign_into(
        &FrameRef::new(&hex(GCS_HEARTBEAT)).unwrap(),
        timestamp_now(),
        &mut fresh
    ));
    gcs.send_to(&fresh, to).unwrap();
    gcs.send_to(&fresh, to).unwrap(); // replay
    let got = drain(&vehicle, WAIT);
    assert_eq!(got.len(), 1, "replayed copy dropped");
    // re-signed by the guard on link 9; payload and header unchanged; verifies with the key
    let fr = FrameRef::new(&got[0]).expect("frame");
    assert_eq!(fr.signature_block().unwrap()[0], 9);
    assert_eq!(fr.unsigned_part(), FrameRef::new(&fresh).unwrap().unsigned_part());
    let mut v = Verifier::new(SigningKey(key_0_to_31()));
    assert_eq!(v.check(&fr, timestamp_now()), Ok(()));
    let c = g.stop();
    assert_eq!((c.signing_rejected, c.forwarded_to_vehicle), (1, 1));
}

#[test]
fn setup_signing_is_never_forwarded() {
    let vehicle = udp();
    let g = start(
        config("udpin:127.0.0.1:0", &format!("udpout:{}", vehicle.local_addr().unwrap())),
        Box::new(PassThrough),
    )
    .expect("guard");
    // SETUP_SIGNING (256) framing only; the guard must drop it whatever its content
    let mut f = vec![0xFD, 42, 0, 0, 0, 255, 230, 0x00, 0x01, 0x00];
    f.extend([0u8; 42]);
    f.extend([0, 0]);
    udp().send_to(&f, g.gcs_addr.unwrap()).unwrap();
    assert!(drain(&vehicle, Duration::from_millis(300)).is_empty());
    assert_eq!(g.stop().setup_signing_dropped, 1);
}

#[test]
fn tcp_streams_are_reassembled_and_forwarded() {
    let vehicle = TcpListener::bind("127.0.0.1:0").unwrap();
    let g = start(
        config("tcpin:127.0.0.1:0", &format!("tcpout:{}", vehicle.local_addr().unwrap())),
        Box::new(PassThrough),
    )
    .expect("guard");
    let (mut v, _) = vehicle.accept().unwrap();
    v.set_read_timeout(Some(Duration::from_millis(100))).unwrap();
    let mut gcs = TcpStream::connect(g.gcs_addr.unwrap()).unwrap();
    gcs.set_read_timeout(Some(Duration::from_millis(100))).unwrap();
    connected(&g, "vehicle", 1); // connect/accept return before the guard registers them
    connected(&g, "gcs", 1);
    let mut stream = hex(GCS_HEARTBEAT);
    stream.extend(hex(PARACHUTE_RELEASE));
    for chunk in stream.chunks(7) {
        gcs.write_all(chunk).unwrap();
        gcs.flush().unwrap();
    }
    let mut got = vec![];
    let mut buf = [0u8; 512];
    for _ in 0..20 {
        if got.len() >= stream.len() {
            break;
        }
        if let Ok(n) = v.read(&mut buf) {
            got.extend_from_slice(&buf[..n]);
        }
    }
    assert_eq!(got, stream);
    v.write_all(&hex(VEHICLE_HEARTBEAT)).unwrap();
    let mut back = vec![];
    for _ in 0..20 {
        if back.len() >= 21 {
            break;
        }
        if let Ok(n) = gcs.read(&mut buf) {
            back.extend_from_slice(&buf[..n]);
        }
    }
    assert_eq!(back, hex(VEHICLE_HEARTBEAT));
    let c = g.stop();
    assert_eq!((c.forwarded_to_vehicle, c.forwarded_to_gcs), (2, 1));
}

#[test]
fn bad_endpoint_is_an_error_not_a_panic() {
    assert!("udpin:127.0.0.1".parse::<Endpoint>().is_err());
    let taken = udp();
    let cfg = config(&format!("udpin:{}", taken.local_addr().unwrap()), "udpout:127.0.0.1:9");
    let err = start(cfg, Box::new(PassThrough)).err().expect("port in use");
    assert!(err.to_string().contains("endpoint `gcs`"), "{err}");
}

/// The guard on one end of a pseudo-terminal pair made by socat (a real peer), the test on the
/// other end, playing the vehicle's serial link.
#[test]
fn serial_endpoint_over_a_pseudo_terminal() {
    let Some(socat) = vouch_testkit::program("socat", "-V") else { return };
    let dir = std::env::temp_dir().join(format!("vouch-guard-pty-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (guard_end, test_end) = (dir.join("guard"), dir.join("test"));
    let child = std::process::Command::new(socat)
        .arg(format!("pty,raw,echo=0,link={}", guard_end.display()))
        .arg(format!("pty,raw,echo=0,link={}", test_end.display()))
        .spawn()
        .expect("socat starts");
    let _socat = KillOnDrop(child);
    let end = std::time::Instant::now() + Duration::from_secs(5);
    while !(guard_end.exists() && test_end.exists()) {
        assert!(std::time::Instant::now() < end, "socat made no pseudo-terminals within 5 s");
        std::thread::sleep(Duration::from_millis(20));
    }
    let mut master =
        std::fs::OpenOptions::new().read(true).write(true).open(&test_end).expect("pty opens");
    let g = start(
        config("udpin:127.0.0.1:0", &format!("serial:{}:57600", guard_end.display())),
        Box::new(PassThrough),
    )
    .expect("guard");
    let gcs = udp();
    let hb = hex(GCS_HEARTBEAT);
    gcs.send_to(&hb, g.gcs_addr.unwrap()).unwrap();
    // read in a helper thread so that a regression fails after 2 s instead of hanging
    let mut reader = master.try_clone().unwrap();
    let n = hb.len();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut got = vec![0u8; n];
        let _ = tx.send(reader.read_exact(&mut got).map(|_| got));
    });
    let got = rx
        .recv_timeout(Duration::from_secs(2))
        .expect("bytes on the serial line within 2 s")
        .unwrap();
    assert_eq!(got, hb);
    // the vehicle answers on the serial line in two pieces; the GCS gets one whole frame
    let vhb = hex(VEHICLE_HEARTBEAT);
    master.write_all(&vhb[..5]).unwrap();
    master.flush().unwrap();
    std::thread::sleep(Duration::from_millis(50));
    master.write_all(&vhb[5..]).unwrap();
    assert_eq!(recv_one(&gcs, WAIT), Some(vhb));
    let c = g.stop();
    assert_eq!((c.forwarded_to_vehicle, c.forwarded_to_gcs), (1, 1));
}

/// A corrupt frame whose length field claims the next frame's bytes must not swallow it: after
/// the bad checksum the guard rescans from the byte after the corrupt frame's start marker.
#[test]
fn enforce_mode_resynchronises_after_a_corrupt_frame_in_a_datagram() {
    let vehicle = udp();
    let mut cfg = config("udpin:127.0.0.1:0", &format!("udpout:{}", vehicle.local_addr().unwrap()));
    cfg.enforce = true;
    let tlog = std::env::temp_dir().join(format!("vouch-guard-resync-{}.tlog", std::process::id()));
    cfg.tlog_path = Some(tlog.clone());
    let Some(inspector) = standard_inspector() else { return };
    let g = start(cfg, inspector).expect("guard");
    let hb = hex(GCS_HEARTBEAT);
    assert_eq!(hb.len(), 21);
    // length byte 9 → 30: the corrupt frame now claims 10 + 30 + 2 = 42 bytes, i.e. itself and
    // the whole heartbeat behind it; its checksum cannot match
    let mut corrupt = hb.clone();
    corrupt[1] = 30;
    let mut d = corrupt.clone();
    d.extend(&hb);
    d.extend(&hb);
    let gcs = udp();
    gcs.send_to(&d, g.gcs_addr.unwrap()).unwrap();
    let mut both = hb.clone();
    both.extend(&hb);
    // both good heartbeats, byte for byte and contiguous (one datagram), nothing of the corrupt one
    assert_eq!(drain(&vehicle, WAIT), vec![both]);
    // a frame with a wrong checksum alone is dropped, not forwarded
    let mut bad_crc = hb.clone();
    bad_crc[20] ^= 0x01;
    gcs.send_to(&bad_crc, g.gcs_addr.unwrap()).unwrap();
    assert!(drain(&vehicle, Duration::from_millis(200)).is_empty());
    let c = g.stop();
    assert_eq!(c.frames_from_gcs, 2, "{c:?}");
    assert_eq!(c.forwarded_to_vehicle, 2, "{c:?}");
    assert_eq!((c.malformed, c.dropped_malformed), (2, 2), "{c:?}");
    // the tlog holds the two good frames once each (8-byte timestamp + frame), no corrupt bytes
    let t = std::fs::read(&tlog).expect("tlog written");
    let _ = std::fs::remove_file(&tlog);
    assert_eq!(t.len(), 2 * (8 + 21));
    assert_eq!((&t[8..29], &t[37..58]), (&hb[..], &hb[..]));
}

/// The same over TCP: the stream reader resynchronises after a corrupt frame (enforce mode).
#[test]
fn tcp_stream_resynchronises_after_a_corrupt_frame() {
    let vehicle = TcpListener::bind("127.0.0.1:0").unwrap();
    let mut cfg = config("tcpin:127.0.0.1:0", &format!("tcpout:{}", vehicle.local_addr().unwrap()));
    cfg.enforce = true;
    let Some(inspector) = standard_inspector() else { return };
    let g = start(cfg, inspector).expect("guard");
    let (mut v, _) = vehicle.accept().unwrap();
    v.set_read_timeout(Some(Duration::from_millis(100))).unwrap();
    let mut gcs = TcpStream::connect(g.gcs_addr.unwrap()).unwrap();
    connected(&g, "vehicle", 1); // connect/accept return before the guard registers them
    connected(&g, "gcs", 1);
    let hb = hex(GCS_HEARTBEAT);
    let mut corrupt = hb.clone();
    corrupt[1] = 30; // claims itself and the heartbeat behind it
    let mut stream = corrupt;
    stream.extend(&hb);
    stream.extend(&hb);
    for chunk in stream.chunks(5) {
        gcs.write_all(chunk).unwrap();
        gcs.flush().unwrap();
    }
    let mut got = vec![];
    let mut buf = [0u8; 512];
    for _ in 0..10 {
        if let Ok(n) = v.read(&mut buf) {
            got.extend_from_slice(&buf[..n]);
        }
    }
    let mut both = hb.clone();
    both.extend(&hb);
    assert_eq!(got, both);
    let c = g.stop();
    assert_eq!((c.forwarded_to_vehicle, c.dropped_malformed), (2, 1), "{c:?}");
}
