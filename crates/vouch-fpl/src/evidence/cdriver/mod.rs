//! Builds and talks to the C side of translation validation: the generated (instrumented)
//! header with its state variables registered ([`super::cstate`]), the project's stub runtime
//! and [`DRIVER_C`], compiled into a small server for a [`Target`]: a process on the host, or a
//! program on an emulated Cortex-M core (module `build`). The server restores a given C state,
//! runs every path of one `auto_nav` call (and every operator jump) from it, and reports the
//! events and the state after each (see the comment at the top of `c/explore_driver.c` for the
//! line protocol, read in module `protocol`).
//!
//! The stub runtime sources are embedded from `tests/stub/` so the `vouch` binary can validate
//! without the source tree; the runtime is therefore the same one the compiler's own tests use.

mod build;
mod protocol;
mod standins;

use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdin, ChildStdout, Stdio};

pub use build::{DRIVER_C, RUNTIME_H, Target, comparison_constants};
use protocol::{crashed, finish, parse_hex, parse_num, record_line};

use super::cstate::{self, Discovery};

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

/// A compiled driver in its own private temporary directory (removed on drop).
pub struct Driver {
    dir: tempfile::TempDir,
    limits: Limits,
    /// Where it runs.
    pub target: Target,
    /// The code-generation flags it was compiled with.
    pub cflags: Vec<String>,
    proc: Proc,
    /// The state variables, in the order of the state bytes.
    pub discovery: Discovery,
    /// The decimal constants of the plan's comparisons, as written (see [`Driver::constants`]).
    pub constants: Vec<String>,
    /// Byte offset of every variable in the state bytes (one more entry: the total length).
    pub offsets: Vec<usize>,
    /// Size of the watched data segment, when the driver can watch it for unregistered writes.
    pub watched: Option<usize>,
    /// Processes started after a crash.
    pub restarts: usize,
    /// The `K` request (how the runs of one call are joined), sent again to a restarted
    /// driver.
    joining: Option<String>,
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
    /// Same questions and events up to a stage start where the run met the explored run, its
    /// state the same but for counters both had put back (each to its own start value): from
    /// there on it is that run, so its state after keeps every rule of the changed-state runs
    /// by construction (a changed counter ends as the explored run's or at its own start).
    Met,
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
        /// The run stopped at a stage start, joined to this node of the call (its answers and
        /// events are those before it; no state after, no runs from the copies).
        joined: Option<usize>,
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
    /// The run budget ran out, or the memory for join points (`memory`).
    pub cut: bool,
    /// The driver had no memory left for another join point (the emulated board's RAM).
    pub memory: bool,
}

/// `auto_nav_init()` from the initial state.
#[derive(Debug, Clone)]
pub struct Initial {
    pub events: Vec<String>,
    pub state: Vec<u8>,
    pub hidden: Vec<usize>,
}

/// Why the C side of the validation could not run.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum DriverError {
    /// The C compiler cannot be started.
    #[error("cannot run the C compiler '{cc}': {source}")]
    #[diagnostic(
        code(fpl::E050),
        help(
            "set CC to a C99 compiler (host), or install gcc-arm-none-eabi and libnewlib-arm-none-eabi (Debian) or set VOUCH_ARM_CC (cortex-m targets)"
        )
    )]
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
    /// The emulator that runs the target build cannot be started.
    #[error("cannot run the emulator '{qemu}': {source}")]
    #[diagnostic(
        code(fpl::E054),
        help("install qemu-system-arm (Debian) or set VOUCH_QEMU_ARM; --target host needs none")
    )]
    NoEmulator {
        /// The emulator command (`$VOUCH_QEMU_ARM` or `qemu-system-arm`).
        qemu: String,
        /// Why it could not start.
        source: std::io::Error,
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

pub(super) fn io_err(what: &str) -> impl FnOnce(std::io::Error) -> DriverError + '_ {
    move |source| DriverError::Io { what: what.to_string(), source }
}

pub(super) fn protocol(msg: impl Into<String>) -> DriverError {
    DriverError::Protocol(msg.into())
}

impl Driver {
    /// Compiles `header` (an instrumented `flight_plan.h`) with its state variables registered
    /// and the stub runtime for `target` (with `cflags`, else the target's default flags), and
    /// starts the server.
    pub fn build(
        header: &str,
        limits: Limits,
        target: Target,
        cflags: Option<&[String]>,
    ) -> Result<Driver, DriverError> {
        build::check_emulator(target)?;
        let cflags = cflags.map_or_else(|| target.default_cflags(), <[String]>::to_vec);
        let dir = tempfile::Builder::new()
            .prefix("vouch-fpl-validate-")
            .permissions(private())
            .tempdir()
            .map_err(io_err("cannot create a private build directory"))?;
        let discovery = cstate::discover(header, RUNTIME_H);
        let constants = build::comparison_constants(header);
        build::write_sources(dir.path(), &discovery, &constants)?;
        if let Err(log) = build::compile(dir.path(), target, &cflags)? {
            return Err(DriverError::HeaderRejected { log });
        }
        let proc = Self::spawn(dir.path(), target, limits)?;
        let mut d = Driver {
            dir,
            limits,
            target,
            cflags,
            proc,
            discovery,
            constants,
            offsets: Vec::new(),
            watched: None,
            restarts: 0,
            joining: None,
        };
        d.read_table()?;
        Ok(d)
    }

