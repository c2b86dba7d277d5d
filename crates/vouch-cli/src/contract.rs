//! The command contract shared by every family: exit codes, failures, the pipe-safe standard
//! output and the one place where diagnostics are printed.
//!
//! Every subcommand is a function `fn(args, &mut Ctx) -> CmdResult`. It writes its main output
//! through [`Ctx::out`] (`writeln!(ctx.out, …)?`), warnings through [`Ctx::warn`], and returns
//! the exit code for its outcome or a [`Failure`]. `main` prints the failure once, in the chosen
//! `--message-format`, and maps it to the exit code. Libraries never print; they return data and
//! typed errors that implement [`miette::Diagnostic`].

use std::fmt;
use std::io::{self, BufWriter, IsTerminal, StdoutLock, Write};
use std::process::ExitCode;

use miette::Diagnostic;

pub use crate::diagnostics::{MessageFormat, Severity};
use crate::safe_text;

/// Exit codes of every `vouch` command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exit {
    /// Success: the input was accepted and nothing was found.
    Ok = 0,
    /// The input (plan, map, protocol, recording, configuration) was rejected.
    Rejected = 1,
    /// Usage error or an I/O error (a file that cannot be read or written, a socket, …).
    Usage = 2,
    /// A checker found violations (or a validation found a disagreement).
    Findings = 3,
}

impl From<Exit> for ExitCode {
    fn from(e: Exit) -> ExitCode {
        ExitCode::from(e as u8)
    }
}

/// Why a command stopped early.
#[derive(Debug)]
pub enum Failure {
    /// The user's input was rejected; the diagnostic says where and why.
    Rejected(miette::Report),
    /// A usage or I/O error.
    Usage(miette::Report),
    /// The reader of standard output went away (`vouch … | head`): end quietly.
    ClosedPipe,
}

impl Failure {
    /// An input rejected by a library, with its located diagnostic.
    pub fn rejected(d: impl Diagnostic + Send + Sync + 'static) -> Failure {
        Failure::Rejected(miette::Report::new(d))
    }

    /// A usage error found after the options were parsed (`{family}::C002`).
    pub fn usage(msg: impl fmt::Display) -> Failure {
        Failure::Usage(miette::Report::new(CliError {
            kind: CliErrorKind::Usage,
            msg: msg.to_string(),
            help: None,
        }))
    }

    /// An I/O error on a named path (`{family}::C001`): an output, or a file beside the main
    /// input, that cannot be read or written.
    pub fn io(path: &std::path::Path, e: &io::Error) -> Failure {
        let msg = format!("{}: {e}", path.display());
        Failure::Usage(miette::Report::new(CliError { kind: CliErrorKind::Io, msg, help: None }))
    }

    /// Reads a text file beside the main input (answers, jumps, …): a failed read is I/O
    /// (`{family}::C001`), bytes that are not UTF-8 are rejected input (`{family}::C003`).
    pub fn read_text(path: &std::path::Path) -> Result<String, Failure> {
        let bytes = std::fs::read(path).map_err(|e| Failure::io(path, &e))?;
        String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            let msg = format!("{}: not a text file (invalid UTF-8 at byte {at})", path.display());
            Failure::Rejected(miette::Report::new(CliError {
                kind: CliErrorKind::NotText,
                msg,
                help: None,
            }))
        })
    }

    /// The exit code this failure ends the process with.
    pub fn exit(&self) -> Exit {
        match self {
            Failure::Rejected(_) => Exit::Rejected,
            Failure::Usage(_) => Exit::Usage,
            Failure::ClosedPipe => Exit::Ok,
        }
    }
}

/// The family of the running command (`fpl`, `mav`, `navfn`; `vouch` for the others), set once
/// by `run` before the command starts, so that the command line's own errors carry a family
/// code like the libraries' errors do.
static FAMILY: std::sync::OnceLock<&'static str> = std::sync::OnceLock::new();

/// Records the running command's family (the first call wins).
pub fn set_family(family: &'static str) {
    let _ = FAMILY.set(family);
}

/// The kinds of errors the command line finds itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum CliErrorKind {
    /// A file or stream the command reads or writes besides its input (`C001`).
    Io,
    /// Options that parse but do not go together, or name nothing (`C002`).
    Usage,
    /// A file read as text that is not text (`C003`, rejected input).
    NotText,
    /// A command line that does not parse: an unknown option, a missing or invalid value
    /// (`C004`, found by clap).
    Syntax,
}

/// An error of the command line itself, coded `{family}::C001` or `{family}::C002`.
#[derive(Debug)]
struct CliError {
    kind: CliErrorKind,
    msg: String,
    help: Option<String>,
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.msg)
    }
}

impl std::error::Error for CliError {}

impl Diagnostic for CliError {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        let family = FAMILY.get().copied().unwrap_or("vouch");
        let n = match self.kind {
            CliErrorKind::Io => "C001",
            CliErrorKind::Usage => "C002",
            CliErrorKind::NotText => "C003",
            CliErrorKind::Syntax => "C004",
        };
        Some(Box::new(format!("{family}::{n}")))
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help.as_ref().map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }
}

