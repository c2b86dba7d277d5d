//! Help pages a person scans, and JSON named one way.
//!
//! Every page (`-h` and `--help`) fits in 100 columns; on `-h` every option keeps its
//! description on its own line (no two-line layout), the global options stand under their own
//! heading; every page shows examples and every command that runs lists its exit codes. The
//! JSON documents of the bundled examples name keys and enumerated values in snake_case.

mod common;

use clap::CommandFactory;
use common::{code, vouch_at_root};
use vouch_cli::Cli;

/// Widest help line allowed (clap wraps at 100 columns when stdout is not a terminal).
const WIDEST: usize = 100;

/// Every command path (`["fpl", "compile"]`, …), the top level first, and whether it runs
/// (a leaf) or groups others.
fn commands() -> Vec<(Vec<String>, bool)> {
    fn walk(cmd: &clap::Command, path: Vec<String>, out: &mut Vec<(Vec<String>, bool)>) {
        let subs: Vec<_> = cmd.get_subcommands().filter(|s| s.get_name() != "help").collect();
        out.push((path.clone(), subs.is_empty()));
        for s in subs {
            let mut p = path.clone();
            p.push(s.get_name().to_string());
            walk(s, p, out);
        }
    }
    let mut cmd = Cli::command();
    cmd.build();
    let mut out = vec![];
    walk(&cmd, vec![], &mut out);
    out
}

/// The page `vouch PATH FLAG` prints.
fn page(path: &[String], flag: &str) -> String {
    let mut args: Vec<&str> = path.iter().map(String::as_str).collect();
    args.push(flag);
    let o = vouch_at_root(&args);
    assert_eq!(code(&o), 0, "vouch {}", args.join(" "));
    String::from_utf8(o.stdout).expect("UTF-8 help")
}

fn name(path: &[String]) -> String {
    format!("vouch {}", path.join(" ")).trim_end().to_string()
}

#[test]
fn every_page_fits_in_100_columns() {
    let mut widest = (0, String::new(), String::new());
    for (path, _) in commands() {
        for flag in ["-h", "--help"] {
            for line in page(&path, flag).lines() {
                let w = line.chars().count();
                if w > widest.0 {
                    widest = (w, format!("{} {flag}", name(&path)), line.to_string());
                }
            }
        }
    }
    let (w, at, line) = widest;
    assert!(w <= WIDEST, "{at}: a line of {w} columns:\n{line}");
}

/// An option line of a `-h` page without its description: clap's two-line layout, which one
/// long description forces on a whole section.
fn is_bare_option(line: &str) -> bool {
    let t = line.trim();
    // options start at column 2 (`-x, --long`) or 6 (`--long`); deeper lines continue a text
    let indent = line.len() - line.trim_start().len();
    (2..=6).contains(&indent)
        && t.starts_with('-')
        && t.split_whitespace().all(|w| w.starts_with('-') || w.starts_with('<') || w == "[")
}

