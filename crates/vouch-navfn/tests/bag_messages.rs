//! Bags and messages, valid and malformed: costmaps as nav2 publishes them (the map, the
//! translated global costmap and its updates, the raw costmap) are the ones plans are checked
//! on; every malformed bag or message gets a clear error with its code (or, for a plan that
//! cannot be judged, a violation), never a panic. The valid messages here are encoded by
//! a small CDR writer of this test (independent of the reader), stored with the `mcap` crate's
//! writer and with SQLite through rusqlite in rosbag2's table layout.

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::{Path, PathBuf};

use miette::Diagnostic;
use vouch_navfn::bagcheck::{
    BagCheckOptions, CostmapKind, PathViolation, ReplayMode, check_bag, check_bag_file,
};
use vouch_navfn::rosbag::msgs::{NavMessage, decode};
use vouch_navfn::rosbag::{Bag, BagError, BagMessage, read_bag};

/// A little-endian CDR writer: alignment relative to the body, as XCDR1 requires.
struct Cdr(Vec<u8>);

impl Cdr {
    fn new() -> Cdr {
        Cdr(Vec::new())
    }
    fn align(&mut self, n: usize) {
        while !self.0.len().is_multiple_of(n) {
            self.0.push(0);
        }
    }
    fn u32(&mut self, v: u32) -> &mut Cdr {
        self.align(4);
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn i32(&mut self, v: i32) -> &mut Cdr {
        self.u32(v as u32)
    }
    fn f32(&mut self, v: f32) -> &mut Cdr {
        self.u32(v.to_bits())
    }
    fn f64(&mut self, v: f64) -> &mut Cdr {
        self.align(8);
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    fn string(&mut self, s: &str) -> &mut Cdr {
        self.u32(s.len() as u32 + 1);
        self.0.extend_from_slice(s.as_bytes());
        self.0.push(0);
        self
    }
    fn header(&mut self, frame: &str) -> &mut Cdr {
        self.i32(1).u32(0).string(frame)
    }
    fn pose(&mut self, p: [f64; 7]) -> &mut Cdr {
        for v in p {
            self.f64(v);
        }
        self
    }
    fn bytes(&mut self, b: &[u8]) -> &mut Cdr {
        self.u32(b.len() as u32);
        self.0.extend_from_slice(b);
        self
    }
    /// With the little-endian encapsulation header.
    fn payload(&self) -> Vec<u8> {
        let mut v = vec![0, 1, 0, 0];
        v.extend_from_slice(&self.0);
        v
    }
}

const IDENTITY: [f64; 7] = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];

fn grid(width: u32, height: u32, cells: &[u8]) -> Vec<u8> {
    let mut c = Cdr::new();
    c.header("map").i32(0).u32(0).f32(1.0).u32(width).u32(height).pose(IDENTITY).bytes(cells);
    c.payload()
}

fn path_msg(points: &[[f64; 2]]) -> Vec<u8> {
    let mut c = Cdr::new();
    c.header("map").u32(points.len() as u32);
    for p in points {
        c.header("map").pose([p[0], p[1], 0.0, 0.0, 0.0, 0.0, 1.0]);
    }
    c.payload()
}

fn msg(topic: &str, type_name: &str, log_time: u64, data: Vec<u8>) -> BagMessage {
    BagMessage { topic: topic.into(), type_name: type_name.into(), log_time, data }
}

fn code(e: &BagError) -> String {
    e.code().map(|c| c.to_string()).unwrap_or_default()
}

/// The test process's private scratch directory (`tempfile`, under the target directory).
fn scratch() -> &'static Path {
    static DIR: std::sync::OnceLock<tempfile::TempDir> = std::sync::OnceLock::new();
    DIR.get_or_init(|| {
        tempfile::Builder::new()
            .prefix("bag-malformed-")
            .tempdir_in(env!("CARGO_TARGET_TMPDIR"))
            .expect("temporary directory")
    })
    .path()
}

fn tmp(name: &str) -> PathBuf {
    scratch().join(name)
}

fn topics() -> std::collections::BTreeSet<String> {
    ["/map", "/plan"].into_iter().map(String::from).collect()
}

