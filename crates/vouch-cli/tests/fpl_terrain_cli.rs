//! Upstream's terrain checks as `vouch fpl compile` shows them: the `No SRTM data found` line
//! (upstream's own with `--upstream-compat`, a `-v` note otherwise) and the `MAJOR NOTICE`
//! warning when a tile puts the ground above the plan. Needs `../shared` (vouch-testkit).

mod common;

use common::vouch;
use std::path::{Path, PathBuf};
use std::process::Output;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// The check cases and the reference Paparazzi home.
fn shared() -> Option<(PathBuf, PathBuf)> {
    let cases = vouch_testkit::shared("fpl/upstream/check_cases", "CASES.tsv")?;
    let home = vouch_testkit::shared("fpl/paparazzi_home", "data/srtm/WW15MGH.DAC.bz2")?;
    Some((cases, home))
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fpl_terrain_cli");
    std::fs::create_dir_all(&dir).expect("tmp dir");
    dir.join(name)
}

#[test]
fn without_a_tile_upstream_compat_prints_upstreams_line() {
    let Some((cases, home)) = shared() else { return };
    let plan = cases.join("c_valid.xml");
    let out = tmp("valid.h");
    let run = |extra: &[&str]| {
        let mut args =
            vec!["fpl", "compile", s(&plan), "--paparazzi-home", s(&home), "-o", s(&out)];
        args.extend_from_slice(extra);
        let o = vouch(&args);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        stderr(&o)
    };
    assert_eq!(run(&["--upstream-compat"]), "No SRTM data found to check altitude.\n");
    assert_eq!(run(&[]), "", "no terrain note by default");
    let verbose = run(&["-v"]);
    assert!(verbose.contains("no SRTM tile N43E001 (searched "), "{verbose}");
    assert!(!verbose.contains("No SRTM data found"));
    // -q silences it, as every note.
    let o = vouch(&[
        "-q",
        "fpl",
        "compile",
        s(&plan),
        "--paparazzi-home",
        s(&home),
        "--upstream-compat",
        "-o",
        s(&out),
    ]);
    assert_eq!(stderr(&o), "");
}

#[test]
fn the_line_is_the_first_of_upstreams_stderr_for_a_corpus_plan() {
    let Some((_, home)) = shared() else { return };
    let Some(corpus) = vouch_testkit::shared("fpl/corpus", "INDEX.tsv") else { return };
    let Some(upstream) = vouch_testkit::shared("fpl/upstream/headers", "basic.stderr") else {
        return;
    };
    let out = tmp("basic.h");
    let o = vouch(&[
        "fpl",
        "compile",
        s(&corpus.join("basic.xml")),
        "--paparazzi-home",
        s(&home),
        "--upstream-compat",
        "--message-format",
        "short",
        "-o",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let expected = std::fs::read_to_string(upstream.join("basic.stderr")).expect("stderr file");
    let first = |t: &str| t.lines().next().unwrap_or_default().to_string();
    assert_eq!(first(&stderr(&o)), first(&expected));
    assert_eq!(first(&expected), "No SRTM data found to check altitude.");
}

#[test]
fn a_tile_above_the_plan_gives_upstreams_major_notice() {
    let Some((cases, shared_home)) = shared() else { return };
    let home = tmp("home_tile");
    let _ = std::fs::remove_dir_all(&home);
    std::fs::create_dir_all(home.join("conf")).expect("tmp");
    std::fs::create_dir_all(home.join("data/srtm")).expect("tmp");
    for f in ["conf/abi.xml", "data/srtm/WW15MGH.DAC.bz2"] {
        std::fs::copy(shared_home.join(f), home.join(f)).expect("copy");
    }
    let tile = 1000i16.to_be_bytes().repeat(1201 * 1201);
    std::fs::write(home.join("data/srtm/N43E001.hgt"), tile).expect("tile");
    let out = tmp("below.h");
    let o = vouch(&[
        "--message-format",
        "short",
        "fpl",
        "compile",
        s(&cases.join("c_srtm_below.xml")),
        "--paparazzi-home",
        s(&home),
        "--upstream-compat",
        "-o",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains(
            "c_srtm_below.xml:2:19: warning[fpl::W027]: MAJOR NOTICE: below SRTM ground altitude \
             (260<1000) in <flight_plan SECURITY_HEIGHT=\"25\" NAME=\"T\""
        ),
        "{err}"
    );
    assert_eq!(err.matches("fpl::W027").count(), 5, "{err}");
    assert!(!err.contains("No SRTM data found"));
}
