//! The routing rules on hand-made tables (expected routes worked out from mavlink-router's
//! documented rules, not from this code).

use super::*;

fn info(sysid: u8, compid: u8, target: Option<(u8, u8)>) -> FrameInfo {
    FrameInfo {
        msgid: 76,
        sysid,
        compid,
        target_sys: target.map(|t| t.0),
        target_comp: target.map(|t| t.1),
    }
}

fn set(mask: RouteMask) -> Vec<usize> {
    indices(mask).collect()
}

/// Vehicle 1/1 on route 0, GCS 255/190 on route 1, GCS 254/190 on route 2.
fn three() -> Routes {
    let none = Filter::default();
    let mut r = Routes::new(
        &[
            (Side::Vehicle, none.clone(), None),
            (Side::Gcs, none.clone(), None),
            (Side::Gcs, none, None),
        ],
        None,
    );
    for ep in 0..3 {
        assert_eq!(r.open(ep, Peer::Fixed), Some(ep));
    }
    r.learn(0, 1, 1);
    r.learn(1, 255, 190);
    r.learn(2, 254, 190);
    r
}

#[test]
fn targeted_frames_go_only_where_the_target_was_seen() {
    let r = three();
    // telemetry from the vehicle (no target): both ground stations, never back
    assert_eq!(set(r.route(0, &info(1, 1, None)).0), vec![1, 2]);
    // a command to 1/1 from one GCS: the vehicle only, not the other GCS
    assert_eq!(set(r.route(1, &info(255, 190, Some((1, 1)))).0), vec![0]);
    // to every component of system 1
    assert_eq!(set(r.route(1, &info(255, 190, Some((1, 0)))).0), vec![0]);
    // to a component of system 1 that was never seen: nowhere
    assert_eq!(set(r.route(1, &info(255, 190, Some((1, 5)))).0), Vec::<usize>::new());
    // to system 0 (broadcast): everyone else
    assert_eq!(set(r.route(1, &info(255, 190, Some((0, 0)))).0), vec![0, 2]);
    // the vehicle's answer to GCS 254/190 reaches that GCS only
    assert_eq!(set(r.route(0, &info(1, 1, Some((254, 190)))).0), vec![2]);
    // to a system never seen anywhere: nowhere
    assert_eq!(r.route(0, &info(1, 1, Some((7, 1)))).0, 0);
}

#[test]
fn a_route_that_has_seen_the_sender_does_not_get_its_frames_back() {
    let mut r = three();
    // the same vehicle is also heard on route 2 (e.g. a second radio)
    r.learn(2, 1, 1);
    assert_eq!(set(r.route(0, &info(1, 1, None)).0), vec![1]);
}

#[test]
fn outgoing_filters_apply_after_routing() {
    let none = Filter::default();
    let block_attitude = Filter { block_msg: vec![30], ..Filter::default() };
    let mut r = Routes::new(
        &[
            (Side::Vehicle, none.clone(), None),
            (Side::Gcs, none, None),
            (Side::Gcs, block_attitude, None),
        ],
        None,
    );
    (0..3).for_each(|ep| {
        r.open(ep, Peer::Fixed);
    });
    r.learn(0, 1, 1);
    let attitude = FrameInfo { msgid: 30, ..info(1, 1, None) };
    assert_eq!(r.route(0, &attitude), (0b010, 0b100));
    let heartbeat = FrameInfo { msgid: 0, ..info(1, 1, None) };
    assert_eq!(r.route(0, &heartbeat), (0b110, 0));
}

#[test]
fn a_group_shares_what_its_routes_have_seen() {
    let none = Filter::default();
    let radio = Some("radio".to_string());
    let mut r = Routes::new(
        &[
            (Side::Vehicle, none.clone(), radio.clone()),
            (Side::Vehicle, none.clone(), radio),
            (Side::Gcs, none, None),
        ],
        None,
    );
    (0..3).for_each(|ep| {
        r.open(ep, Peer::Fixed);
    });
    r.learn(0, 1, 1);
    // a frame of the vehicle that came over link 0 is not sent back over the parallel link 1
    assert_eq!(set(r.route(0, &info(1, 1, None)).0), vec![2]);
    // a command to 1/1 goes over both links
    r.learn(2, 255, 190);
    assert_eq!(set(r.route(2, &info(255, 190, Some((1, 1)))).0), vec![0, 1]);
}

