//! The bad-input catalogue against every `vouch navfn` subcommand that reads input: `plan`
//! (map YAML and PGM), `suite run`, `suite diff`, `campaign` (suite folders), `check-bag`
//! (bags) and `report merge` (reports). Every case must end with the exit code of the contract
//! (1 rejected, 2 usage or I/O), a `navfn::` code on the error in every message format, no
//! panic and no raw control byte on the terminal. Expected codes by reasoning: a path that
//! cannot be read is I/O (`E010` maps and suites, `E030` bags, `E058` reports) — a file named
//! inside the input (a suite's map) included —; bytes that are not a map are `E011` (a line
//! of a text file) or `E012` (the file as a whole); not a bag is `E031`, a damaged one `E032`;
//! not a report `E040`, a report without its format `E041`.

mod bad_inputs_support;

use std::path::{Path, PathBuf};

use bad_inputs_support::{
    ESCAPES, Expect, Kind, binary_bytes, file, huge_line, io, rejected, run_catalogue, scratch,
};

fn examples() -> PathBuf {
    vouch_testkit::repo_root().join("examples/navfn")
}

fn folder(dir: &Path, name: &str) -> PathBuf {
    let d = dir.join(name);
    std::fs::create_dir_all(&d).expect("folder");
    d
}

fn s(p: &Path) -> String {
    p.to_str().expect("utf-8 path").to_string()
}

/// A map_server YAML of `kind` (the valid one names the bundled warehouse image).
fn yaml_input(dir: &Path, kind: Kind) -> (PathBuf, Expect) {
    let good = std::fs::read_to_string(examples().join("warehouse.yaml")).expect("yaml");
    std::fs::copy(examples().join("warehouse.pgm"), dir.join("warehouse.pgm")).expect("pgm");
    let line = rejected("navfn::E011");
    match kind {
        Kind::Missing => (dir.join("missing.yaml"), io("navfn::E010")),
        Kind::Directory => (folder(dir, "folder.yaml"), io("navfn::E010")),
        Kind::Empty => (file(dir, "empty.yaml", b""), rejected("navfn::E012")),
        Kind::Binary => (file(dir, "binary.yaml", &binary_bytes()), rejected("navfn::E012")),
        Kind::Truncated => (file(dir, "cut.yaml", &good.as_bytes()[..good.len() / 3]), line),
        Kind::HugeLine => (file(dir, "huge.yaml", &huge_line()), line),
        Kind::ControlInValue => {
            let text = good.replacen("resolution: ", &format!("resolution: {ESCAPES}"), 1);
            assert_ne!(text, good);
            (file(dir, "control_value.yaml", text.as_bytes()), line)
        }
        Kind::ControlInName => {
            let text = good.replacen("resolution:", &format!("reso{ESCAPES}lution:"), 1);
            assert_ne!(text, good);
            (file(dir, "control_name.yaml", text.as_bytes()), line)
        }
        Kind::WrongFormat => {
            (file(dir, "xml.yaml", b"<map><image>warehouse.pgm</image></map>\n"), line)
        }
    }
}

/// A PGM image of `kind`.
fn pgm_input(dir: &Path, kind: Kind) -> (PathBuf, Expect) {
    let good = std::fs::read(examples().join("warehouse.pgm")).expect("pgm");
    let whole = rejected("navfn::E012");
    let path = match kind {
        Kind::Missing => return (dir.join("missing.pgm"), io("navfn::E010")),
        Kind::Directory => return (folder(dir, "folder.pgm"), io("navfn::E010")),
        Kind::Empty => file(dir, "empty.pgm", b""),
        Kind::Binary => file(dir, "binary.pgm", &binary_bytes()),
        Kind::Truncated => file(dir, "cut.pgm", &good[..good.len() / 2]),
        Kind::HugeLine => file(dir, "huge.pgm", &huge_line()),
        Kind::ControlInValue => {
            file(dir, "cv.pgm", format!("P5\n2{ESCAPES} 2\n255\nabcd").as_bytes())
        }
        Kind::ControlInName => {
            file(dir, "cn.pgm", format!("P{ESCAPES}\n2 2\n255\nabcd").as_bytes())
        }
        Kind::WrongFormat => file(dir, "yaml.pgm", b"image: warehouse.pgm\nresolution: 0.05\n"),
    };
    (path, whole)
}

