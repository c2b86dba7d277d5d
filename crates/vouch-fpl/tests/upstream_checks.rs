//! Every upstream check (UPSTREAM_CHECKS.md) against upstream's recorded answer: each of the
//! one-check plans in `../shared/fpl/upstream/check_cases/` is compiled as `vouch fpl compile`
//! does (front end, passes, header with upstream's notices) with the reference Paparazzi home,
//! and vouch's outcome is compared with what upstream's `gen_aircraft` did
//! (`CASES.tsv`, column `rc_gen_aircraft_header`, and its stderr):
//! * upstream rejected (exit 1 or 2) → vouch rejects, with a located error and a stable code;
//! * upstream warned (a NOTICE or warning on stderr) → vouch accepts with a warning;
//! * upstream accepted silently → vouch accepts;
//!
//! except the documented cases where vouch is stricter ([`STRICTER`]), which vouch rejects.
//! The settings cases are checked on the settings step, the environment cases with a
//! Paparazzi home made for them.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use vouch_fpl::diag::Diagnostic;
use vouch_fpl::emit::settings::settings;
use vouch_fpl::emit::{EmitOptions, compile_plan_full};
use vouch_fpl::front::parse_file;

/// Cases upstream accepts where vouch rejects: upstream's C would be wrong, or the plan would
/// silently mean something else (docs/fpl-compiler.md, "Stricter than upstream").
const STRICTER: [(&str, &str); 12] = [
    ("blocks_300", "301 blocks: block numbers are uint8_t in C"),
    ("for_big", "a for bound beyond int8_t wraps: the loop runs zero times"),
    ("wp_dup", "duplicate waypoint names: two WP_ defines, lookups silently take the first"),
    ("wp_height_nan", "a non-numeric height is silently replaced by the plan altitude"),
    ("hmh_nan", "a non-numeric home_mode_height is silently ignored"),
    ("gf_alt_nan", "a non-numeric geofence_max_alt silently disables the geofence"),
    (
        "indexofblock_while",
        "IndexOfBlock of an unknown block: the while condition silently becomes TRUE",
    ),
    ("indexofblock_alt", "IndexOfBlock of an unknown block: the alt attribute is silently dropped"),
    ("gf_sector_unknown", "InsideNowhere(): a function no sector defines, the C fails to build"),
    ("stay_glide", "NavGlide(, wp): not valid C"),
    ("stay_route_nodtd", "NavSegment(, wp): not valid C"),
    ("goto_nodtd", "an internal <goto> jumps to a label that may not exist"),
];

/// Cases checked on the settings step instead of the header.
const SETTINGS_CASES: [&str; 5] = [
    "set_var_us",
    "set_var_ok",
    "set_handler_nodtd",
    "set_handler_both_nodtd",
    "set_persist_nodtd",
];

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Outcome {
    Reject,
    Warn,
    Accept,
}

struct Case {
    header_rc: i32,
    settings_rc: i32,
    stderr: String,
}

fn cases(dir: &Path) -> HashMap<String, Case> {
    let text = std::fs::read_to_string(dir.join("CASES.tsv")).expect("CASES.tsv");
    text.lines()
        .skip(1)
        .filter_map(|l| {
            let c: Vec<&str> = l.split('\t').collect();
            let rc = |i: usize| c.get(i).and_then(|v| v.parse().ok()).unwrap_or(0);
            Some((
                c.first()?.to_string(),
                Case {
                    header_rc: rc(2),
                    settings_rc: rc(6),
                    stderr: c.get(7).unwrap_or(&"").to_string(),
                },
            ))
        })
        .collect()
}

fn upstream_outcome(c: &Case) -> Outcome {
    match (c.header_rc, c.stderr.trim().is_empty()) {
        (0, true) => Outcome::Accept,
        (0, false) => Outcome::Warn,
        _ => Outcome::Reject,
    }
}

/// vouch's outcome and its diagnostics (errors first).
fn vouch(plan: &Path, home: &Path) -> (Outcome, Vec<Diagnostic>) {
    let p = match parse_file(plan) {
        Ok(p) => p,
        Err(d) => return (Outcome::Reject, d.items),
    };
    let opts = EmitOptions { paparazzi_home: Some(home.to_path_buf()), ..EmitOptions::default() };
    match compile_plan_full(&p, &opts) {
        Err(e) => (Outcome::Reject, e.to_diagnostics(&p.sources).items),
        Ok(out) => {
            let mut w = p.warnings.clone();
            w.extend(out.notices);
            w.extend(out.corrections);
            (if w.is_empty() { Outcome::Accept } else { Outcome::Warn }, w)
        }
    }
}

