//! Map readers: the nav2 maps load like map_server + static layer would (compared with the
//! independently built `suite_ros` costmaps), and bad maps get clear, located errors.

mod common;

use std::path::Path;

use vouch_navfn::maps::{load_ros_map, parse_map_yaml, parse_suite_text, pgm::parse_pgm, MapError};

#[test]
fn nav2_400x400_map_equals_suite_ros_costmap() {
    let Some(shared) = common::shared_navfn() else { return };
    let map = load_ros_map(&shared.join("nav2_maps/map.pgm"), true).expect("map.pgm loads");
    let reference = std::fs::read(shared.join("suite_ros/400x400_ros/map.bin")).unwrap();
    assert_eq!((map.width, map.height), (400, 400));
    assert_eq!(map.costmap, reference, "no inflation on this map: bytes must be identical");
}

#[test]
fn nav2_maps_agree_with_suite_ros_on_lethal_and_unknown_cells() {
    let Some(shared) = common::shared_navfn() else { return };
    for (image, yaml) in [
        ("empty_room.pgm", None),
        ("keepout_mask.pgm", Some("keepout_mask.yaml")),
        ("map_circular.pgm", Some("map_circular.yaml")),
        ("speed_mask.pgm", Some("speed_mask.yaml")),
    ] {
        let path = shared.join("nav2_maps").join(yaml.unwrap_or(image));
        let map = load_ros_map(&path, true).unwrap_or_else(|e| panic!("{e}"));
        let stem = image.trim_end_matches(".pgm");
        let reference = std::fs::read(shared.join("suite_ros").join(stem).join("map.bin")).unwrap();
        assert_eq!(map.costmap.len(), reference.len(), "{stem}");
        for (i, (&ours, &theirs)) in map.costmap.iter().zip(&reference).enumerate() {
            // inflation (not modelled here) raises free cells to 1..=253 and overwrites
            // unknown cells within the inscribed radius (nav2 InflationLayer, inflate_unknown off)
            let ok = match ours {
                254 => theirs == 254,
                255 => theirs >= 253,
                _ => theirs <= 253,
            };
            assert!(ok, "{stem} cell {i}: ours {ours}, suite_ros {theirs}");
        }
    }
}

