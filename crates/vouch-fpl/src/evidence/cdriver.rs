//! Builds and talks to the C side of translation validation: the generated (instrumented)
//! header with its state variables registered ([`super::cstate`]), the project's stub runtime
//! and [`DRIVER_C`], compiled by the system C compiler into a small server process. The server
//! restores a given C state, runs every path of one `auto_nav` call (and every operator jump)
//! from it, and reports the events and the state after each (see the comment at the top of
//! `c/explore_driver.c` for the line protocol).
//!
//! The stub runtime sources are embedded from `tests/stub/` so the `vouch` binary can validate
//! without the source tree; the runtime is therefore the same one the compiler's own tests use.

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

use super::cstate::{self, Discovery};

pub const DRIVER_C: &str = include_str!("c/explore_driver.c");

/// The stub runtime's declarations: its globals are state variables too.
pub const RUNTIME_H: &str = include_str!("../../tests/stub/include/fp_stub.h");

/// (relative path, contents) of the stub runtime files.
const STUB_FILES: &[(&str, &str)] = &[
    ("fp_stub.c", include_str!("../../tests/stub/fp_stub.c")),
    ("include/fp_stub.h", RUNTIME_H),
    ("include/std.h", include_str!("../../tests/stub/include/std.h")),
    ("include/autopilot.h", include_str!("../../tests/stub/include/autopilot.h")),
    ("include/generated/modules.h", include_str!("../../tests/stub/include/generated/modules.h")),
    ("include/modules/core/abi.h", include_str!("../../tests/stub/include/modules/core/abi.h")),
];

/// What the driver is asked to explore with (fixed for one build).
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Paths of one explored call before the request is cut.
    pub leaf_budget: usize,
    /// Questions one call may ask before it is reported as not ending.
    pub question_limit: usize,
    /// Values tried for a non-literal integer (inclusive).
    pub values: (i64, i64),
}

/// A compiled driver in its own temporary directory (removed on drop).
pub struct Driver {
    dir: PathBuf,
    limits: Limits,
    proc: Proc,
    /// The state variables, in the order of the state bytes.
    pub discovery: Discovery,
    /// Byte offset of every variable in the state bytes (one more entry: the total length).
    pub offsets: Vec<usize>,
    /// Size of the watched data segment, when the driver can watch it for unregistered writes.
    pub watched: Option<usize>,
    /// Processes started after a crash.
    pub restarts: usize,
}

struct Proc {
    child: Child,
    stdin: ChildStdin,
    stdout: BufReader<ChildStdout>,
}

/// The run of the same answers from a copy of the state with its dropped parts changed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Second {
    /// Same questions and events; the state after it.
    Same(Vec<u8>),
    /// Other questions or other events (those it produced).
    Differs(Vec<String>),
}

/// One run the C made from a requested state: a call path or an operator jump.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CRun {
    /// A complete path or jump: answers consumed (empty for a jump), event lines, state after,
    /// the runs from the copies (in order, up to the first that differs), and offsets of the
    /// watched segment written outside the registered variables.
    Done {
        jump: Option<usize>,
        answers: Vec<i64>,
        events: Vec<String>,
        after: Vec<u8>,
        seconds: Vec<Second>,
        hidden: Vec<usize>,
    },
    /// The call asked more questions than the limit (a loop inside one call).
    TooLong { answers: Vec<i64> },
    /// The process died (signal or time-out) on this answer prefix, or during the operator
    /// jump to this block.
    Crashed { status: i64, answers: Vec<i64>, jump: Option<usize> },
}

impl CRun {
    /// The answers the run consumed.
    pub fn answers(&self) -> &[i64] {
        match self {
            CRun::Done { answers, .. }
            | CRun::TooLong { answers }
            | CRun::Crashed { answers, .. } => answers,
        }
    }
}

/// Everything the driver reported for one state.
#[derive(Debug, Clone, Default)]
pub struct Expansion {
    /// Call paths, then jumps (when asked for).
    pub runs: Vec<CRun>,
    /// The path budget ran out.
    pub cut: bool,
}

