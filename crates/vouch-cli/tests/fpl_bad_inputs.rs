//! The bad-input catalogue against every `vouch fpl` subcommand that reads a plan (and
//! `aircraft`, which reads `conf.xml`): the exit code of the contract (1 rejected, 2 usage or
//! I/O), an `fpl::` code on the error in every message format, no panic, no raw control byte
//! on the terminal. The expected codes follow from the kind of input: an unreadable path is
//! I/O (`fpl::E001`), a file of zero bytes an empty plan (`fpl::E009`), anything else that is
//! not a well-formed plan malformed XML (`fpl::E002`) — control characters are not XML
//! characters.

mod bad_inputs_support;

use std::path::{Path, PathBuf};

use bad_inputs_support::{
    ESCAPES, Expect, Kind, binary_bytes, file, huge_line, io, raw_controls, rejected,
    run_catalogue, scratch,
};

fn demo() -> String {
    let p = vouch_testkit::repo_root().join("examples/fpl/demo.xml");
    std::fs::read_to_string(p).expect("the demo plan")
}

/// The catalogue's file of `kind`, as a flight plan.
fn plan_input(dir: &Path, kind: Kind) -> PathBuf {
    let demo = demo();
    match kind {
        Kind::Missing => dir.join("missing.xml"),
        Kind::Directory => {
            let d = dir.join("folder.xml");
            std::fs::create_dir_all(&d).expect("folder");
            d
        }
        Kind::Empty => file(dir, "empty.xml", b""),
        Kind::Binary => file(dir, "binary.xml", &binary_bytes()),
        Kind::Truncated => file(dir, "truncated.xml", &demo.as_bytes()[..demo.len() / 2]),
        Kind::HugeLine => file(dir, "huge.xml", &huge_line()),
        Kind::ControlInValue => {
            let text = demo.replacen("name=\"vouch demo\"", &format!("name=\"vouch{ESCAPES}\""), 1);
            assert_ne!(text, demo);
            file(dir, "control_value.xml", text.as_bytes())
        }
        Kind::ControlInName => {
            let text = demo.replacen("name=\"STDBY\"", &format!("name=\"ST{ESCAPES}DBY\""), 1);
            assert_ne!(text, demo);
            file(dir, "control_name.xml", text.as_bytes())
        }
        Kind::WrongFormat => {
            file(dir, "json.xml", br#"{"flight_plan": {"name": "demo", "blocks": []}}"#)
        }
    }
}

/// What the contract says about a bad plan of `kind`.
fn plan_expect(kind: Kind) -> Expect {
    match kind {
        Kind::Missing | Kind::Directory => io("fpl::E001"),
        Kind::Empty => rejected("fpl::E009"),
        _ => rejected("fpl::E002"),
    }
}

fn s(p: &Path) -> String {
    p.to_str().expect("utf-8 path").to_string()
}

#[test]
fn every_plan_reader_answers_every_bad_input_with_a_coded_error() {
    let dir = scratch();
    let demo = s(&vouch_testkit::repo_root().join("examples/fpl/demo.xml"));
    let mut cases = Vec::new();
    for kind in Kind::ALL {
        let p = s(&plan_input(dir.path(), kind));
        for sub in ["parse", "compile", "validate", "lint", "check", "graph", "sim"] {
            let args = vec!["fpl".to_string(), sub.to_string(), p.clone()];
            cases.push((format!("fpl {sub} {kind:?}"), args, plan_expect(kind)));
        }
        // either side of a diff
        let args = vec!["fpl".into(), "diff".into(), p.clone(), demo.clone()];
        cases.push((format!("fpl diff {kind:?} demo"), args, plan_expect(kind)));
        let args = vec!["fpl".into(), "diff".into(), demo.clone(), p.clone()];
        cases.push((format!("fpl diff demo {kind:?}"), args, plan_expect(kind)));
    }
    run_catalogue(cases);
}

#[test]
fn aircraft_answers_every_bad_conf_xml_with_a_coded_error() {
    let dir = scratch();
    let home = dir.path().join("paparazzi");
    std::fs::create_dir_all(&home).expect("home");
    let mut cases = Vec::new();
    for kind in Kind::ALL {
        let conf = s(&plan_input(dir.path(), kind));
        let args = ["fpl", "aircraft", "--name", "Demo", "--paparazzi-home", &s(&home), "--conf"]
            .iter()
            .map(|a| a.to_string())
            .chain([conf])
            .collect();
        let want = match kind {
            Kind::Missing | Kind::Directory => io("fpl::E028"),
            _ => rejected("fpl::E028"),
        };
        cases.push((format!("fpl aircraft --conf {kind:?}"), args, want));
    }
    // A Paparazzi home without conf/conf.xml: the file cannot be read, an I/O error.
    let args = ["fpl", "aircraft", "--name", "Demo", "--paparazzi-home", &s(&home)]
        .iter()
        .map(|a| a.to_string())
        .collect();
    cases.push(("fpl aircraft (home without conf.xml)".into(), args, io("fpl::E028")));
    run_catalogue(cases);
}

/// DEL and the C1 controls are XML characters, so a plan can carry them into an accepted
/// plan's names; what the commands print for people shows them escaped.
#[test]
fn names_with_del_and_c1_controls_are_printed_escaped() {
    let dir = scratch();
    let text = demo().replacen("name=\"Wait GPS\"", "name=\"Wait\u{9b}2J\u{7f}GPS\"", 1);
    let plan = s(&file(dir.path(), "c1.xml", text.as_bytes()));
    for args in [
        vec!["fpl", "parse", &plan],
        vec!["fpl", "parse", "--json", &plan],
        vec!["fpl", "lint", &plan],
        vec!["fpl", "sim", &plan, "--steps", "5"],
        vec!["fpl", "check", &plan, "--property", "never block(Standby)"],
    ] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_vouch"))
            .args(&args)
            .output()
            .expect("runs");
        let out = String::from_utf8_lossy(&o.stdout);
        assert!(matches!(o.status.code(), Some(0 | 1 | 3)), "{args:?}: {o:?}");
        for (stream, bytes) in [("stdout", &o.stdout), ("stderr", &o.stderr)] {
            let raw = raw_controls(bytes);
            assert!(raw.is_empty(), "{args:?}: raw control bytes on {stream}: {raw:?}");
        }
        if args[2] == "--json" {
            assert!(out.contains("Wait\\u009b2J\\u007fGPS"), "{args:?}: {out}");
        } else if matches!(args[1], "parse" | "sim") {
            assert!(out.contains("Wait\\u{9b}2J\\u{7f}GPS"), "{args:?}: {out}");
        }
    }
}