#[test]
fn yaml_naming_a_missing_image_is_an_io_error_naming_the_image() {
    let dir = std::env::temp_dir().join(format!("vouch-missing-image-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let yaml = dir.join("room.yaml");
    std::fs::write(&yaml, "image: empty.pgm\nresolution: 0.1\n").expect("written");
    let err = load_ros_map(&yaml, true).unwrap_err();
    assert!(err.is_io(), "{err}");
    assert!(err.to_string().contains("empty.pgm"), "{err}");
    assert_eq!(err.path(), dir.join("empty.pgm"));
    let _ = std::fs::remove_dir_all(&dir);
}

fn yaml_err(text: &str) -> String {
    parse_map_yaml(Path::new("m.yaml"), text).unwrap_err().located()
}

#[test]
fn syntax_errors_point_at_the_field() {
    let text = "image: m.pgm\nresolution: fast\n";
    let err = parse_map_yaml(Path::new("m.yaml"), text).unwrap_err();
    let MapError::Syntax(e) = &err else { panic!("{err:?}") };
    assert_eq!(e.line, 2);
    assert_eq!(&text[e.span.offset()..e.span.offset() + e.span.len()], "fast");
    assert_eq!(
        miette::Diagnostic::code(&err).map(|c| c.to_string()).as_deref(),
        Some("navfn::E011")
    );
}

#[test]
fn bad_yaml_values_are_rejected_with_line_numbers() {
    let base = "image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
    assert!(yaml_err(&format!("{base}occupied_thresh: 1.5\n"))
        .contains("m.yaml:4: occupied_thresh 1.5 is outside [0, 1]"));
    assert!(yaml_err(&format!("{base}free_thresh: -0.1\n")).contains("m.yaml:4: free_thresh"));
    assert!(
        yaml_err("image: m.pgm\nresolution: 0\n").contains("m.yaml:2: resolution 0 must be > 0")
    );
    assert!(
        yaml_err(&format!("{base}mode: fancy\n")).contains("mode must be trinary, scale or raw")
    );
    assert!(yaml_err("image: m.pgm\nresolution: 1\norigin: [1, 2]\n")
        .contains("m.yaml:3: origin must be"));
    assert!(yaml_err("resolution: 1\n").contains("missing `image:`"));
    assert!(yaml_err(&format!("{base}occupied_thresh: 0.2\nfree_thresh: 0.5\n"))
        .contains("exceeds occupied_thresh"));
    assert!(yaml_err(&format!("{base}negate: 2\n")).contains("negate must be 0 or 1"));
}

#[test]
fn yaml_modes_and_negate_parse() {
    let m = parse_map_yaml(Path::new("m.yaml"), "image: a.pgm\nresolution: 0.05\norigin: [-10.0, -10.0, 0.0]\nnegate: 1\nmode: scale\noccupied_thresh: 0.99\nfree_thresh: 0.01\n").unwrap();
    assert!(m.negate);
    assert_eq!(m.mode, vouch_navfn::maps::MapMode::Scale);
    assert_eq!(m.origin, [-10.0, -10.0, 0.0]);
    assert_eq!((m.occupied_thresh, m.free_thresh), (0.99, 0.01));
}

#[test]
fn bad_pgm_files_are_rejected() {
    let p = Path::new("x.pgm");
    let e = parse_pgm(p, b"P5\n4 4\n255\n\x00\x01").unwrap_err().to_string();
    assert!(e.contains("truncated PGM: 4x4 needs 16 data bytes, found 2"), "{e}");
    let e = parse_pgm(p, b"P6\n1 1\n255\n\x00\x00\x00").unwrap_err().to_string();
    assert!(e.contains("not a PGM image"), "{e}");
    let e = parse_pgm(p, b"P5\n1 1\n70000\n\x00").unwrap_err().to_string();
    assert!(e.contains("maxval 70000"), "{e}");
    let e = parse_pgm(p, b"P2\n2 1\n255\n3\n").unwrap_err().to_string();
    assert!(e.contains("2 samples expected, found 1"), "{e}");
    let e = parse_pgm(p, b"P2\n1 1\n10\n11\n").unwrap_err().to_string();
    assert!(e.contains("exceeds maxval"), "{e}");
    let e = parse_pgm(p, b"P5\n0 3\n255\n").unwrap_err().to_string();
    assert!(e.contains("empty"), "{e}");
    let ok = parse_pgm(p, b"P2\n# comment\n2 1\n255\n0 255\n").unwrap();
    assert_eq!(ok.pixels, vec![0, 255]);
}

fn suite_err(text: &str, map: Vec<u8>) -> String {
    parse_suite_text(Path::new("t/test.txt"), text, |_| Ok(map)).unwrap_err().located()
}

#[test]
fn bad_suite_files_are_rejected() {
    assert!(suite_err("3 3\nmap.bin\n\n1 1 1 1\n", vec![50; 8])
        .contains("map has 8 bytes, but t/test.txt declares 3x3 = 9"));
    assert!(suite_err("3 x\nmap.bin\n", vec![]).contains("t/test.txt:1: map size `x`"));
    assert!(suite_err("3 3\nmap.bin\n\n1 1 1\n", vec![50; 9])
        .contains("t/test.txt:4: expected `x0 y0 x1 y1`"));
    assert!(suite_err("3 3\nmap.bin\n\n1 1 nan 1\n", vec![50; 9])
        .contains("t/test.txt:4: `nan` is not a finite number"));
    assert!(suite_err("", vec![]).contains("empty test file"));
    let ok =
        parse_suite_text(Path::new("t/test.txt"), "3 3\nmap.bin\n\n-1 comment\n1 1 1 2\n", |_| {
            Ok(vec![50; 9])
        })
        .unwrap();
    assert_eq!(ok.cases.len(), 1);
    assert_eq!(ok.cases[0].line, 5);
    // a case outside the map is detected when its cells are taken
    let out =
        parse_suite_text(Path::new("t/test.txt"), "3 3\nmap.bin\n\n1 1 3 1\n", |_| Ok(vec![50; 9]))
            .unwrap();
    assert!(out.cases[0].cells(3, 3).is_none());
}