/// `auto_nav_init()` from the initial state.
#[derive(Debug, Clone)]
pub struct Initial {
    pub events: Vec<String>,
    pub state: Vec<u8>,
    pub hidden: Vec<usize>,
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

/// Compiles the driver in `dir`; `Ok(Err(log))` when the compiler rejects the sources.
fn compile(dir: &std::path::Path) -> Result<Result<(), String>, DriverError> {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_string());
    let out = Command::new(&cc)
        .current_dir(dir)
        .args(["-std=c99", "-O0", "-w", "-Iinclude", "-I."])
        .args([
            "-Dfp_cond=vouch_stub_fp_cond",
            "-Dfp_code=vouch_stub_fp_code",
            "-Dfp_value=vouch_stub_fp_value",
        ])
        // everything resolved at start-up, the GOT read-only: the watched segment then holds
        // only the program's own static variables
        .args(["-Wl,-z,relro,-z,now"])
        .args(["fp_stub.c", "explore_driver.c", "-o", "driver"])
        .output()
        .map_err(|source| DriverError::NoCompiler { cc, source })?;
    if out.status.success() {
        return Ok(Ok(()));
    }
    let msg = String::from_utf8_lossy(&out.stderr);
    Ok(Err(msg.lines().take(20).collect::<Vec<_>>().join("\n")))
}

impl Driver {
    /// Compiles `header` (an instrumented `flight_plan.h`) with its state variables registered
    /// and the stub runtime, and starts the server.
    pub fn build(header: &str, limits: Limits) -> Result<Driver, DriverError> {
        let dir = next_unique_dir();
        let discovery = cstate::discover(header, RUNTIME_H);
        let written = (|| {
            std::fs::create_dir_all(dir.join("include/generated")).map_err(io_err("temp dir"))?;
            std::fs::create_dir_all(dir.join("include/modules/core"))
                .map_err(io_err("temp dir"))?;
            for (rel, text) in STUB_FILES {
                std::fs::write(dir.join(rel), text).map_err(io_err(rel))?;
            }
            std::fs::write(dir.join("flight_plan.h"), &discovery.registered_header)
                .map_err(io_err("flight_plan.h"))?;
            std::fs::write(dir.join("vouch_runtime_vars.h"), &discovery.runtime_registrations)
                .map_err(io_err("vouch_runtime_vars.h"))?;
            std::fs::write(dir.join("explore_driver.c"), DRIVER_C).map_err(io_err("driver"))?;
            compile(&dir)
        })();
        match written {
            Ok(Ok(())) => {}
            Ok(Err(log)) => {
                let _ = std::fs::remove_dir_all(&dir);
                return Err(DriverError::HeaderRejected { log });
            }
            Err(e) => {
                let _ = std::fs::remove_dir_all(&dir);
                return Err(e);
            }
        }
        let proc = match Self::spawn(&dir, limits) {
            Ok(p) => p,
            Err(e) => {
                let _ = std::fs::remove_dir_all(&dir);
                return Err(e);
            }
        };
        let mut d = Driver {
            dir,
            limits,
            proc,
            discovery,
            offsets: Vec::new(),
            watched: None,
            restarts: 0,
        };
        d.read_table()?;
        Ok(d)
    }

    fn spawn(dir: &std::path::Path, l: Limits) -> Result<Proc, DriverError> {
        let mut child = Command::new(dir.join("driver"))
            .args([l.leaf_budget, l.question_limit].map(|n| n.to_string()))
            .args([l.values.0, l.values.1].map(|n| n.to_string()))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .map_err(io_err("cannot start the driver"))?;
        let stdin = child.stdin.take().ok_or_else(|| protocol("no standard input"))?;
        let stdout =
            BufReader::new(child.stdout.take().ok_or_else(|| protocol("no standard output"))?);
        Ok(Proc { child, stdin, stdout })
    }

    /// The first two lines of a fresh process: the variable sizes and the watched segment.
    fn read_table(&mut self) -> Result<(), DriverError> {
        let vars = self.read_line()?;
        let sizes: Vec<usize> = vars
            .strip_prefix("vars ")
            .ok_or_else(|| protocol(format!("expected the variable table, got '{vars}'")))?
            .split_whitespace()
            .skip(1)
            .map(|w| w.parse().map_err(|_| protocol(format!("bad size '{w}'"))))
            .collect::<Result<_, _>>()?;
        if sizes.len() != self.discovery.vars.len() {
            return Err(protocol(format!(
                "{} variables registered, {} discovered",
                sizes.len(),
                self.discovery.vars.len()
            )));
        }
        let mut offsets = Vec::with_capacity(sizes.len() + 1);
        let mut at = 0;
        for s in &sizes {
            offsets.push(at);
            at += s;
        }
        offsets.push(at);
        self.offsets = offsets;
        let watch = self.read_line()?;
        let w: i64 = watch
            .strip_prefix("watch ")
            .and_then(|w| w.trim().parse().ok())
            .ok_or_else(|| protocol(format!("bad watch line '{watch}'")))?;
        self.watched = usize::try_from(w).ok();
        Ok(())
    }

