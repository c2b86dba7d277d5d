//! The malformed-input catalogue: every crafted broken plan under `tests/malformed/` must fail
//! with the error kind and line listed in `tests/malformed/EXPECT.tsv` (and in the listed file
//! for errors inside included procedures) — never a panic, never a success.

use std::path::PathBuf;

use vouch_fpl::diag::ErrorKind;
use vouch_fpl::front::parse_file;

fn kind_named(s: &str) -> ErrorKind {
    match s {
        "Xml" => ErrorKind::Xml,
        "EmptyPlan" => ErrorKind::EmptyPlan,
        "MissingElement" => ErrorKind::MissingElement,
        "WrongRoot" => ErrorKind::WrongRoot,
        "UnknownBlock" => ErrorKind::UnknownBlock,
        "UnknownWaypoint" => ErrorKind::UnknownWaypoint,
        "DuplicateBlock" => ErrorKind::DuplicateBlock,
        "DuplicateWaypoint" => ErrorKind::DuplicateWaypoint,
        "UnknownStage" => ErrorKind::UnknownStage,
        "UnknownAttribute" => ErrorKind::UnknownAttribute,
        "MissingAttribute" => ErrorKind::MissingAttribute,
        "BadExpression" => ErrorKind::BadExpression,
        "BadNumber" => ErrorKind::BadNumber,
        "NumberOutOfRange" => ErrorKind::NumberOutOfRange,
        "BadValue" => ErrorKind::BadValue,
        "Conflict" => ErrorKind::Conflict,
        "UnexpectedElement" => ErrorKind::UnexpectedElement,
        "IncludeNotFound" => ErrorKind::IncludeNotFound,
        "IncludeLoop" => ErrorKind::IncludeLoop,
        "MissingParam" => ErrorKind::MissingParam,
        "ProcedureStage" => ErrorKind::ProcedureStage,
        other => panic!("EXPECT.tsv names an unknown kind {other}"),
    }
}

#[test]
fn every_malformed_plan_fails_with_the_expected_kind_and_line() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/malformed");
    let expect = std::fs::read_to_string(dir.join("EXPECT.tsv")).expect("EXPECT.tsv");
    let mut problems = Vec::new();
    let mut n = 0;
    for line in expect.lines().filter(|l| !l.starts_with('#') && !l.trim().is_empty()) {
        let f: Vec<&str> = line.split('\t').collect();
        let (file, kind, want_line) =
            (f[0], kind_named(f[1]), f[2].parse::<u32>().expect("line number"));
        n += 1;
        let res = std::panic::catch_unwind(|| parse_file(dir.join(file)));
        let Ok(res) = res else {
            problems.push(format!("{file}: PANIC"));
            continue;
        };
        let Err(d) = res else {
            problems.push(format!("{file}: parsed successfully"));
            continue;
        };
        let Some(e) = d.errors().find(|e| e.kind == kind) else {
            problems.push(format!("{file}: no {kind:?} error; got:\n{}", d.listing()));
            continue;
        };
        if e.line != Some(want_line) {
            problems.push(format!(
                "{file}: {kind:?} at line {:?}, expected {want_line}\n{}",
                e.line,
                d.listing()
            ));
        }
        if let Some(holder) = f.get(3) {
            let path = e.file.clone().unwrap_or_default();
            if !path.ends_with(holder) {
                problems.push(format!("{file}: error located in {path}, expected {holder}"));
            }
        }
        // The short form shows the location; miette's rendering of the excerpt never fails.
        let text = d.listing();
        assert!(text.contains(&format!(":{want_line}:")) || e.span.is_none(), "{file}: {text}");
        let mut boxed = String::new();
        miette::GraphicalReportHandler::new_themed(miette::GraphicalTheme::unicode_nocolor())
            .render_report(&mut boxed, &d)
            .expect("renders");
        assert!(boxed.contains(e.kind.code()), "{file}: {boxed}");
    }
    assert!(n >= 25, "the catalogue must hold at least 25 plans, has {n}");
    assert!(problems.is_empty(), "{} problems:\n{}", problems.len(), problems.join("\n\n"));
}
