//! Builds and talks to the C side of translation validation: the generated (instrumented)
//! header, the project's stub runtime and [`DRIVER_C`], compiled by the system C compiler into a
//! small server process that replays answer prefixes and forks at every question
//! (see the comment at the top of `c/explore_driver.c`).
//!
//! The stub runtime sources are embedded from `tests/stub/` so the `vouch` binary can validate
//! without the source tree; the runtime is therefore the same one the compiler's own tests use.

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

pub const DRIVER_C: &str = include_str!("c/explore_driver.c");

/// (relative path, contents) of the stub runtime files.
const STUB_FILES: &[(&str, &str)] = &[
    ("fp_stub.c", include_str!("../../tests/stub/fp_stub.c")),
    ("include/fp_stub.h", include_str!("../../tests/stub/include/fp_stub.h")),
    ("include/std.h", include_str!("../../tests/stub/include/std.h")),
    ("include/autopilot.h", include_str!("../../tests/stub/include/autopilot.h")),
    ("include/generated/modules.h", include_str!("../../tests/stub/include/generated/modules.h")),
    ("include/modules/core/abi.h", include_str!("../../tests/stub/include/modules/core/abi.h")),
];

/// A compiled driver in its own temporary directory (removed on drop).
pub struct Driver {
    dir: PathBuf,
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
}

/// One leaf of an explored call, as the C printed it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CPath {
    /// A complete path: answers consumed, event lines, state after the call.
    Done { answers: Vec<i64>, events: Vec<String>, after: [usize; 4] },
    /// The call asked more questions than the driver's limit (a loop inside one call).
    TooLong { answers: Vec<i64> },
    /// The process died (signal or time-out) on this answer prefix.
    Crashed { status: i64, answers: Vec<i64> },
}

impl CPath {
    /// The answers the path consumed.
    pub fn answers(&self) -> &[i64] {
        match self {
            CPath::Done { answers, .. }
            | CPath::TooLong { answers }
            | CPath::Crashed { answers, .. } => answers,
        }
    }
}

/// What the driver reported for one request.
#[derive(Debug, Clone, Default)]
pub struct Explored {
    /// Events of `auto_nav_init()` (only for requests at call 0).
    pub init: Option<Vec<String>>,
    /// State after the replayed prefix.
    pub replayed: Option<[usize; 4]>,
    pub paths: Vec<CPath>,
    /// The leaf budget ran out.
    pub cut: bool,
}

fn next_unique_dir() -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!("vouch-fpl-validate-{}-{n}", std::process::id()))
}

/// Why the C side of the validation could not run.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum DriverError {
    /// The C compiler cannot be started.
    #[error("cannot run the C compiler '{cc}': {source}")]
    #[diagnostic(code(fpl::E050), help("set CC to a C99 compiler"))]
    NoCompiler {
        /// The compiler command (`$CC` or `cc`).
        cc: String,
        /// Why it could not start.
        source: std::io::Error,
    },
    /// The generated header does not compile with the stub runtime (a defect of the
    /// generator or of the stub).
    #[error("the generated header does not compile with the stub runtime:\n{log}")]
    #[diagnostic(code(fpl::E051))]
    HeaderRejected {
        /// The first lines of the compiler's messages.
        log: String,
    },
    /// A temporary file or the driver process could not be written, read or started.
    #[error("{what}: {source}")]
    #[diagnostic(code(fpl::E052))]
    Io {
        /// What was being done.
        what: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The driver said something that does not follow its line protocol.
    #[error("the C driver: {0}")]
    #[diagnostic(code(fpl::E053))]
    Protocol(String),
}

fn io_err(what: &str) -> impl FnOnce(std::io::Error) -> DriverError + '_ {
    move |source| DriverError::Io { what: what.to_string(), source }
}

fn protocol(msg: impl Into<String>) -> DriverError {
    DriverError::Protocol(msg.into())
}

