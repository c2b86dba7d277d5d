//! Every flight plan of the upstream corpus (`shared/fpl/corpus`, INDEX.tsv) goes through the
//! front end: the 104 that upstream compiles parse, the two that upstream rejects fail with a
//! located error naming the bad value/reference, and block/stage counts agree with the
//! independently produced INDEX.tsv.

use std::path::Path;

use vouch_fpl::ast::{FlightPlan, Stage, StageKind};
use vouch_fpl::diag::ErrorKind;
use vouch_fpl::front::parse_file;

mod common;
use common::corpus_dir as corpus;

struct Row {
    path: String,
    kind: String,
    blocks: usize,
    stages: usize,
    generator_ok: bool,
}

fn index(dir: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(dir.join("INDEX.tsv")).expect("INDEX.tsv readable");
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            Row {
                path: f[0].to_string(),
                kind: f[1].to_string(),
                blocks: f[2].parse().expect("blocks column"),
                stages: f[3].parse().expect("stages column"),
                generator_ok: f[6] == "yes",
            }
        })
        .collect()
}

/// INDEX.tsv counting: while/for count one plus their bodies; a path counts once.
fn count(stages: &[Stage], seen_paths: &mut Vec<(u32, u32)>) -> usize {
    let mut n = 0;
    for s in stages {
        if s.from_path {
            let key = (s.span.file.0, s.span.start);
            if !seen_paths.contains(&key) {
                seen_paths.push(key);
                n += 1;
            }
            continue;
        }
        n += 1;
        match &s.kind {
            StageKind::While(w) => n += count(&w.body, seen_paths),
            StageKind::For(f) => n += count(&f.body, seen_paths),
            _ => {}
        }
    }
    n
}

fn own_counts(p: &FlightPlan) -> (usize, usize) {
    let own: Vec<_> = p.blocks.iter().filter(|b| b.procedure.is_none() && !b.implicit).collect();
    let mut seen = Vec::new();
    (own.len(), own.iter().map(|b| count(&b.stages, &mut seen)).sum())
}

#[test]
fn corpus_flight_plans_parse_like_upstream() {
    let Some(dir) = corpus() else { return };
    let rows = index(&dir);
    assert_eq!(rows.iter().filter(|r| r.kind == "flight_plan").count(), 106);
    let mut failures = Vec::new();
    let mut parsed = 0;
    for r in rows.iter().filter(|r| r.kind == "flight_plan") {
        let res = parse_file(dir.join(&r.path));
        match (&res, r.generator_ok) {
            (Ok(p), true) => {
                parsed += 1;
                let (b, s) = own_counts(p);
                if (b, s) != (r.blocks, r.stages) {
                    failures.push(format!(
                        "{}: blocks/stages {b}/{s}, INDEX says {}/{}",
                        r.path, r.blocks, r.stages
                    ));
                }
                assert_eq!(p.blocks.last().map(|b| b.name.value.as_str()), Some("HOME"));
            }
            (Err(d), true) => {
                failures.push(format!("{}: unexpected failure:\n{}", r.path, d.listing()))
            }
            (Ok(_), false) => failures.push(format!("{}: parsed but upstream rejects it", r.path)),
            (Err(_), false) => {}
        }
    }
    assert!(failures.is_empty(), "{} problems:\n{}", failures.len(), failures.join("\n"));
    assert_eq!(parsed, 104);
}

#[test]
fn example_template_fails_on_its_placeholder_value() {
    let Some(dir) = corpus() else { return };
    let d = parse_file(dir.join("example.xml")).expect_err("example.xml must be rejected");
    let e = d.first().expect("an error");
    assert_eq!(e.kind, ErrorKind::BadNumber);
    assert!(e.message.contains("???"), "message names the value: {}", e.message);
    assert!(e.message.contains("lat0"), "message names the attribute: {}", e.message);
    let text = std::fs::read_to_string(dir.join("example.xml")).unwrap();
    let line = text.lines().position(|l| l.contains("lat0=\"???\"")).unwrap() as u32 + 1;
    assert_eq!(e.line, Some(line));
}

#[test]
fn superbitrf_fails_on_the_missing_block() {
    let Some(dir) = corpus() else { return };
    let d = parse_file(dir.join("rotorcraft_basic_superbitrf.xml")).expect_err("must be rejected");
    let e = d.first().expect("an error");
    assert_eq!(e.kind, ErrorKind::UnknownBlock);
    assert!(e.message.contains("Land_Here"), "{}", e.message);
    let text = std::fs::read_to_string(dir.join("rotorcraft_basic_superbitrf.xml")).unwrap();
    let line = text.lines().position(|l| l.contains("deroute=\"Land_Here\"")).unwrap() as u32 + 1;
    assert_eq!(e.line, Some(line));
    assert!(e.col.unwrap_or(0) > 1);
}

#[test]
fn procedures_are_rejected_as_main_files() {
    let Some(dir) = corpus() else { return };
    for r in index(&dir).iter().filter(|r| r.kind == "procedure") {
        let d = parse_file(dir.join(&r.path)).expect_err("a procedure is not a flight plan");
        assert_eq!(d.first().unwrap().kind, ErrorKind::WrongRoot, "{}", r.path);
    }
}