/// A suite folder of `kind` (its `test.txt`, and a copy of a bundled map where it names one).
fn suite_input(dir: &Path, kind: Kind) -> (PathBuf, Expect) {
    let src = examples().join("suite/field/blocks_30x20");
    let good = std::fs::read_to_string(src.join("test.txt")).expect("test.txt");
    let d = folder(dir, &format!("suite_{kind:?}"));
    std::fs::copy(src.join("map.bin"), d.join("map.bin")).expect("map.bin");
    let line = rejected("navfn::E011");
    let expect = match kind {
        Kind::Missing => return (dir.join("missing_suite"), io("navfn::E010")),
        Kind::Directory => {
            std::fs::remove_file(d.join("map.bin")).expect("empty folder");
            return (d, rejected("navfn::E012"));
        }
        Kind::Empty => {
            file(&d, "test.txt", b"");
            rejected("navfn::E012")
        }
        Kind::Binary => {
            file(&d, "test.txt", &binary_bytes());
            rejected("navfn::E012")
        }
        Kind::Truncated => {
            // the size line and half of the map's name
            file(&d, "test.txt", &good.as_bytes()[..good.find("map.bin").expect("name") + 3]);
            io("navfn::E010")
        }
        Kind::HugeLine => {
            file(&d, "test.txt", &huge_line());
            line
        }
        Kind::ControlInValue => {
            let text = good.replacen("\n\n", &format!("\n\n1{ESCAPES} "), 1);
            file(&d, "test.txt", text.as_bytes());
            line
        }
        Kind::ControlInName => {
            // the map file it names cannot be read: I/O, the name shown escaped
            file(
                &d,
                "test.txt",
                good.replacen("map.bin", &format!("map{ESCAPES}.bin"), 1).as_bytes(),
            );
            io("navfn::E010")
        }
        Kind::WrongFormat => {
            file(&d, "test.txt", b"size: [30, 20]\nmap: map.bin\n");
            line
        }
    };
    (d, expect)
}

/// A rosbag2 bag of `kind` (files named `.mcap`/`.db3`, folders as rosbag2 writes them).
fn bag_input(dir: &Path, kind: Kind) -> (PathBuf, Expect) {
    let not_a_bag = rejected("navfn::E031");
    match kind {
        Kind::Missing => (dir.join("missing.mcap"), io("navfn::E030")),
        Kind::Directory => (folder(dir, "empty_bag"), not_a_bag),
        Kind::Empty => (file(dir, "empty.mcap", b""), not_a_bag),
        Kind::Binary => (file(dir, "binary.mcap", &binary_bytes()), not_a_bag),
        Kind::Truncated => {
            let db =
                std::fs::read(examples().join("warehouse_bag/warehouse_bag.db3")).expect("db3");
            (file(dir, "cut.db3", &db[..db.len() / 2]), rejected("navfn::E032"))
        }
        Kind::HugeLine => (file(dir, "huge.mcap", &huge_line()), not_a_bag),
        Kind::ControlInValue => {
            let bytes = [b"\x89MCAP0\r\n".as_slice(), ESCAPES.as_bytes()].concat();
            (file(dir, "control.mcap", &bytes), rejected("navfn::E032"))
        }
        Kind::ControlInName => (folder(dir, &format!("bag{ESCAPES}")), not_a_bag),
        Kind::WrongFormat => {
            (file(dir, "yaml.mcap", b"rosbag2_bagfile_information:\n  version: 5\n"), not_a_bag)
        }
    }
}