#[test]
fn the_sniffer_gets_everything() {
    let none = Filter::default();
    let mut r = Routes::new(
        &[
            (Side::Vehicle, none.clone(), None),
            (Side::Gcs, none.clone(), None),
            (Side::Gcs, none, None),
        ],
        Some(254),
    );
    (0..3).for_each(|ep| {
        r.open(ep, Peer::Fixed);
    });
    r.learn(0, 1, 1);
    r.learn(1, 255, 190);
    r.learn(2, 254, 1);
    assert_eq!(set(r.route(1, &info(255, 190, Some((1, 1)))).0), vec![0, 2]);
}

#[test]
fn connections_of_one_endpoint_are_routes_of_their_own() {
    let none = Filter::default();
    let mut r = Routes::new(&[(Side::Vehicle, none.clone(), None), (Side::Gcs, none, None)], None);
    let v = r.open(0, Peer::Fixed).unwrap();
    let a = addr(1);
    let b = addr(2);
    let ra = r.open(1, Peer::Udp(a)).unwrap();
    let rb = r.open(1, Peer::Udp(b)).unwrap();
    assert_eq!(r.open(1, Peer::Udp(a)), Some(ra), "the same connection is the same route");
    r.learn(v, 1, 1);
    r.learn(ra, 255, 190);
    r.learn(rb, 254, 190);
    assert_eq!(set(r.route(v, &info(1, 1, Some((255, 190)))).0), vec![ra]);
    assert_eq!(set(r.route(v, &info(1, 1, None)).0), vec![ra, rb]);
    assert_eq!(r.toward(Side::Gcs, 254, 190), 1 << rb);
    assert_eq!(r.toward(Side::Gcs, 9, 9), 1 << ra | 1 << rb, "unknown: the whole side");
    // a closed connection gets nothing; its slot is reused with an empty memory
    r.close(1, Peer::Udp(a));
    assert_eq!(set(r.route(v, &info(1, 1, None)).0), vec![rb]);
    let c = r.open(1, Peer::Udp(addr(3))).unwrap();
    assert_eq!(c, ra);
    assert_eq!(set(r.route(v, &info(1, 1, Some((255, 190)))).0), Vec::<usize>::new());
}

#[test]
fn tables_are_bounded() {
    let mut r = Routes::new(&[(Side::Gcs, Filter::default(), None)], None);
    for i in 0..MAX_ROUTES {
        assert!(r.open(0, Peer::Stream(i as u64)).is_some());
    }
    assert_eq!(r.open(0, Peer::Stream(9999)), None);
    for s in 0..=255u8 {
        r.learn(0, s, 1);
    }
    assert_eq!(r.ids_not_learned, 256 - MAX_IDS_PER_ROUTE as u64);
}

#[test]
fn targets_are_read_from_the_dialect_with_truncated_fields_as_zero() {
    let Ok(d) = Dialect::default_dialect() else { return };
    let t = Targets::new(Arc::new(d));
    // COMMAND_LONG to 1/1 (pymavlink command_long_encode(1, 1, 208, 0, 2, 0, 0, 0, 0, 0, 0))
    let hex =
        "fd20000000ffe64c000000000040000000000000000000000000000000000000000000000000d0000101a15d";
    let bytes: Vec<u8> = (0..hex.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&hex[i..i + 2], 16).unwrap())
        .collect();
    let f = FrameRef::new(&bytes).unwrap();
    assert_eq!(t.of(&f), (Some(1), Some(1)));
    // HEARTBEAT has no target fields
    let hb = [0xfd, 9, 0, 0, 0, 1, 1, 0, 0, 0, 0, 0, 0, 0, 2, 3, 0, 4, 3, 0, 0];
    assert_eq!(t.of(&FrameRef::new(&hb).unwrap()), (None, None));
    // PARAM_REQUEST_LIST to 0/0 with the zero target fields truncated away (payload length 1
    // would be wrong for MAVLink 2; 0 bytes is not allowed, so one zero byte is kept)
    let prl = [0xfd, 1, 0, 0, 0, 255, 190, 21, 0, 0, 0, 0, 0];
    assert_eq!(t.of(&FrameRef::new(&prl).unwrap()), (Some(0), Some(0)));
}

fn addr(i: u16) -> std::net::SocketAddr {
    std::net::SocketAddr::from(([127, 0, 0, 1], 2000 + i))
}
