//! Inputs as real Paparazzi trees hold them, byte-identical with upstream under
//! `--upstream-compat`, the expected bytes being upstream's own output for the corpus
//! (`../shared/fpl/upstream/`), made by the unmodified OCaml generator:
//! * plans saved with Windows line endings (every `.xml` of the corpus rewritten with CRLF):
//!   xml-light ends a text line at a carriage return, so header, dump and settings equal
//!   upstream's output for the LF originals (plans with a line break inside an attribute
//!   value are left out: upstream keeps the `\r` there too, so their output differs from the
//!   LF original's);
//! * a procedure that exists both beside the plan's tree and under
//!   `$PAPARAZZI_HOME/conf/flight_plans`: upstream includes the second (its search order is the
//!   plan's directory, then the home), and so does `--upstream-compat`; by default vouch takes
//!   the first and a located warning names both files.

use std::path::{Path, PathBuf};

use vouch_fpl::emit::{EmitOptions, compile_plan_full};
use vouch_fpl::front::{Options, parse_file_with};

fn copy_tree(from: &Path, to: &Path, crlf: bool) {
    std::fs::create_dir_all(to).expect("mkdir");
    assert!(from.is_dir(), "{}", from.display());
    for e in std::fs::read_dir(from).expect("read_dir") {
        let e = e.expect("entry");
        let target = to.join(e.file_name());
        if e.file_type().expect("type").is_dir() {
            copy_tree(&e.path(), &target, crlf);
        } else if crlf && target.extension().is_some_and(|x| x == "xml") {
            let text = std::fs::read_to_string(e.path()).expect("read");
            std::fs::write(&target, text.replace("\r\n", "\n").replace('\n', "\r\n"))
                .expect("write");
        } else {
            std::fs::copy(e.path(), &target).expect("copy");
        }
    }
}

/// A line break inside a quoted attribute value (a quote opened on one line, closed on another).
fn value_spans_lines(text: &str) -> bool {
    let mut in_tag = false;
    let mut quote: Option<char> = None;
    let mut in_comment = false;
    let b = text.as_bytes();
    let mut i = 0;
    while i < b.len() {
        let c = b[i] as char;
        if in_comment {
            if b[i..].starts_with(b"-->") {
                in_comment = false;
            }
        } else if let Some(q) = quote {
            if c == q {
                quote = None;
            } else if c == '\n' {
                return true;
            }
        } else if in_tag {
            match c {
                '"' | '\'' => quote = Some(c),
                '>' => in_tag = false,
                _ => {}
            }
        } else if b[i..].starts_with(b"<!--") {
            in_comment = true;
        } else if c == '<' {
            in_tag = true;
        }
        i += 1;
    }
    false
}

struct Env {
    corpus: PathBuf,
    upstream: PathBuf,
    /// A Paparazzi home as upstream's outputs were made with: `../shared/fpl/paparazzi_home`
    /// with the corpus as its `conf/flight_plans` (a copy: the shared folder holds that link
    /// as a plain file).
    home: PathBuf,
    _dir: tempfile::TempDir,
}

fn env() -> Option<Env> {
    let corpus = vouch_testkit::shared("fpl/corpus", "INDEX.tsv")?;
    let shared_home = vouch_testkit::shared("fpl/paparazzi_home", "conf/abi.xml")?;
    let dir = tempfile::tempdir().expect("tempdir");
    let home = dir.path().join("home");
    std::fs::create_dir_all(home.join("data/srtm")).expect("mkdir");
    std::fs::create_dir_all(home.join("conf")).expect("mkdir");
    for f in ["conf/abi.xml", "conf/abi.dtd", "data/srtm/WW15MGH.DAC.bz2"] {
        std::fs::copy(shared_home.join(f), home.join(f)).expect("copy");
    }
    copy_tree(&corpus, &home.join("conf/flight_plans"), false);
    Some(Env {
        corpus,
        upstream: vouch_testkit::shared("fpl/upstream", "INDEX.tsv")?,
        home,
        _dir: dir,
    })
}

fn compat(home: &Path, rel: &str) -> EmitOptions {
    EmitOptions {
        source_path: rel.to_string(),
        upstream_compat: true,
        paparazzi_home: Some(home.to_path_buf()),
        ..EmitOptions::default()
    }
}

fn compat_front(home: &Path) -> Options {
    Options {
        upstream_includes: true,
        upstream_flight_plans: Some(home.join("conf/flight_plans")),
        ..Options::default()
    }
}