impl Driver {
    /// Compiles `header` (an instrumented `flight_plan.h`) with the stub runtime and starts the
    /// server. `cc` is taken from `$CC`, else `cc`. `leaf_budget` bounds the paths of one
    /// explored call; `question_limit` the questions one call may ask before it is reported
    /// as not ending (the validator passes the static bound).
    pub fn build(
        header: &str,
        leaf_budget: usize,
        question_limit: usize,
    ) -> Result<Driver, DriverError> {
        let dir = next_unique_dir();
        std::fs::create_dir_all(dir.join("include/generated")).map_err(io_err("temp dir"))?;
        std::fs::create_dir_all(dir.join("include/modules/core")).map_err(io_err("temp dir"))?;
        for (rel, text) in STUB_FILES {
            std::fs::write(dir.join(rel), text).map_err(io_err(rel))?;
        }
        std::fs::write(dir.join("flight_plan.h"), header).map_err(io_err("flight_plan.h"))?;
        std::fs::write(dir.join("explore_driver.c"), DRIVER_C).map_err(io_err("driver"))?;
        let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_string());
        let out = Command::new(&cc)
            .current_dir(&dir)
            .args(["-std=c99", "-O0", "-w", "-Iinclude", "-I."])
            .args([
                "-Dfp_cond=vouch_stub_fp_cond",
                "-Dfp_code=vouch_stub_fp_code",
                "-Dfp_value=vouch_stub_fp_value",
            ])
            .args(["fp_stub.c", "explore_driver.c", "-o", "driver"])
            .output();
        let out = match out {
            Ok(o) => o,
            Err(source) => {
                let _ = std::fs::remove_dir_all(&dir);
                return Err(DriverError::NoCompiler { cc, source });
            }
        };
        if !out.status.success() {
            let _ = std::fs::remove_dir_all(&dir);
            let msg = String::from_utf8_lossy(&out.stderr);
            let first: Vec<&str> = msg.lines().take(20).collect();
            return Err(DriverError::HeaderRejected { log: first.join("\n") });
        }
        Self::start(dir, leaf_budget, question_limit)
    }

    fn start(
        dir: PathBuf,
        leaf_budget: usize,
        question_limit: usize,
    ) -> Result<Driver, DriverError> {
        let mut child = Command::new(dir.join("driver"))
            .arg(leaf_budget.to_string())
            .arg(question_limit.to_string())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .map_err(io_err("cannot start the driver"))?;
        let stdin = child.stdin.take().ok_or_else(|| protocol("no standard input"))?;
        let stdout =
            BufReader::new(child.stdout.take().ok_or_else(|| protocol("no standard output"))?);
        Ok(Driver { dir, child, stdin, stdout })
    }

    fn send(&mut self, request: char, calls: usize, answers: &[i64]) -> Result<(), DriverError> {
        let mut line = format!("{request} {calls} {}", answers.len());
        for a in answers {
            line.push(' ');
            line.push_str(&a.to_string());
        }
        line.push('\n');
        self.stdin.write_all(line.as_bytes()).map_err(io_err("driver write"))?;
        self.stdin.flush().map_err(io_err("driver write"))
    }

    fn read_line(&mut self) -> Result<String, DriverError> {
        let mut l = String::new();
        let n = self.stdout.read_line(&mut l).map_err(io_err("driver read"))?;
        if n == 0 {
            return Err(protocol("the driver ended unexpectedly"));
        }
        if l.ends_with('\n') {
            l.pop();
        }
        Ok(l)
    }

    /// Replays `calls` calls with `answers`, then explores every path of the next call.
    pub fn explore(&mut self, calls: usize, answers: &[i64]) -> Result<Explored, DriverError> {
        self.send('E', calls, answers)?;
        let mut ex = Explored::default();
        let mut cur: Option<(Vec<i64>, Vec<String>)> = None;
        let mut in_init = false;
        loop {
            let l = self.read_line()?;
            let (tag, rest) = l.split_once(' ').unwrap_or((l.as_str(), ""));
            match tag {
                "I" => {
                    in_init = true;
                    ex.init = Some(Vec::new());
                }
                "Q" => {
                    in_init = false;
                    ex.replayed = Some(parse_state(rest)?);
                }
                "P" => cur = Some((parse_answers(rest)?, Vec::new())),
                "S" => {
                    let (answers, events) =
                        cur.take().ok_or_else(|| protocol("S line outside a path"))?;
                    ex.paths.push(CPath::Done { answers, events, after: parse_state(rest)? });
                }
                "L" => ex.paths.push(CPath::TooLong { answers: parse_answers(rest)? }),
                "A" => {
                    let (st, rest) = rest.split_once(' ').unwrap_or((rest, "0"));
                    let status =
                        st.parse::<i64>().map_err(|_| protocol(format!("bad line '{l}'")))?;
                    ex.paths.push(CPath::Crashed { status, answers: parse_answers(rest)? });
                }
                "done" => {
                    ex.cut = rest.trim() == "1";
                    return Ok(ex);
                }
                _ => {
                    if let Some((_, ev)) = cur.as_mut() {
                        ev.push(l);
                    } else if in_init {
                        if let Some(i) = ex.init.as_mut() {
                            i.push(l);
                        }
                    } else {
                        return Err(protocol(format!("unexpected line '{l}'")));
                    }
                }
            }
        }
    }

    /// One plain run of `calls` calls; returns the trace text (format of `Run::to_text`) and
    /// whether the process ended normally.
    pub fn walk(&mut self, calls: usize, answers: &[i64]) -> Result<(String, bool), DriverError> {
        self.send('W', calls, answers)?;
        let mut out = String::new();
        let mut ok = true;
        loop {
            let l = self.read_line()?;
            if l.starts_with("done ") {
                return Ok((out, ok));
            }
            if l.starts_with("A ") {
                ok = false;
                continue;
            }
            out.push_str(&l);
            out.push('\n');
        }
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn parse_answers(rest: &str) -> Result<Vec<i64>, DriverError> {
    let mut it = rest.split_whitespace();
    let n: usize = it
        .next()
        .and_then(|w| w.parse().ok())
        .ok_or_else(|| protocol(format!("bad answer list '{rest}'")))?;
    let v = it
        .map(|w| w.parse::<i64>().map_err(|_| protocol(format!("bad answer '{w}'"))))
        .collect::<Result<Vec<_>, _>>()?;
    if v.len() != n {
        return Err(protocol(format!("answer count mismatch in '{rest}'")));
    }
    Ok(v)
}

fn parse_state(rest: &str) -> Result<[usize; 4], DriverError> {
    let v: Vec<usize> = rest.split_whitespace().filter_map(|w| w.parse().ok()).collect();
    match v.as_slice() {
        [a, b, c, d] => Ok([*a, *b, *c, *d]),
        _ => Err(protocol(format!("bad state line '{rest}'"))),
    }
}