#[test]
fn cdr_written_independently_decodes_to_the_same_values() {
    let m = msg("/map", "nav_msgs/msg/OccupancyGrid", 1, grid(3, 2, &[0, 100, 255, 0, 0, 100]));
    let NavMessage::Grid(g) = decode(&m).expect("decodes") else { panic!("a grid") };
    assert_eq!((g.width, g.height, g.resolution, g.frame_id.as_str()), (3, 2, 1.0, "map"));
    let p = msg("/plan", "nav_msgs/msg/Path", 2, path_msg(&[[0.5, 1.25], [2.0, -3.0]]));
    let NavMessage::Path(frame, poses) = decode(&p).expect("decodes") else { panic!("a path") };
    assert_eq!(frame, "map");
    assert_eq!(
        (poses[1].position.x, poses[1].position.y, poses[1].orientation.w),
        (2.0, -3.0, 1.0)
    );
}

#[test]
fn malformed_messages_are_decode_errors_naming_topic_and_time() {
    let catalogue: Vec<(&str, &str, Vec<u8>, &str)> = vec![
        ("/map", "nav_msgs/msg/OccupancyGrid", vec![0, 1], "shorter than the CDR header"),
        ("/map", "nav_msgs/msg/OccupancyGrid", vec![0, 7, 0, 0, 1, 2], "is not plain CDR"),
        (
            "/map",
            "nav_msgs/msg/OccupancyGrid",
            grid(3, 3, &[0; 4]),
            "needs 9 cells, the message holds 4",
        ),
        ("/map", "nav_msgs/msg/OccupancyGrid", grid(u32::MAX, u32::MAX, &[]), "exceeds"),
        ("/map", "nav_msgs/msg/OccupancyGrid", grid(3, 2, &[0; 6])[..30].to_vec(), "bad CDR"),
        (
            "/plan",
            "nav_msgs/msg/Path",
            {
                let mut c = Cdr::new();
                c.header("map").u32(1_000_000);
                c.payload()
            },
            "bad CDR",
        ),
        (
            "/plan",
            "nav_msgs/msg/Path",
            {
                let mut c = Cdr::new();
                c.u32(u32::MAX);
                c.payload()
            },
            "bad CDR",
        ),
        ("/plan", "sensor_msgs/msg/Image", path_msg(&[]), "unsupported message type"),
    ];
    for (topic, type_name, data, expect) in catalogue {
        let e = decode(&msg(topic, type_name, 42, data)).expect_err(expect);
        let text = e.to_string();
        assert!(text.contains(expect) && text.contains(topic) && text.contains("42"), "{text}");
        assert_eq!(code(&e), "navfn::E033");
    }
}

#[test]
fn damaged_storage_is_rejected_with_its_file() {
    let empty = tmp("empty.mcap");
    std::fs::write(&empty, b"").expect("written");
    let e = read_bag(&empty, &topics()).expect_err("empty");
    assert_eq!(code(&e), "navfn::E031", "{e}");

    let folder = tmp("no-storage");
    std::fs::create_dir_all(&folder).expect("dir");
    std::fs::write(folder.join("metadata.yaml"), "rosbag2_bagfile_information: {}\n")
        .expect("written");
    let e = read_bag(&folder, &topics()).expect_err("no storage file");
    assert!(e.to_string().contains("no .mcap or .db3"), "{e}");

    let junk = tmp("junk.mcap");
    std::fs::write(&junk, b"\x89MCAP0\r\n\x01\x02\x03").expect("written");
    let e = read_bag(&junk, &topics()).expect_err("junk");
    assert_eq!(code(&e), "navfn::E032", "{e}");
    assert!(e.to_string().contains("junk.mcap"), "{e}");

    let missing = read_bag(Path::new("/no/such/bag"), &topics()).expect_err("missing");
    assert!(missing.is_io());
}

/// A valid MCAP (the `mcap` crate's writer) with a map and a plan, then cut short.
fn mcap_bytes() -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    {
        let mut w = mcap::Writer::new(&mut out).expect("writer");
        let grid_schema =
            w.add_schema("nav_msgs/msg/OccupancyGrid", "ros2msg", b"").expect("schema");
        let path_schema = w.add_schema("nav_msgs/msg/Path", "ros2msg", b"").expect("schema");
        let no_meta = BTreeMap::new();
        let map = w.add_channel(grid_schema, "/map", "cdr", &no_meta).expect("channel");
        let plan = w.add_channel(path_schema, "/plan", "cdr", &no_meta).expect("channel");
        let header = |channel_id, log_time| mcap::records::MessageHeader {
            channel_id,
            sequence: 0,
            log_time,
            publish_time: log_time,
        };
        let cells = vec![0u8; 100];
        w.write_to_known_channel(&header(map, 1), &grid(10, 10, &cells)).expect("map");
        let line: Vec<[f64; 2]> = (0..11).map(|i| [1.0 + 0.5 * i as f64, 5.0]).collect();
        w.write_to_known_channel(&header(plan, 2), &path_msg(&line)).expect("plan");
        w.finish().expect("finish");
    }
    out.into_inner()
}