/// A campaign report of `kind`.
fn report_input(dir: &Path, kind: Kind) -> (PathBuf, Expect) {
    let not_a_report = rejected("navfn::E040");
    match kind {
        Kind::Missing => (dir.join("missing.json"), io("navfn::E058")),
        Kind::Directory => (folder(dir, "folder.json"), io("navfn::E058")),
        Kind::Empty => (file(dir, "empty.json", b""), not_a_report),
        Kind::Binary => (file(dir, "binary.json", &binary_bytes()), not_a_report),
        Kind::Truncated => {
            (file(dir, "cut.json", b"{\"format\": 2, \"vouch_version\": \"0."), not_a_report)
        }
        Kind::HugeLine => (file(dir, "huge.json", &huge_line()), not_a_report),
        Kind::ControlInValue => {
            let text = format!("{{\"format\": 2, \"vouch_version\": \"{ESCAPES}\"}}");
            (file(dir, "cv.json", text.as_bytes()), not_a_report)
        }
        Kind::ControlInName => {
            // valid JSON (the key's escape is JSON's): a report without its format
            (file(dir, "cn.json", b"{\"for\\u001b]0;x\\u0007mat\": 2}"), rejected("navfn::E041"))
        }
        Kind::WrongFormat => (file(dir, "yaml.json", b"format: 2\ncases: 0\n"), not_a_report),
    }
}

fn args(words: &[&str]) -> Vec<String> {
    words.iter().map(|w| w.to_string()).collect()
}

#[test]
fn every_navfn_reader_answers_every_bad_input_with_a_coded_error() {
    let dir = scratch();
    let out = s(&dir.path().join("out.json"));
    let mut cases = Vec::new();
    for kind in Kind::ALL {
        let d = folder(dir.path(), &format!("{kind:?}"));
        for (what, (p, want)) in [("yaml", yaml_input(&d, kind)), ("pgm", pgm_input(&d, kind))] {
            let a = args(&["navfn", "plan", &s(&p), "--start", "1,1", "--goal", "2,2"]);
            cases.push((format!("navfn plan {what} {kind:?}"), a, want));
        }
        let (suite, want) = suite_input(&d, kind);
        let suite = s(&suite);
        cases.push((
            format!("navfn suite run {kind:?}"),
            args(&["navfn", "suite", "run", &suite]),
            want,
        ));
        let a = args(&["navfn", "suite", "run", &suite, "--trace", "cells"]);
        cases.push((format!("navfn suite run --trace {kind:?}"), a, want));
        let a = args(&["navfn", "suite", "diff", &suite, "--oracle", "/bin/false"]);
        cases.push((format!("navfn suite diff {kind:?}"), a, want));
        let a = args(&["navfn", "campaign", &suite, "-o", &out]);
        cases.push((format!("navfn campaign {kind:?}"), a, want));
        let (bag, want) = bag_input(&d, kind);
        cases.push((
            format!("navfn check-bag {kind:?}"),
            args(&["navfn", "check-bag", &s(&bag)]),
            want,
        ));
        let (report, want) = report_input(&d, kind);
        let a = args(&["navfn", "report", "merge", &s(&report), "-o", &out]);
        cases.push((format!("navfn report merge {kind:?}"), a, want));
    }
    // Valid inputs that hold nothing to check: rejected, never a pass.
    let zero = folder(dir.path(), "zero_cases/only");
    std::fs::write(zero.join("test.txt"), "3 3\nmap.bin\n\n").expect("test.txt");
    std::fs::write(zero.join("map.bin"), [0u8; 9]).expect("map.bin");
    let zero = s(&zero);
    let none = rejected("navfn::E012");
    cases.push(("navfn suite run (no case)".into(), args(&["navfn", "suite", "run", &zero]), none));
    // an oracle that answers nothing to nothing: the comparison still holds no case
    let a = args(&["navfn", "suite", "diff", &zero, "--oracle", "/bin/true"]);
    cases.push(("navfn suite diff (no case)".into(), a, none));
    let a = args(&["navfn", "campaign", &zero, "-o", &out]);
    cases.push(("navfn campaign (no case)".into(), a, none));
    let bag = s(&examples().join("warehouse_bag"));
    let a = args(&["navfn", "check-bag", &bag, "--plan-topic", "/no_plans_here"]);
    cases.push(("navfn check-bag (no plan)".into(), a, rejected("navfn::E034")));
    run_catalogue(cases);
}
