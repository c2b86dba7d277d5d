//! Upstream's SRTM checks (UPSTREAM_CHECKS.md H8, H12c, A2, A3) on Paparazzi homes made for
//! them: synthetic tiles (a flat 1000 m ground) beside the reference home's geoid grid. The
//! expected texts come from upstream's run of the same check case (`CASES.tsv`,
//! `env_srtm_below`); the tile formats and broken tiles from `tests/malformed/tiles/`.

use std::io::Write;
use std::path::{Path, PathBuf};

use vouch_fpl::diag::{Diagnostic, ErrorKind};
use vouch_fpl::emit::srtm::{Sample, SearchPath};
use vouch_fpl::emit::terrain::Coverage;
use vouch_fpl::emit::{EmitOptions, Emitted, compile_plan_full};
use vouch_fpl::front::{parse_file, parse_str};

const GL3_BYTES: usize = 1201 * 1201 * 2;

/// A flat 3" tile at `metres`.
fn flat_tile(metres: i16) -> Vec<u8> {
    metres.to_be_bytes().repeat(GL3_BYTES / 2)
}

fn shared() -> Option<(PathBuf, PathBuf)> {
    let cases = vouch_testkit::shared("fpl/upstream/check_cases", "CASES.tsv")?;
    let home = vouch_testkit::shared("fpl/paparazzi_home", "data/srtm/WW15MGH.DAC.bz2")?;
    Some((cases, home))
}

/// A Paparazzi home with the reference `abi.xml` and geoid grid, and these tile files.
fn home(name: &str, shared_home: &Path, tiles: &[(&str, &[u8])]) -> PathBuf {
    let home = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("srtm_{name}"));
    let _ = std::fs::remove_dir_all(&home);
    std::fs::create_dir_all(home.join("conf")).expect("tmp");
    std::fs::create_dir_all(home.join("data/srtm")).expect("tmp");
    for f in ["conf/abi.xml", "data/srtm/WW15MGH.DAC.bz2"] {
        std::fs::copy(shared_home.join(f), home.join(f)).expect("copy");
    }
    for (file, bytes) in tiles {
        std::fs::write(home.join("data/srtm").join(file), bytes).expect("tile");
    }
    home
}

fn compile(plan: &vouch_fpl::ast::FlightPlan, home: &Path) -> Result<Emitted, Vec<Diagnostic>> {
    let opts = EmitOptions { paparazzi_home: Some(home.to_path_buf()), ..EmitOptions::default() };
    compile_plan_full(plan, &opts).map_err(|e| e.to_diagnostics(&plan.sources).items)
}

fn below(e: &Emitted) -> Vec<&Diagnostic> {
    e.notices.iter().filter(|d| d.kind == ErrorKind::BelowTerrain).collect()
}

/// Upstream's recorded stderr of a check case (its first 240 characters).
fn upstream_stderr(cases: &Path, name: &str) -> String {
    let tsv = std::fs::read_to_string(cases.join("CASES.tsv")).expect("CASES.tsv");
    let row = tsv.lines().find(|l| l.starts_with(&format!("{name}\t"))).expect("case row");
    let text = row.split('\t').nth(7).expect("stderr column");
    text.strip_suffix("...").unwrap_or(text).to_string()
}

#[test]
fn env_srtm_below_prints_upstreams_major_notice() {
    let Some((cases, shared_home)) = shared() else { return };
    let plan = parse_file(cases.join("c_srtm_below.xml")).expect("parses");
    let with_tile = home("below", &shared_home, &[("N43E001.hgt", &flat_tile(1000))]);
    let e = compile(&plan, &with_tile).expect("accepted, as upstream (exit 0)");
    let expected = upstream_stderr(&cases, "env_srtm_below");
    assert_eq!(expected.chars().count(), 240, "CASES.tsv cuts at 240 characters");
    let notices = below(&e);
    assert!(notices[0].message.starts_with(&expected), "{}\n{expected}", notices[0].message);
    // The dummy waypoint, HOME, A (plan altitude 260) and B (300) are below 1000 m too.
    let alts: Vec<&str> = notices.iter().map(|d| &d.message[41..51]).collect();
    assert_eq!(alts, ["(260<1000)", "(260<1000)", "(260<1000)", "(260<1000)", "(300<1000)"]);
    assert!(notices[1].message.ends_with(" in <waypoint name=\"dummy\" x=\"0.\" y=\"0.\"/>"));
    assert!(
        notices[4].message.ends_with(" in <waypoint Y=\"50\" X=\"-100\" NAME=\"B\" ALT=\"300\"/>")
    );
    assert!(notices.iter().all(|d| d.line.is_some()), "located");
    assert_eq!(e.terrain, Coverage::Tile(with_tile.join("data/srtm/N43E001.hgt")));
    // The header does not depend on the terrain.
    let without = compile(&plan, &shared_home).expect("accepted");
    assert_eq!(e.header, without.header);
    assert_eq!(
        without.terrain,
        Coverage::NoTile {
            name: "N43E001".into(),
            searched: SearchPath::of_home(Some(&shared_home)).searched().to_vec(),
        }
    );
    assert!(below(&without).is_empty());
}