/// A command line clap could not parse, as a coded usage failure (`{family}::C004`, exit 2):
/// clap's first line is the message (without its `error: `), the rest (the usage, a hint) the
/// help. Printed like every other diagnostic, so the input it quotes is escaped.
pub fn syntax_failure(clap_text: &str) -> Failure {
    let text = clap_text.trim();
    let (first, rest) = text.split_once('\n').unwrap_or((text, ""));
    let msg = first.strip_prefix("error: ").unwrap_or(first).to_string();
    let rest = rest.trim();
    let help = (!rest.is_empty()).then(|| rest.to_string());
    Failure::Usage(miette::Report::new(CliError { kind: CliErrorKind::Syntax, msg, help }))
}

/// What every subcommand returns.
pub type CmdResult = Result<Exit, Failure>;

/// How much a command says besides its main output.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Verbosity {
    /// `-q`: errors only.
    Quiet,
    /// Errors, warnings and summaries.
    Normal,
    /// `-v`: also progress details.
    Verbose,
}

/// Standard output that reports a closed pipe as [`Failure::ClosedPipe`] instead of panicking.
pub struct Out {
    inner: BufWriter<StdoutLock<'static>>,
}

impl Out {
    /// Buffered standard output (flushed by [`Out::flush`] and at the end of the command).
    pub fn stdout() -> Out {
        Out { inner: BufWriter::with_capacity(64 * 1024, io::stdout().lock()) }
    }

    /// Makes `write!(out, …)?` / `writeln!(out, …)?` return a [`Failure`]. Formatted text is
    /// for people: control characters in it are escaped ([`safe_text::escape`]).
    pub fn write_fmt(&mut self, args: fmt::Arguments<'_>) -> Result<(), Failure> {
        let mut w = safe_text::EscapingWriter { inner: &mut self.inner, error: None };
        match fmt::Write::write_fmt(&mut w, args) {
            Ok(()) => Ok(()),
            Err(_) => Err(match w.error {
                Some(e) => stdout_failure(e),
                None => Failure::usage("standard output: formatting failed"),
            }),
        }
    }

    /// Writes a text rendering for people (tables, outlines, summaries) with its control
    /// characters escaped.
    pub fn text(&mut self, text: &str) -> Result<(), Failure> {
        self.write_all(safe_text::escape(text).as_bytes())
    }

    /// Writes raw bytes unchanged: a generated file sent to standard output (a header, a dump,
    /// golden lines) is an artefact, byte for byte. Text for people goes through [`Out::text`].
    pub fn write_all(&mut self, bytes: &[u8]) -> Result<(), Failure> {
        self.inner.write_all(bytes).map_err(stdout_failure)
    }

    /// Writes one pretty-printed JSON document followed by a newline (DEL, C1 and bidi
    /// controls in strings as `\uXXXX`, like the C0 controls JSON escapes itself).
    pub fn json<T: serde::Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Failure> {
        safe_text::to_json_writer(&mut self.inner, value, true).map_err(json_failure)?;
        self.write_all(b"\n")
    }

    /// Writes one compact JSON value on its own line (JSON Lines streams).
    pub fn json_line<T: serde::Serialize + ?Sized>(&mut self, value: &T) -> Result<(), Failure> {
        safe_text::to_json_writer(&mut self.inner, value, false).map_err(json_failure)?;
        self.write_all(b"\n")
    }

    /// Flushes what was buffered (before a long wait, or before the process ends).
    pub fn flush(&mut self) -> Result<(), Failure> {
        self.inner.flush().map_err(stdout_failure)
    }
}

fn json_failure(e: serde_json::Error) -> Failure {
    match e.io_error_kind() {
        Some(io::ErrorKind::BrokenPipe) => Failure::ClosedPipe,
        _ => Failure::usage(format_args!("standard output: {e}")),
    }
}

fn stdout_failure(e: io::Error) -> Failure {
    if e.kind() == io::ErrorKind::BrokenPipe {
        Failure::ClosedPipe
    } else {
        Failure::usage(format_args!("standard output: {e}"))
    }
}

/// Everything a subcommand needs besides its arguments.
pub struct Ctx {
    /// The main output.
    pub out: Out,
    /// How diagnostics are printed.
    pub format: MessageFormat,
    /// `-q` / `-v`.
    pub verbosity: Verbosity,
}

impl Ctx {
    /// Whether progress bars may be drawn (a terminal on stderr, not `-q`).
    pub fn progress_allowed(&self) -> bool {
        self.verbosity > Verbosity::Quiet && io::stderr().is_terminal()
    }

    /// Prints a warning (a diagnostic of any severity) once, unless `-q`.
    pub fn warn(&self, d: &dyn Diagnostic) {
        if self.verbosity > Verbosity::Quiet {
            crate::diagnostics::print(self.format, d, Severity::Warning);
        }
    }

    /// Prints a plain note on stderr (summaries, progress lines), unless `-q`; escaped like
    /// every message.
    pub fn note(&self, msg: impl fmt::Display) {
        if self.verbosity > Verbosity::Quiet {
            let _ = writeln!(io::stderr(), "{}", safe_text::escape(&msg.to_string()));
        }
    }
}
