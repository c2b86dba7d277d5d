//! Map readers: the nav2 maps load like map_server + static layer would (compared with the
//! independently built `suite_ros` costmaps), and bad maps get clear, located errors.

mod common;

use std::path::Path;

use vouch_navfn::maps::{MapError, load_ros_map, parse_map_yaml, parse_suite_text, pgm::parse_pgm};

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
    let tmp = tempfile::tempdir().expect("temp dir");
    let dir = tmp.path();
    let yaml = dir.join("room.yaml");
    std::fs::write(&yaml, format!("image: empty.pgm\n{REST}")).expect("written");
    let err = load_ros_map(&yaml, true).unwrap_err();
    assert!(err.is_io(), "{err}");
    assert!(err.to_string().contains("empty.pgm"), "{err}");
    assert_eq!(err.path(), dir.join("empty.pgm"));
}

/// Everything map_server requires besides `image:`.
const REST: &str =
    "resolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";

fn yaml_err(text: &str) -> String {
    parse_map_yaml(Path::new("m.yaml"), text).unwrap_err().located()
}

#[test]
fn syntax_errors_point_at_the_field() {
    let text = format!("image: m.pgm\n{}", REST.replace("0.05", "fast"));
    let err = parse_map_yaml(Path::new("m.yaml"), &text).unwrap_err();
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
    let with = |key: &str, value: &str| {
        let mut t = String::from("image: m.pgm\n");
        for l in REST.lines() {
            if l.starts_with(key) {
                t.push_str(&format!("{key}: {value}\n"));
            } else {
                t.push_str(l);
                t.push('\n');
            }
        }
        t
    };
    assert!(yaml_err(&with("resolution", "0")).contains("m.yaml:2: resolution 0 must be"));
    assert!(yaml_err(&with("resolution", ".inf")).contains("m.yaml:2: resolution inf"));
    assert!(
        yaml_err(&with("origin", "[1, 2]")).contains("m.yaml:3: origin should have 3 elements")
    );
    assert!(yaml_err(&with("origin", "[1, x, 0]")).contains("m.yaml:3: origin element `x`"));
    assert!(yaml_err(&with("negate", "2.5")).contains("m.yaml:4: negate must be an integer"));
    assert!(
        yaml_err(&with("free_thresh", "low")).contains("m.yaml:6: free_thresh must be a number")
    );
    assert!(
        yaml_err(&format!("image: m.pgm\n{REST}mode: fancy\n"))
            .contains("m.yaml:7: mode must be trinary, scale or raw")
    );
    assert!(yaml_err(REST).contains("m.yaml:1: missing `image:`"));
    assert!(yaml_err(&format!("image: ''\n{REST}")).contains("the image tag is empty"));
    assert!(yaml_err("image: [m.pgm\n").contains("m.yaml:"));
    assert!(yaml_err("- a\n- b\n").contains("must be a mapping"));
}