    fn spawn(dir: &std::path::Path, target: Target, l: Limits) -> Result<Proc, DriverError> {
        let (mut cmd, intro) = build::command(dir, target, l)?;
        let mut child = cmd
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .map_err(io_err("cannot start the driver"))?;
        let stdin = child.stdin.take().ok_or_else(|| protocol("no standard input"))?;
        let stdout =
            BufReader::new(child.stdout.take().ok_or_else(|| protocol("no standard output"))?);
        let mut p = Proc { child, stdin, stdout };
        if let Some(line) = intro {
            p.stdin.write_all(line.as_bytes()).map_err(io_err("driver write"))?;
            p.stdin.write_all(b"\n").map_err(io_err("driver write"))?;
            p.stdin.flush().map_err(io_err("driver write"))?;
        }
        Ok(p)
    }

    /// The private directory the driver was built in (removed with the driver).
    pub fn build_dir(&self) -> &std::path::Path {
        self.dir.path()
    }

    /// How the driver was built and where it ran, for reports.
    pub fn describe(&self) -> String {
        self.target.describe(&self.cflags)
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
        self.proc = Self::spawn(self.dir.path(), self.target, self.limits)?;
        self.restarts += 1;
        self.read_table()?;
        match self.joining.clone() {
            Some(line) => self.send_joining(&line),
            None => Ok(()),
        }
    }

    /// Joins the runs of one call at stage starts (see `vouch_at_stage` in the driver):
    /// `ranges` are the counter variables as (id, block, init stage, loop-back stage); with
    /// `mask`, a counter is put back to its value at the start of the call at every stage start
    /// outside its loop. On an emulated core the join points may take 1 MiB; a call that needs
    /// more is cut ([`Expansion::memory`]).
    pub fn join_runs(&mut self, mask: bool, ranges: &[[usize; 4]]) -> Result<(), DriverError> {
        // the emulated boards have 4 MiB for code, data, heap and stack: a quarter of it for
        // the join points; beyond, the call is reported cut (no limit on the host)
        let bytes = if self.target == Target::Host { 0 } else { 1 << 20 };
        let mut line = format!("K 1 {} {bytes} {}", u8::from(mask), ranges.len());
        for r in ranges {
            for n in r {
                line.push_str(&format!(" {n}"));
            }
        }
        self.send_joining(&line)?;
        self.joining = Some(line);
        Ok(())
    }

    fn send_joining(&mut self, line: &str) -> Result<(), DriverError> {
        self.send(line)?;
        let l = self.read_line()?;
        if !l.starts_with("done") {
            return Err(protocol(format!("expected the end of the K request, got '{l}'")));
        }
        Ok(())
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
    /// is set, an operator jump to every block. With joined runs ([`Driver::join_runs`]), the
    /// run from a copy numbered `stoppable` or later stops where it meets the explored run
    /// with only put-back counters differing ([`Second::Met`]).
    pub fn expand(
        &mut self,
        state: &[u8],
        copies: &[Vec<u8>],
        stoppable: usize,
        jumps: bool,
    ) -> Result<Expansion, DriverError> {
        let mut line =
            format!("X {} {} {} {stoppable}", u8::from(jumps), hex::encode(state), copies.len());
        for c in copies {
            line.push(' ');
            line.push_str(&hex::encode(c));
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
                    ex.cut = rest.trim() != "0";
                    ex.memory = rest.trim() == "2";
                    return Ok(ex);
                }
                _ => record_line(&mut ex, &mut cur, &l, (state, copies))?,
            }
        }
    }

    /// The values the compiled C gives the [`Driver::constants`], in their order (read back as
    /// the double the compiler made of each literal).
    pub fn constant_values(&mut self) -> Result<Vec<f64>, DriverError> {
        self.send("F")?;
        let mut out = Vec::new();
        loop {
            let l = self.read_line()?;
            if l.starts_with("done") {
                return Ok(out);
            }
            let bytes = l
                .strip_prefix("F ")
                .and_then(|h| hex::decode(h.trim()).ok())
                .and_then(|b| <[u8; 8]>::try_from(b).ok())
                .ok_or_else(|| protocol(format!("bad constant line '{l}'")))?;
            out.push(f64::from_le_bytes(bytes));
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
                if !ok && self.target != Target::Host {
                    // on the target the walk runs in the server itself, which has ended
                    self.restart()?;
                }
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

/// Owner only (0700): no other user can add to or change the programs built there.
fn private() -> std::fs::Permissions {
    use std::os::unix::fs::PermissionsExt;
    std::fs::Permissions::from_mode(0o700)
}

impl Drop for Driver {
    fn drop(&mut self) {
        // (the build directory is removed when `dir` drops)
        let _ = self.proc.child.kill();
        let _ = self.proc.child.wait();
    }
}