/// The files and texts beside the plan: `sim --conditions` (answers) and `--jumps`, and a
/// `check --property`. An empty answers file is valid (no answers: every condition false), a
/// cut one still a list of numbers, so those kinds are not bad input here.
#[test]
fn answers_jumps_and_properties_answer_bad_input_with_a_coded_error() {
    let dir = scratch();
    let demo = s(&vouch_testkit::repo_root().join("examples/fpl/demo.xml"));
    let mut cases = Vec::new();
    for kind in Kind::ALL {
        let d = dir.path().join(format!("{kind:?}"));
        std::fs::create_dir_all(&d).expect("folder");
        let (path, answers, jumps) = match kind {
            Kind::Missing => (d.join("missing.txt"), io("fpl::C001"), io("fpl::C001")),
            Kind::Directory => (d.clone(), io("fpl::C001"), io("fpl::C001")),
            Kind::Binary => (
                file(&d, "binary.txt", &binary_bytes()),
                rejected("fpl::C003"),
                rejected("fpl::C003"),
            ),
            Kind::HugeLine => {
                (file(&d, "huge.txt", &huge_line()), rejected("fpl::E041"), rejected("fpl::E044"))
            }
            Kind::ControlInValue | Kind::ControlInName => (
                file(&d, "control.txt", format!("1 0 {ESCAPES} 1").as_bytes()),
                rejected("fpl::E041"),
                rejected("fpl::E044"),
            ),
            Kind::WrongFormat => (
                file(&d, "json.txt", br#"{"answers": [1, 0]}"#),
                rejected("fpl::E041"),
                rejected("fpl::E044"),
            ),
            Kind::Empty | Kind::Truncated => continue,
        };
        for (option, want) in [("--conditions", answers), ("--jumps", jumps)] {
            let args = ["fpl", "sim", &demo, option, &s(&path)].map(String::from).to_vec();
            cases.push((format!("fpl sim {option} {kind:?}"), args, want));
        }
    }
    let property = format!("never block({ESCAPES})");
    let args = ["fpl", "check", &demo, "--property", &property].map(String::from).to_vec();
    cases.push(("fpl check --property with escapes".into(), args, rejected("fpl::E042")));
    run_catalogue(cases);
}