const CRAFTED: &str = r#"<flight_plan name="t" lat0="43.46223" lon0="1.27289" alt="1100" ground_alt="185" security_height="25" max_dist_from_home="100000">
<waypoints>
<waypoint name="HOME" x="0" y="0"/>
<waypoint name="A" x="100" y="50" alt="900"/>
<waypoint name="B" x="-100" y="50" alt="1000"/>
<waypoint name="C" lat="44.5" lon="1.3" height="700"/>
</waypoints>
<blocks><block name="b"><go wp="A"/></block></blocks></flight_plan>"#;

#[test]
fn only_waypoints_strictly_below_the_terrain_are_reported() {
    let Some((_, shared_home)) = shared() else { return };
    let plan = parse_str("t.xml", CRAFTED).expect("parses");
    let h = home("waypoint", &shared_home, &[("N43E001.hgt", &flat_tile(1000))]);
    let e = compile(&plan, &h).expect("accepted");
    let notices = below(&e);
    // The plan (1100), dummy, HOME, B (1000: not strictly below) pass; C is in N44E001 (none).
    assert_eq!(notices.len(), 1, "{notices:?}");
    assert_eq!(
        notices[0].message,
        "MAJOR NOTICE: below SRTM ground altitude (900<1000) in <waypoint name=\"A\" x=\"100\" \
         y=\"50\" alt=\"900\"/>"
    );
    assert_eq!(notices[0].line, Some(4));
    // C's tile, present and lower than C: the quoted element is the localised waypoint.
    let h = home("waypoint_c", &shared_home, &[("N44E001.hgt", &flat_tile(1000))]);
    let e = compile(&plan, &h).expect("accepted");
    let notices = below(&e);
    assert_eq!(notices.len(), 1, "{notices:?}");
    assert!(
        notices[0].message.starts_with(
            "MAJOR NOTICE: below SRTM ground altitude (885<1000) in <waypoint name=\"C\" lat=\"44.5\" lon=\"1.3\" height=\"700\" x=\""
        ),
        "{}",
        notices[0].message
    );
    assert!(matches!(e.terrain, Coverage::NoTile { .. }));
}

#[test]
fn an_unreadable_tile_stops_at_the_reference_and_is_a_warning_at_a_waypoint() {
    let Some((_, shared_home)) = shared() else { return };
    let plan = parse_str("t.xml", CRAFTED).expect("parses");
    let short = &flat_tile(1000)[..1000];
    // At the reference upstream stops (End_of_file): a located fpl::E025.
    let h = home("short_ref", &shared_home, &[("N43E001.hgt", short)]);
    let err = compile(&plan, &h).expect_err("rejected");
    assert_eq!(err[0].kind.code(), "fpl::E025");
    assert_eq!(err[0].line, Some(1));
    assert!(err[0].message.contains("N43E001.hgt") && err[0].message.contains("1000 bytes"));
    // At a waypoint upstream skips the check: a warning, once.
    let h = home("short_wp", &shared_home, &[("N44E001.hgt", short)]);
    let e = compile(&plan, &h).expect("accepted");
    let unchecked: Vec<_> =
        e.notices.iter().filter(|d| d.kind == ErrorKind::TerrainUnchecked).collect();
    assert_eq!(unchecked.len(), 1);
    assert!(unchecked[0].message.contains("waypoint 'C'"), "{}", unchecked[0].message);
}

#[test]
fn the_southernmost_half_row_of_a_tile_is_not_checked() {
    let Some((_, shared_home)) = shared() else { return };
    // 43.0001°N: upstream's row index falls past the tile (it stops there with
    // "index out of bounds"); vouch checks nothing at the reference.
    let xml = CRAFTED
        .replace("lat0=\"43.46223\"", "lat0=\"43.0001\"")
        .replace("alt=\"1100\"", "alt=\"300\"");
    let plan = parse_str("t.xml", &xml).expect("parses");
    let h = home("off_tile", &shared_home, &[("N43E001.hgt", &flat_tile(1000))]);
    let e = compile(&plan, &h).expect("accepted");
    assert_eq!(e.terrain, Coverage::OffTile(h.join("data/srtm/N43E001.hgt")));
    assert!(!below(&e).iter().any(|d| d.message.contains("<flight_plan")));
}