#[test]
fn truncated_and_bit_flipped_mcap_is_an_error_or_the_same_messages() {
    let bytes = mcap_bytes();
    let whole = tmp("whole.mcap");
    std::fs::write(&whole, &bytes).expect("written");
    let bag = read_bag(&whole, &topics()).expect("valid MCAP");
    assert_eq!(bag.messages.len(), 2);
    for cut in [bytes.len() / 3, bytes.len() / 2, bytes.len() - 9] {
        let f = tmp(&format!("cut-{cut}.mcap"));
        std::fs::write(&f, &bytes[..cut]).expect("written");
        if let Err(e) = read_bag(&f, &topics()) {
            assert_eq!(code(&e), "navfn::E032", "{e}");
        }
    }
    // every single-byte change: an error, or messages that then decode or fail cleanly
    for i in (0..bytes.len()).step_by(7) {
        let mut b = bytes.clone();
        b[i] ^= 0x5a;
        if let Ok(messages) = vouch_navfn::rosbag::read_mcap_bytes(&b, &topics()) {
            let _ = check_bag(&Bag { files: Vec::new(), messages }, &BagCheckOptions::default());
        }
    }
}

#[test]
fn sqlite_bags_with_wrong_tables_or_formats_are_rejected() {
    let make = |name: &str, sql: &str| -> PathBuf {
        let f = tmp(name);
        let _ = std::fs::remove_file(&f);
        let db = rusqlite::Connection::open(&f).expect("db");
        db.execute_batch(sql).expect("sql");
        f
    };
    let no_tables = make("no-tables.db3", "CREATE TABLE other (x INTEGER);");
    let e = read_bag(&no_tables, &topics()).expect_err("no tables");
    assert_eq!(code(&e), "navfn::E032", "{e}");
    assert!(e.to_string().contains("no such table"), "{e}");

    let layout = "CREATE TABLE topics (id INTEGER PRIMARY KEY, name TEXT, type TEXT, serialization_format TEXT, offered_qos_profiles TEXT);\
                  CREATE TABLE messages (id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER, data BLOB);";
    let yaml_format = make(
        "yaml-format.db3",
        &format!(
            "{layout} INSERT INTO topics VALUES (1, '/plan', 'nav_msgs/msg/Path', 'yaml', ''); INSERT INTO messages VALUES (1, 1, 5, x'00');"
        ),
    );
    let e = read_bag(&yaml_format, &topics()).expect_err("yaml");
    assert!(e.to_string().contains("serialization format `yaml`"), "{e}");
    let negative = make(
        "negative.db3",
        &format!(
            "{layout} INSERT INTO topics VALUES (1, '/plan', 'nav_msgs/msg/Path', 'cdr', ''); INSERT INTO messages VALUES (1, 1, -5, x'00');"
        ),
    );
    let e = read_bag(&negative, &topics()).expect_err("negative time");
    assert!(e.to_string().contains("negative timestamp -5"), "{e}");
    let text_data = make(
        "text-data.db3",
        &format!(
            "{layout} INSERT INTO topics VALUES (1, '/plan', 'nav_msgs/msg/Path', 'cdr', ''); INSERT INTO messages VALUES (1, 1, 5, 'not a blob');"
        ),
    );
    let report = check_bag_file(&text_data, &BagCheckOptions::default());
    assert!(report.is_err(), "a text cell is no CDR message");
}