#[test]
fn yaml_that_map_server_accepts_is_accepted() {
    // a document start, block-style origin, comments, yaml-cpp's booleans and integer bases,
    // mode in capitals, thresholds without range checks (map_server checks none)
    let text = "%YAML 1.2\n---\n# map\nimage: \"a.pgm\"\nresolution: 5e-2\norigin:\n  - -10\n  - -10.5\n  - 0.0\nnegate: Yes\nmode: SCALE\noccupied_thresh: 0.99\nfree_thresh: 0.01\nmap_type: occupancy\n...\n";
    let m = parse_map_yaml(Path::new("m.yaml"), text).unwrap();
    assert!(m.negate);
    assert_eq!(m.mode, vouch_navfn::maps::MapMode::Scale);
    assert_eq!(m.origin, [-10.0, -10.5, 0.0]);
    assert_eq!(m.resolution, 0.05);
    assert_eq!((m.occupied_thresh, m.free_thresh), (0.99, 0.01));
    let flow = "{image: b.png, resolution: 1, origin: [0, 0, 0], negate: 0x0, occupied_thresh: 0.2, free_thresh: 0.5}";
    let m = parse_map_yaml(Path::new("m.yaml"), flow).unwrap();
    assert!(!m.negate);
    assert_eq!((m.occupied_thresh, m.free_thresh), (0.2, 0.5));
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
    assert!(
        suite_err("3 3\nmap.bin\n\n1 1 1 1\n", vec![50; 8])
            .contains("map has 8 bytes, but t/test.txt declares 3x3 = 9")
    );
    assert!(suite_err("3 x\nmap.bin\n", vec![]).contains("t/test.txt:1: map size `x`"));
    assert!(
        suite_err("3 3\nmap.bin\n\n1 1 1\n", vec![50; 9])
            .contains("t/test.txt:4: expected `x0 y0 x1 y1`")
    );
    assert!(
        suite_err("3 3\nmap.bin\n\n1 1 nan 1\n", vec![50; 9])
            .contains("t/test.txt:4: `nan` is not a finite number")
    );
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

/// Writes `yaml` and `image` into a fresh folder and loads the map.
fn load_pair(tag: &str, yaml: &str, image_name: &str, image: &[u8]) -> vouch_navfn::maps::RosMap {
    let tmp = tempfile::Builder::new().prefix(tag).tempdir().expect("temp dir");
    let dir = tmp.path();
    std::fs::write(dir.join(image_name), image).expect("image written");
    std::fs::write(dir.join("m.yaml"), yaml).expect("yaml written");
    load_ros_map(&dir.join("m.yaml"), true).unwrap_or_else(|e| panic!("{e}"))
}

fn meta(mode: &str, negate: u8, occ: f64, free: f64) -> String {
    format!(
        "image: i.pgm\nresolution: 1\norigin: [0, 0, 0]\nnegate: {negate}\nmode: {mode}\noccupied_thresh: {occ}\nfree_thresh: {free}\n"
    )
}

#[test]
fn map_server_modes_convert_pixels_as_nav2_does() {
    // one row; values worked out by hand from map_server's float formulas
    let pgm = b"P2\n6 1\n255\n0 255 205 89 90 128\n";
    let tri = load_pair("tri", &meta("trinary", 0, 0.65, 0.196), "i.pgm", pgm);
    // 205 → 1 − 205/255 = 0.19608 > 0.196: unknown; 89 → 0.65098 ≥ 0.65: occupied
    assert_eq!(tri.occupancy, vec![100, 0, -1, 100, -1, -1]);
    assert_eq!(tri.costmap, vec![254, 0, 255, 254, 255, 255]);
    let neg = load_pair("neg", &meta("trinary", 1, 0.65, 0.196), "i.pgm", pgm);
    assert_eq!(neg.occupancy, vec![0, 100, 100, -1, -1, -1]);
    let scale = load_pair(
        "scale",
        &meta("scale", 0, 0.99, 0.01),
        "i.pgm",
        b"P2\n4 1\n255\n0 255 128 250\n",
    );
    // 128 → (0.498039 − 0.01) / 0.98 · 100 = 49.8 → 50; 250 → 0.98 → 1
    assert_eq!(scale.occupancy, vec![100, 0, 50, 1]);
    let raw =
        load_pair("raw", &meta("raw", 0, 0.65, 0.196), "i.pgm", b"P2\n4 1\n255\n0 100 101 255\n");
    assert_eq!(raw.occupancy, vec![0, 100, -1, -1]);
    // rows are flipped: row 0 of the grid is the bottom row of the image
    let two_rows =
        load_pair("rows", &meta("trinary", 0, 0.65, 0.196), "i.pgm", b"P2\n1 2\n255\n0\n255\n");
    assert_eq!(two_rows.occupancy, vec![0, 100]);
    // a 16-bit PGM is read through ImageMagick's 8-bit export: 65535 → 255, 0 → 0
    let wide =
        load_pair("wide", &meta("trinary", 0, 0.65, 0.196), "i.pgm", b"P2\n2 1\n65535\n0 65535\n");
    assert_eq!(wide.occupancy, vec![100, 0]);
}

#[test]
fn transparent_png_pixels_are_unknown_in_trinary_and_scale_modes() {
    let mut png_bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut png_bytes, 3, 1);
        enc.set_color(png::ColorType::GrayscaleAlpha);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().unwrap();
        // white opaque, white half transparent, black opaque
        w.write_image_data(&[255, 255, 255, 128, 0, 255]).unwrap();
    }
    for mode in ["trinary", "scale"] {
        let yaml = meta(mode, 0, 0.65, 0.196).replace("i.pgm", "i.png");
        let m = load_pair(mode, &yaml, "i.png", &png_bytes);
        assert_eq!(m.occupancy, vec![0, -1, 100], "{mode}");
    }
    let raw = load_pair(
        "rawpng",
        &meta("raw", 0, 0.65, 0.196).replace("i.pgm", "i.png"),
        "i.png",
        &png_bytes,
    );
    assert_eq!(raw.occupancy, vec![-1, -1, 0], "raw mode ignores alpha");
}