fn rad(deg: f64) -> f64 {
    vouch_fpl::emit::geo::rad_of_deg(deg)
}

fn sample_in(dir: &Path) -> Sample {
    SearchPath::dirs(vec![dir.to_path_buf()]).sample(rad(43.46223), rad(1.27289))
}

/// `bytes` as the first member of a zip archive (deflated or stored).
fn zip(name: &str, bytes: &[u8], deflate: bool) -> Vec<u8> {
    let data = if deflate {
        let mut z = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::fast());
        z.write_all(bytes).expect("deflate");
        z.finish().expect("deflate")
    } else {
        bytes.to_vec()
    };
    let mut out = b"PK\x03\x04\x14\x00\x00\x00".to_vec();
    out.extend_from_slice(&(if deflate { 8u16 } else { 0u16 }).to_le_bytes());
    out.extend_from_slice(&[0; 8]); // time, date, crc
    out.extend_from_slice(&(data.len() as u32).to_le_bytes());
    out.extend_from_slice(&(bytes.len() as u32).to_le_bytes());
    out.extend_from_slice(&(name.len() as u16).to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes());
    out.extend_from_slice(name.as_bytes());
    out.extend_from_slice(&data);
    out
}

#[test]
fn compressed_tiles_are_read_as_upstreams_decompressors_read_them() {
    let tile = flat_tile(1000);
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    gz.write_all(&tile).expect("gzip");
    let gz = gz.finish().expect("gzip");
    let mut bz = bzip2::write::BzEncoder::new(Vec::new(), bzip2::Compression::fast());
    bz.write_all(&tile).expect("bzip2");
    let bz = bz.finish().expect("bzip2");
    let files: [(&str, Vec<u8>); 5] = [
        ("N43E001.hgt.gz", gz.clone()),
        ("N43E001.hgt.bz2", bz),
        ("N43E001.hgt.zip", zip("N43E001.hgt", &tile, true)),
        ("N43E001.hgt.ZIP", zip("N43E001.hgt", &tile, false)),
        // gunzip goes by the content, not the name.
        ("N43E001.hgt.zip", gz),
    ];
    for (i, (file, bytes)) in files.iter().enumerate() {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("srtm_compressed_{i}"));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("tmp");
        std::fs::write(dir.join(file), bytes).expect("tile");
        match sample_in(&dir) {
            Sample::Height(h, t) => {
                assert_eq!(h, 1000.0, "{file}");
                assert_eq!(t.path, dir.join(file));
            }
            other => panic!("{file}: {other:?}"),
        }
    }
}

#[test]
fn the_one_arc_second_name_is_searched_first_and_sets_the_size() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("srtm_gl1_first");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("tmp");
    std::fs::write(dir.join("N43E001.hgt"), flat_tile(1000)).expect("tile");
    // A 3" tile under the 1" name is read as 3601×3601 samples: too short.
    std::fs::write(dir.join("N43E001.SRTMGL1.hgt"), flat_tile(1000)).expect("tile");
    std::fs::write(dir.join("N43E001.SRTMGL1.hgt.gz"), b"\x1f\x8b").expect("tile");
    match sample_in(&dir) {
        Sample::Unreadable(e) => {
            assert_eq!(e.path, dir.join("N43E001.SRTMGL1.hgt"), "no suffix before .gz");
            assert!(e.reason.contains("25934402 expected"), "{}", e.reason);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn every_malformed_tile_is_a_clear_error() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/malformed/tiles");
    let expect = std::fs::read_to_string(dir.join("EXPECT.tsv")).expect("EXPECT.tsv");
    let mut n = 0;
    for line in expect.lines().filter(|l| !l.starts_with('#') && !l.is_empty()) {
        let (case, text) = line.split_once('\t').expect("two columns");
        match sample_in(&dir.join(case)) {
            Sample::Unreadable(e) => {
                assert!(e.reason.contains(text), "{case}: {}", e.reason);
                assert!(e.path.starts_with(dir.join(case)), "{case}: names the file");
            }
            other => panic!("{case}: {other:?}"),
        }
        n += 1;
    }
    assert_eq!(n, 11);
}