#[test]
fn plans_without_a_costmap_or_with_a_bad_update_are_reported() {
    let plan = msg("/plan", "nav_msgs/msg/Path", 5, path_msg(&[[1.0, 1.0], [1.5, 1.0]]));
    let bag = Bag { files: Vec::new(), messages: vec![plan.clone()] };
    let report = check_bag(&bag, &BagCheckOptions::default()).expect("checked");
    assert_eq!(report.plans[0].violations, vec![PathViolation::NoCostmap]);
    assert_eq!(report.summary.failed, 1);

    let empty_plan = msg("/plan", "nav_msgs/msg/Path", 6, path_msg(&[]));
    let map = msg("/map", "nav_msgs/msg/OccupancyGrid", 1, grid(10, 10, &[0; 100]));
    let bag = Bag { files: Vec::new(), messages: vec![map.clone(), empty_plan] };
    let report = check_bag(&bag, &BagCheckOptions::default()).expect("checked");
    assert_eq!(report.plans[0].violations, vec![PathViolation::EmptyPath]);

    let mut update = Cdr::new();
    update.header("map").i32(8).i32(8).u32(5).u32(5).bytes(&[0; 25]);
    let update = msg(
        "/global_costmap/costmap_updates",
        "map_msgs/msg/OccupancyGridUpdate",
        3,
        update.payload(),
    );
    let mut costmap = map.clone();
    costmap.topic = "/global_costmap/costmap".into();
    let bag = Bag { files: Vec::new(), messages: vec![costmap, update] };
    let e = check_bag(&bag, &BagCheckOptions::default()).expect_err("update outside the map");
    assert!(e.to_string().contains("an update outside the costmap"), "{e}");
}

fn costmap_msg(topic: &str, type_name: &str, log_time: u64, cells: &[u8]) -> BagMessage {
    let data = if type_name == "nav2_msgs/msg/Costmap" {
        let mut c = Cdr::new();
        c.header("map").i32(0).u32(0).i32(0).u32(0).string("master").f32(1.0).u32(10).u32(10);
        c.pose(IDENTITY).bytes(cells);
        c.payload()
    } else {
        grid(10, 10, cells)
    };
    msg(topic, type_name, log_time, data)
}

/// A straight plan across the middle row of a 10 × 10 map with 1 m cells.
fn straight_plan(log_time: u64) -> BagMessage {
    let line: Vec<[f64; 2]> = (0..15).map(|i| [1.0 + 0.5 * i as f64, 5.0]).collect();
    msg("/plan", "nav_msgs/msg/Path", log_time, path_msg(&line))
}

#[test]
fn costmap_updates_and_the_raw_costmap_are_in_force_when_the_plan_is_recorded() {
    let opts = BagCheckOptions { replay: ReplayMode::Off, ..BagCheckOptions::default() };
    let free = [0u8; 100];
    let costmap = costmap_msg("/global_costmap/costmap", "nav_msgs/msg/OccupancyGrid", 1, &free);
    // an update puts a wall (translated value 100 = lethal) across column 5, rows 3..8
    let mut wall = Cdr::new();
    wall.header("map").i32(5).i32(3).u32(1).u32(5).bytes(&[100; 5]);
    let update = msg(
        "/global_costmap/costmap_updates",
        "map_msgs/msg/OccupancyGridUpdate",
        2,
        wall.payload(),
    );
    let before = straight_plan(1);
    let after = straight_plan(3);
    let bag = Bag { files: Vec::new(), messages: vec![costmap, before, update, after] };
    let report = check_bag(&bag, &opts).expect("checked");
    assert!(report.plans[0].violations.is_empty(), "{:?}", report.plans[0].violations);
    let v = &report.plans[1].violations;
    assert!(v.iter().any(|x| matches!(x, PathViolation::PoseInObstacle { .. })), "{v:?}");
    let used = report.plans[1].costmap.as_ref().expect("costmap");
    assert_eq!((used.kind, used.log_time, used.exact), (CostmapKind::Translated, 2, true));

    // a map with the wall, then the raw costmap without it: the raw costmap is in force
    let mut walled = [0u8; 100];
    for row in 3..8 {
        walled[row * 10 + 5] = 100;
    }
    let map = costmap_msg("/map", "nav_msgs/msg/OccupancyGrid", 1, &walled);
    let raw = costmap_msg("/global_costmap/costmap_raw", "nav2_msgs/msg/Costmap", 2, &free);
    let bag = Bag { files: Vec::new(), messages: vec![map.clone(), straight_plan(3)] };
    let report = check_bag(&bag, &opts).expect("checked");
    assert!(!report.plans[0].violations.is_empty(), "the map's wall is in force");
    let bag = Bag { files: Vec::new(), messages: vec![map, raw, straight_plan(3)] };
    let report = check_bag(&bag, &opts).expect("checked");
    assert!(report.plans[0].violations.is_empty(), "{:?}", report.plans[0].violations);
    assert_eq!(report.plans[0].costmap.as_ref().map(|c| c.kind), Some(CostmapKind::Raw));
}