#[test]
fn crlf_plans_give_upstreams_bytes() {
    let Some(e) = env() else { return };
    let dir = tempfile::tempdir().expect("tempdir");
    copy_tree(&e.corpus, dir.path(), true);
    let index = std::fs::read_to_string(e.corpus.join("INDEX.tsv")).expect("index");
    let (mut checked, mut left_out, mut failures) = (0, Vec::new(), Vec::new());
    for line in index.lines().skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        if f.get(1) != Some(&"flight_plan") || f.get(6) != Some(&"yes") {
            continue;
        }
        let rel = f[0];
        let original = std::fs::read_to_string(e.corpus.join(rel)).expect("read");
        if value_spans_lines(&original) {
            left_out.push(rel.to_string());
            continue;
        }
        let path = dir.path().join(rel);
        assert!(std::fs::read_to_string(&path).expect("crlf").contains("\r\n"));
        let plan = parse_file_with(&path, &compat_front(&e.home)).expect("parses");
        let stem = rel.trim_end_matches(".xml");
        let built = compile_plan_full(&plan, &compat(&e.home, rel)).expect("compiles");
        let want = std::fs::read_to_string(e.upstream.join(format!("headers/{stem}.h")))
            .expect("upstream header");
        if built.header != want {
            failures.push(format!("{rel}: header"));
        }
        let dump = vouch_fpl::emit::dump::dump(&plan).expect("dump");
        let want = std::fs::read_to_string(e.upstream.join(format!("dumps/{stem}.xml")))
            .expect("upstream dump");
        if dump != want {
            failures.push(format!("{rel}: dump"));
        }
        let settings = e.upstream.join(format!("settings/{stem}.xml"));
        if settings.is_file() {
            let s = vouch_fpl::emit::settings::settings(&plan, "v7.0_unstable").expect("settings");
            if s.xml != std::fs::read_to_string(&settings).expect("settings") {
                failures.push(format!("{rel}: settings.xml"));
            }
        }
        checked += 1;
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert_eq!(checked + left_out.len(), 104);
    assert!(checked >= 80, "{checked} checked, left out: {left_out:?}");
}

/// The fork's tree: `fork/flight_plan.dtd`, the plan under `fork/AGGIEAIR/`, and its own
/// (different) copy of the landing procedure at `fork/AGGIEAIR/aggieair_landing.xml`.
fn fork(e: &Env) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().expect("tempdir");
    let fork = dir.path().join("fork");
    std::fs::create_dir_all(fork.join("AGGIEAIR")).expect("mkdir");
    std::fs::copy(e.corpus.join("flight_plan.dtd"), fork.join("flight_plan.dtd")).expect("dtd");
    let rel = "AGGIEAIR/BasicTuning_BlueRoom2.xml";
    std::fs::copy(e.corpus.join(rel), fork.join(rel)).expect("plan");
    let proc = std::fs::read_to_string(e.corpus.join("AGGIEAIR/aggieair_landing.xml")).expect("p");
    let changed = proc.replacen("\"Landing CW\"", "\"Landing CW (fork)\"", 1);
    assert_ne!(changed, proc);
    std::fs::write(fork.join("AGGIEAIR/aggieair_landing.xml"), changed).expect("write");
    (dir, fork.join(rel))
}

#[test]
fn includes_follow_upstreams_search_order_under_upstream_compat() {
    let Some(e) = env() else { return };
    let (_dir, plan_path) = fork(&e);
    let rel = "AGGIEAIR/BasicTuning_BlueRoom2.xml";
    let want = std::fs::read_to_string(e.upstream.join("headers/AGGIEAIR/BasicTuning_BlueRoom2.h"))
        .expect("upstream header");
    let want_dump =
        std::fs::read_to_string(e.upstream.join("dumps/AGGIEAIR/BasicTuning_BlueRoom2.xml"))
            .expect("upstream dump");

    // --upstream-compat: the home's procedure, upstream's bytes, no warning about it.
    let plan = parse_file_with(&plan_path, &compat_front(&e.home)).expect("parses");
    let procedure = plan.sources.files[1].path.clone();
    assert!(procedure.starts_with(&e.home.join("conf/flight_plans").display().to_string()));
    assert_eq!(compile_plan_full(&plan, &compat(&e.home, rel)).expect("compiles").header, want);
    assert_eq!(vouch_fpl::emit::dump::dump(&plan).expect("dump"), want_dump);
    assert!(plan.warnings.iter().all(|w| !w.message.contains("would include")));

    // Default: the fork's own procedure, and a warning located at the include naming both.
    let opts = Options {
        upstream_flight_plans: Some(e.home.join("conf/flight_plans")),
        ..Options::default()
    };
    let plan = parse_file_with(&plan_path, &opts).expect("parses");
    assert!(plan.sources.files[1].path.ends_with("fork/AGGIEAIR/aggieair_landing.xml"));
    let w = plan
        .warnings
        .iter()
        .find(|w| w.message.contains("would include"))
        .expect("a warning naming both procedures");
    assert!(w.message.contains("fork/AGGIEAIR/aggieair_landing.xml"), "{}", w.message);
    assert!(w.message.contains("conf/flight_plans/AGGIEAIR/aggieair_landing.xml"), "{}", w.message);
    let span = w.span.expect("located");
    let text = std::fs::read_to_string(&plan_path).expect("read");
    assert_eq!(&text[span.range()], "AGGIEAIR/aggieair_landing.xml");
    assert_ne!(compile_plan_full(&plan, &compat(&e.home, rel)).expect("compiles").header, want);
}
