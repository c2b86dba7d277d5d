//! The bad-input catalogue every family's CLI is run against (`*_bad_inputs.rs`): each kind of
//! bad file, and the checks every run must pass whatever the kind — the exit code of the
//! contract (1 input rejected, 2 usage or I/O), a family code on the error in every message
//! format, no panic, no raw control byte on stdout or stderr, and messages of a bounded size
//! (a huge line is shown cut).
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// One kind of bad input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A path that does not exist.
    Missing,
    /// A directory where a file is expected (an empty one where a folder is accepted).
    Directory,
    /// A file of zero bytes.
    Empty,
    /// Bytes that are no text and no image: every byte value, control bytes included.
    Binary,
    /// A valid file cut in the middle.
    Truncated,
    /// One line of a mebibyte.
    HugeLine,
    /// Terminal escape sequences (`ESC ] 0 ; … BEL`, `ESC [ 2 J`) in an attribute or value.
    ControlInValue,
    /// The same in a name (a waypoint's, a map image's, a key).
    ControlInName,
    /// Another format under the right extension (JSON in `.xml`, XML in `.yaml`, …).
    WrongFormat,
}

impl Kind {
    /// Every kind, in catalogue order.
    pub const ALL: [Kind; 9] = [
        Kind::Missing,
        Kind::Directory,
        Kind::Empty,
        Kind::Binary,
        Kind::Truncated,
        Kind::HugeLine,
        Kind::ControlInValue,
        Kind::ControlInName,
        Kind::WrongFormat,
    ];
}

/// The crafted escape sequence: retitles an xterm and clears the screen if printed raw.
pub const ESCAPES: &str = "\u{1b}]0;pwned\u{7}\u{1b}[2J";

/// Every byte value, in an order that starts with bytes no text format accepts.
pub fn binary_bytes() -> Vec<u8> {
    (0..4096u32).map(|i| ((i * 37 + 0x9b) % 256) as u8).collect()
}

/// One mebibyte on one line.
pub fn huge_line() -> Vec<u8> {
    vec![b'x'; 1 << 20]
}

/// A fresh private directory for one test's files.
pub fn scratch() -> tempfile::TempDir {
    tempfile::Builder::new().prefix("vouch-bad-inputs").tempdir().expect("temporary directory")
}

/// Writes `bytes` to `dir/name` and returns the path.
pub fn file(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).expect("write test input");
    p
}

/// The outcome a case must have.
#[derive(Clone, Copy, Debug)]
pub struct Expect {
    /// Exit status: 1 rejected, 2 usage or I/O.
    pub exit: i32,
    /// The family code of the error (`fpl::E002`).
    pub code: &'static str,
}

/// Shorthand: `rejected("fpl::E002")`.
pub fn rejected(code: &'static str) -> Expect {
    Expect { exit: 1, code }
}

/// Shorthand: `io("fpl::E001")`.
pub fn io(code: &'static str) -> Expect {
    Expect { exit: 2, code }
}

fn run(args: &[String], format: &str) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vouch"))
        .arg("--message-format")
        .arg(format)
        .args(args)
        .env_remove("PAPARAZZI_HOME")
        .output()
        .expect("the vouch binary runs")
}

/// Bytes a terminal acts on: C0 controls other than tab and line ends, DEL, and the C1
/// controls in UTF-8 (0xC2 0x80–0x9F).
pub fn raw_controls(bytes: &[u8]) -> Vec<String> {
    let mut found = Vec::new();
    for (i, w) in bytes.iter().enumerate() {
        let c1 = *w == 0xc2 && bytes.get(i + 1).is_some_and(|n| (0x80..=0x9f).contains(n));
        if (*w < 0x20 && !matches!(w, b'\t' | b'\n' | b'\r')) || *w == 0x7f || c1 {
            found.push(format!("0x{w:02x} at {i}"));
        }
    }
    found
}

/// Runs `args` in the human, short and JSON message formats and returns what is wrong (empty
/// when the case holds) and the exit status observed.
pub fn check(label: &str, args: &[String], want: Expect) -> (Vec<String>, Option<i32>) {
    let mut wrong = Vec::new();
    let mut observed = None;
    for format in ["human", "short", "json"] {
        let o = run(args, format);
        let err = String::from_utf8_lossy(&o.stderr);
        let code = o.status.code();
        observed = observed.or(code);
        let mut fail = |what: String| wrong.push(format!("{label} [{format}]: {what}"));
        if code != Some(want.exit) {
            fail(format!("exit {code:?}, want {} — {}", want.exit, first_line(&err)));
        }
        // a huge line is shown cut: messages stay readable whatever the input
        if o.stderr.len() > 16 * 1024 {
            fail(format!("{} bytes on stderr", o.stderr.len()));
        }
        if err.contains("panicked") || code == Some(101) {
            fail(format!("panicked: {err}"));
        }
        for (stream, bytes) in [("stdout", &o.stdout), ("stderr", &o.stderr)] {
            let raw = raw_controls(bytes);
            if !raw.is_empty() {
                fail(format!("raw control bytes on {stream}: {}", raw.join(", ")));
            }
        }
        let coded = match format {
            "short" => err.lines().any(|l| l.contains(&format!("error[{}]", want.code))),
            "json" => err
                .lines()
                .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
                .any(|v| v["code"] == want.code && v["severity"] == "error"),
            _ => err.contains(want.code),
        };
        if !coded {
            fail(format!("no error coded {} — {}", want.code, first_line(&err)));
        }
    }
    (wrong, observed)
}

fn first_line(s: &str) -> String {
    let lines = s.lines().filter(|l| !l.trim().is_empty()).take(3).collect::<Vec<_>>().join(" / ");
    lines.chars().take(400).collect()
}

/// Runs every case and fails with the list of what is wrong; prints the table of exit codes
/// observed (`--nocapture` shows it).
pub fn run_catalogue(cases: Vec<(String, Vec<String>, Expect)>) {
    let mut wrong = Vec::new();
    println!("{:<44} {:>4}  code", "case", "exit");
    for (label, args, want) in &cases {
        let (w, exit) = check(label, args, *want);
        println!("{label:<44} {:>4}  {}", exit.map_or("-".into(), |e| e.to_string()), want.code);
        wrong.extend(w);
    }
    assert!(
        wrong.is_empty(),
        "{} of {} cases wrong:\n{}",
        wrong.len(),
        cases.len(),
        wrong.join("\n")
    );
}