fn dirs() -> Option<(PathBuf, PathBuf)> {
    let cases = vouch_testkit::shared("fpl/upstream/check_cases", "CASES.tsv")?;
    let home = vouch_testkit::shared("fpl/paparazzi_home", "conf/abi.xml")?;
    Some((cases, home))
}

#[test]
fn every_check_case_has_upstreams_outcome_or_a_documented_stricter_one() {
    let Some((dir, home)) = dirs() else { return };
    let all = cases(&dir);
    let (mut matched, mut stricter, mut failures) = (0, 0, Vec::new());
    let mut names: Vec<&String> = all.keys().collect();
    names.sort();
    for name in names {
        let plan = dir.join(format!("c_{name}.xml"));
        if !plan.is_file() || SETTINGS_CASES.contains(&name.as_str()) {
            continue;
        }
        let up = upstream_outcome(&all[name]);
        let (ours, diags) = vouch(&plan, &home);
        let is_stricter = STRICTER.iter().any(|(n, _)| n == name);
        let ok = match (up, ours) {
            (Outcome::Reject, Outcome::Reject) => {
                let first = &diags[0];
                first.kind.code().starts_with("fpl::E")
                    && (first.line.is_some() || first.span.is_none())
            }
            (Outcome::Warn, Outcome::Warn) => true,
            (Outcome::Accept, Outcome::Accept | Outcome::Warn) => !is_stricter,
            (Outcome::Accept | Outcome::Warn, Outcome::Reject) if is_stricter => {
                stricter += 1;
                continue;
            }
            _ => false,
        };
        if ok {
            matched += 1;
        } else {
            let first = diags.first().map(Diagnostic::brief).unwrap_or_default();
            failures.push(format!("{name}: upstream {up:?}, vouch {ours:?} {first}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert_eq!(stricter, STRICTER.len(), "every documented stricter case is rejected");
    assert_eq!(matched + stricter, 128, "cases with a plan file, outside the settings ones");
}

#[test]
fn settings_cases_have_upstreams_outcome() {
    let Some((dir, _)) = dirs() else { return };
    let all = cases(&dir);
    for name in SETTINGS_CASES {
        let plan = parse_file(dir.join(format!("c_{name}.xml"))).expect("the plan parses");
        let result = settings(&plan, "v7.0_unstable");
        let upstream_rejects = all[name].settings_rc != 0;
        assert_eq!(result.is_err(), upstream_rejects, "{name}: {result:?}");
        if let Err(e) = result {
            assert!(e.span.is_some(), "{name}: located");
        }
    }
}

/// A Paparazzi home for the environment cases: `abi.xml` and the grid, each optional.
fn make_home(name: &str, abi: bool, grid: Option<&[u8]>, shared: &Path) -> PathBuf {
    let home = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("home_{name}"));
    let _ = std::fs::remove_dir_all(&home);
    std::fs::create_dir_all(home.join("conf")).expect("tmp");
    std::fs::create_dir_all(home.join("data/srtm")).expect("tmp");
    if abi {
        std::fs::copy(shared.join("conf/abi.xml"), home.join("conf/abi.xml")).expect("abi");
    }
    match grid {
        Some(g) => std::fs::write(home.join("data/srtm/WW15MGH.DAC"), g).expect("grid"),
        None if name == "noabi" => {
            let bz2 = "data/srtm/WW15MGH.DAC.bz2";
            std::fs::copy(shared.join(bz2), home.join(bz2)).map(|_| ()).expect("grid")
        }
        None => {}
    }
    home
}

#[test]
fn environment_cases_have_upstreams_outcome() {
    let Some((dir, shared)) = dirs() else { return };
    let valid = dir.join("c_valid.xml");
    // env_bz2: only the .bz2 grid (the reference home) works.
    assert_eq!(vouch(&valid, &shared).0, Outcome::Accept);
    // env_nogeoid, env_trunc, env_noabi: upstream exits 2, 2, 1.
    for (name, abi, grid) in
        [("nogeoid", true, None), ("trunc", true, Some(&[0u8; 1000][..])), ("noabi", false, None)]
    {
        let home = make_home(name, abi, grid, &shared);
        let (outcome, diags) = vouch(&valid, &home);
        assert_eq!(outcome, Outcome::Reject, "env_{name}");
        assert_eq!(diags[0].kind.code(), "fpl::E025", "env_{name}: {:?}", diags[0]);
    }
    // env_nofile.
    assert!(parse_file(dir.join("no_such_plan.xml")).is_err_and(|d| d.is_io()));
}