    /// Length of the state bytes.
    pub fn state_len(&self) -> usize {
        self.offsets.last().copied().unwrap_or(0)
    }

    /// The bytes of variable `id` in `state`.
    pub fn var_bytes<'s>(&self, state: &'s [u8], id: usize) -> &'s [u8] {
        match (self.offsets.get(id), self.offsets.get(id + 1)) {
            (Some(&a), Some(&b)) if b <= state.len() => &state[a..b],
            _ => &[],
        }
    }

    fn restart(&mut self) -> Result<(), DriverError> {
        let _ = self.proc.child.kill();
        let _ = self.proc.child.wait();
        self.proc = Self::spawn(&self.dir, self.limits)?;
        self.restarts += 1;
        self.read_table()
    }

    fn send(&mut self, line: &str) -> Result<(), DriverError> {
        self.proc.stdin.write_all(line.as_bytes()).map_err(io_err("driver write"))?;
        self.proc.stdin.write_all(b"\n").map_err(io_err("driver write"))?;
        self.proc.stdin.flush().map_err(io_err("driver write"))
    }

    fn read_line(&mut self) -> Result<String, DriverError> {
        let mut l = String::new();
        let n = self.proc.stdout.read_line(&mut l).map_err(io_err("driver read"))?;
        if n == 0 {
            return Err(protocol("the driver ended unexpectedly"));
        }
        if l.ends_with('\n') {
            l.pop();
        }
        Ok(l)
    }

    /// `auto_nav_init()` from the initial state.
    pub fn initial(&mut self) -> Result<Initial, DriverError> {
        self.send("I")?;
        let mut init = Initial { events: Vec::new(), state: Vec::new(), hidden: Vec::new() };
        loop {
            let l = self.read_line()?;
            let (tag, rest) = l.split_once(' ').unwrap_or((l.as_str(), ""));
            match tag {
                "I" => {}
                "Z" => init.state = parse_hex(rest)?,
                "H" => init.hidden.push(parse_num(rest)?),
                "done" => return Ok(init),
                _ => init.events.push(l),
            }
        }
    }

    /// Every path of one call from `state` (each repeated from every copy), then, when `jumps`
    /// is set, an operator jump to every block.
    pub fn expand(
        &mut self,
        state: &[u8],
        copies: &[Vec<u8>],
        jumps: bool,
    ) -> Result<Expansion, DriverError> {
        let mut line = format!("X {} {} {}", u8::from(jumps), hex(state), copies.len());
        for c in copies {
            line.push(' ');
            line.push_str(&hex(c));
        }
        self.send(&line)?;
        let mut ex = Expansion::default();
        let mut cur: Option<CRun> = None;
        loop {
            let l = match self.read_line() {
                Ok(l) => l,
                Err(DriverError::Protocol(_)) => {
                    // died without a word (e.g. a stack overflow): a crash on the run in progress
                    finish(&mut ex, cur.take());
                    ex.runs.push(CRun::Crashed { status: -1, answers: Vec::new(), jump: None });
                    self.restart()?;
                    return Ok(ex);
                }
                Err(e) => return Err(e),
            };
            let (tag, rest) = l.split_once(' ').unwrap_or((l.as_str(), ""));
            match tag {
                "A" => {
                    finish(&mut ex, cur.take());
                    ex.runs.push(crashed(rest)?);
                    // the process ends after its "done": start another one
                    let _ = self.read_line();
                    self.restart()?;
                    return Ok(ex);
                }
                "done" => {
                    finish(&mut ex, cur.take());
                    ex.cut = rest.trim() == "1";
                    return Ok(ex);
                }
                _ => record_line(&mut ex, &mut cur, &l, (state, copies))?,
            }
        }
    }

    /// One plain run of `calls` calls from the initial state, in a child process; returns the
    /// trace text (format of `Run::to_text`) and whether the process ended normally.
    pub fn walk(&mut self, calls: usize, answers: &[i64]) -> Result<(String, bool), DriverError> {
        let mut line = format!("W {calls} {}", answers.len());
        for a in answers {
            line.push(' ');
            line.push_str(&a.to_string());
        }
        self.send(&line)?;
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
        let _ = self.proc.child.kill();
        let _ = self.proc.child.wait();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn finish(ex: &mut Expansion, run: Option<CRun>) {
    ex.runs.extend(run);
}

fn done_run(jump: Option<usize>, answers: Vec<i64>) -> CRun {
    CRun::Done {
        jump,
        answers,
        events: Vec::new(),
        after: Vec::new(),
        seconds: Vec::new(),
        hidden: Vec::new(),
    }
}

/// `A <status> k a1..ak` or `A <status> J b`.
fn crashed(rest: &str) -> Result<CRun, DriverError> {
    let (st, rest) = rest.split_once(' ').unwrap_or((rest, "0"));
    let status = st.parse::<i64>().map_err(|_| protocol(format!("bad status '{st}'")))?;
    Ok(match rest.strip_prefix("J ") {
        Some(b) => CRun::Crashed { status, answers: Vec::new(), jump: Some(parse_num(b)?) },
        None => CRun::Crashed { status, answers: parse_answers(rest)?, jump: None },
    })
}

/// One line of an `X` answer other than its end: a record starts (`P`, `J`, `L`) or the current
/// one goes on (`S`, `T`, `H`, event lines). `states` are the requested state and its copies.
fn record_line(
    ex: &mut Expansion,
    cur: &mut Option<CRun>,
    l: &str,
    states: (&[u8], &[Vec<u8>]),
) -> Result<(), DriverError> {
    let (tag, rest) = l.split_once(' ').unwrap_or((l, ""));
    match (tag, cur.as_mut()) {
        ("P", _) => {
            finish(ex, cur.take());
            *cur = Some(done_run(None, parse_answers(rest)?));
        }
        ("J", _) => {
            finish(ex, cur.take());
            *cur = Some(done_run(Some(parse_num(rest)?), Vec::new()));
        }
        ("L", _) => {
            finish(ex, cur.take());
            ex.runs.push(CRun::TooLong { answers: parse_answers(rest)? });
        }
        ("S", Some(CRun::Done { after, .. })) => *after = apply_changes(states.0, rest)?,
        ("T", Some(CRun::Done { seconds, .. })) => {
            let (i, changes) = rest.split_once(' ').unwrap_or((rest, ""));
            let base = states.1.get(parse_num(i)?).ok_or_else(|| protocol("T line for no copy"))?;
            seconds.push(if changes.trim() == "!" {
                Second::Differs(Vec::new())
            } else {
                Second::Same(apply_changes(base, changes)?)
            })
        }
        // (a run that did not end is reported as such already)
        ("H", Some(CRun::Done { hidden, .. })) => hidden.push(parse_num(rest)?),
        ("H", _) => {}
        ("S" | "T", _) => return Err(protocol(format!("{tag} line outside a run"))),
        (_, Some(CRun::Done { seconds, events, .. })) => match seconds.last_mut() {
            Some(Second::Differs(ev2)) => ev2.push(l.to_string()),
            _ => events.push(l.to_string()),
        },
        _ => return Err(protocol(format!("unexpected line '{l}'"))),
    }
    Ok(())
}

/// Lowercase hexadecimal text of `bytes`.
pub fn hex(bytes: &[u8]) -> String {
    const DIGITS: &[u8; 16] = b"0123456789abcdef";
    let mut s = String::with_capacity(2 * bytes.len());
    for b in bytes {
        s.push(char::from(DIGITS[usize::from(b >> 4)]));
        s.push(char::from(DIGITS[usize::from(b & 15)]));
    }
    s
}

fn parse_hex(text: &str) -> Result<Vec<u8>, DriverError> {
    let t = text.trim().as_bytes();
    if !t.len().is_multiple_of(2) {
        return Err(protocol("odd hexadecimal state"));
    }
    t.chunks(2)
        .map(|c| {
            std::str::from_utf8(c)
                .ok()
                .and_then(|s| u8::from_str_radix(s, 16).ok())
                .ok_or_else(|| protocol("bad hexadecimal state"))
        })
        .collect()
}

fn parse_num(text: &str) -> Result<usize, DriverError> {
    text.trim().parse().map_err(|_| protocol(format!("bad number '{text}'")))
}

/// `base` with the ` offset=value` changes of a driver line applied.
fn apply_changes(base: &[u8], changes: &str) -> Result<Vec<u8>, DriverError> {
    let mut s = base.to_vec();
    for w in changes.split_whitespace() {
        let (o, v) = w.split_once('=').ok_or_else(|| protocol(format!("bad change '{w}'")))?;
        let o: usize = o.parse().map_err(|_| protocol(format!("bad offset '{o}'")))?;
        let v: u8 = v.parse().map_err(|_| protocol(format!("bad byte '{v}'")))?;
        *s.get_mut(o).ok_or_else(|| protocol(format!("offset {o} out of the state")))? = v;
    }
    Ok(s)
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