#[test]
fn short_pages_keep_each_option_on_one_line_and_globals_apart() {
    let mut bad = vec![];
    for (path, _) in commands() {
        let p = page(&path, "-h");
        if let Some(l) = p.lines().find(|l| is_bare_option(l)) {
            bad.push(format!("{}: two-line layout at `{}`", name(&path), l.trim()));
        }
        let global = p.find("Global options:");
        let format = p.find("--message-format");
        if global.is_none() || format < global {
            bad.push(format!("{}: --message-format not under `Global options:`", name(&path)));
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn every_page_has_examples_and_every_command_its_exit_codes() {
    let mut bad = vec![];
    let (mut pages, mut leaves) = (0, 0);
    for (path, leaf) in commands() {
        let p = page(&path, "-h");
        pages += 1;
        let examples = p.split("Example:\n").nth(1).or(p.split("Examples:\n").nth(1));
        if !examples.and_then(|e| e.lines().next()).is_some_and(|l| l.contains("vouch ")) {
            bad.push(format!("{}: no `Example(s):` with a vouch command", name(&path)));
        }
        if leaf {
            leaves += 1;
            if !p.contains("Exit codes: 0 ") {
                bad.push(format!("{}: no `Exit codes:`", name(&path)));
            }
        }
    }
    assert!(bad.is_empty(), "{}", bad.join("\n"));
    assert!(pages >= 29 && leaves >= 20, "{pages} pages, {leaves} commands");
}

#[test]
fn descriptions_are_one_line() {
    let mut long = vec![];
    let mut top = Cli::command();
    top.build();
    fn walk(cmd: &clap::Command, prefix: &str, long: &mut Vec<String>) {
        for s in cmd.get_subcommands().filter(|s| s.get_name() != "help") {
            let name = format!("{prefix} {}", s.get_name());
            let about = s.get_about().map(|a| a.to_string()).unwrap_or_default();
            if about.chars().count() > 80 || about.contains('\n') {
                long.push(format!("{name}: {} characters: {about}", about.chars().count()));
            }
            walk(s, &name, long);
        }
    }
    walk(&top, "vouch", &mut long);
    assert!(long.is_empty(), "descriptions longer than a line:\n{}", long.join("\n"));
}

/// Keys of objects whose keys are data (map names, relation@transform, …), not names of ours.
const DATA_KEYS: &[&str] = &["maps", "metamorphic", "categories", "properties", "relations"];
/// Fields whose string values are data (names from the input, free text), not enumerations.
const DATA_VALUES: &[&str] = &[
    "name",
    "text",
    "blocks",
    "value",
    "message",
    "path",
    "file",
    "topic",
    "frame",
    "protocol",
    "property",
    "detail",
    "why",
    "messages",
    "roles",
    "suite",
    "dir",
    "raw",
    "coords",
    "cmd",
    "vouch_version",
    "source",
    "label",
    "block",
    "stage",
    "kind_name",
    "content",
    "digest",
    "call",
    "command",
];

fn snake(s: &str) -> bool {
    !s.is_empty() && s.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_')
}

/// A string that names something of ours (one word, no spaces, letters first).
fn identifier_like(s: &str) -> bool {
    s.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

fn check_names(v: &serde_json::Value, at: &str, data_keys: bool, bad: &mut Vec<String>) {
    match v {
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                let key_ok = data_keys || snake(k);
                if !key_ok {
                    bad.push(format!("{at}: key `{k}`"));
                }
                let data = DATA_KEYS.contains(&k.as_str());
                if DATA_VALUES.contains(&k.as_str()) {
                    continue;
                }
                check_names(x, &format!("{at}.{k}"), data, bad);
            }
        }
        serde_json::Value::Array(xs) => {
            xs.iter().for_each(|x| check_names(x, &format!("{at}[]"), false, bad));
        }
        serde_json::Value::String(s) if identifier_like(s) && !snake(s) => {
            bad.push(format!("{at}: value `{s}`"));
        }
        _ => {}
    }
}

#[test]
fn json_documents_name_keys_and_values_in_snake_case() {
    let dir = tempfile::tempdir().expect("scratch directory");
    let report = dir.path().join("report.json");
    let report = report.to_str().expect("UTF-8 path");
    let runs: [&[&str]; 9] = [
        &["fpl", "parse", "--json", "examples/fpl/demo.xml"],
        &["fpl", "sim", "--json", "examples/fpl/demo.xml", "--steps", "5", "--seed", "7"],
        &["fpl", "check", "--json", "examples/fpl/demo.xml"],
        &["fpl", "lint", "--json", "examples/fpl/demo.xml"],
        &["mav", "lint", "--json"],
        &["mav", "check", "--json", "examples/mav/early_ack.tlog"],
        &[
            "navfn",
            "plan",
            "examples/navfn/warehouse.yaml",
            "--start",
            "1,1",
            "--goal",
            "8.5,6.5",
            "--json",
        ],
        &["navfn", "check-bag", "examples/navfn/warehouse_bag", "--json"],
        &["navfn", "campaign", "examples/navfn/suite", "-q", "-o", report],
    ];
    let mut bad = vec![];
    for args in runs {
        let o = vouch_at_root(args);
        assert!(code(&o) <= 3, "vouch {}: {}", args.join(" "), String::from_utf8_lossy(&o.stderr));
        let text = if args.contains(&report) {
            std::fs::read_to_string(report).expect("the campaign report")
        } else {
            String::from_utf8(o.stdout).expect("UTF-8")
        };
        let v: serde_json::Value = serde_json::from_str(&text).expect("one JSON document");
        check_names(&v, &args[..2].join(" "), false, &mut bad);
    }
    bad.dedup();
    assert!(bad.is_empty(), "names not in snake_case:\n{}", bad.join("\n"));
}
