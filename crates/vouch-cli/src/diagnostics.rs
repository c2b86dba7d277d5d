//! Prints diagnostics on standard error, once, in the format chosen by `--message-format`.

use std::io::{self, IsTerminal, Write};

use clap::ValueEnum;
use miette::{Diagnostic, GraphicalReportHandler, GraphicalTheme, SourceSpan};

use crate::safe_text::SafeDiagnostic;

/// How diagnostics are printed on standard error.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum MessageFormat {
    /// Boxes with the source excerpt (a plain variant when stderr is not a terminal).
    #[default]
    Human,
    /// One line per message: `file:line:col: error[CODE]: message`, for editors and CI.
    Short,
    /// One JSON object per message (JSON Lines).
    Json,
}

/// Severity used when a diagnostic does not state its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Severity {
    /// An error: the command failed.
    Error,
    /// A warning: the command went on.
    Warning,
}

/// Where a diagnostic points: file name and 1-based line and column.
struct Location {
    file: Option<String>,
    line: usize,
    column: usize,
}

fn location(d: &dyn Diagnostic) -> Option<Location> {
    let source = d.source_code()?;
    let span: SourceSpan = d.labels()?.next()?.inner().to_owned();
    let contents = source.read_span(&span, 0, 0).ok()?;
    Some(Location {
        file: contents.name().map(str::to_owned),
        line: contents.line() + 1,
        column: contents.column() + 1,
    })
}

fn severity_of(d: &dyn Diagnostic, default: Severity) -> &'static str {
    match d.severity() {
        Some(miette::Severity::Error) => "error",
        Some(miette::Severity::Warning) => "warning",
        Some(miette::Severity::Advice) => "note",
        None => match default {
            Severity::Error => "error",
            Severity::Warning => "warning",
        },
    }
}

/// `file:line:col: error[CODE]: message` (the parts that are unknown are left out).
pub fn short_line(d: &dyn Diagnostic, default: Severity) -> String {
    let mut s = String::new();
    if let Some(loc) = location(d) {
        if let Some(f) = &loc.file {
            s.push_str(f);
            s.push(':');
        }
        s.push_str(&format!("{}:{}: ", loc.line, loc.column));
    }
    s.push_str(severity_of(d, default));
    if let Some(code) = d.code() {
        s.push_str(&format!("[{code}]"));
    }
    s.push_str(&format!(": {d}"));
    s
}

fn json_object(d: &dyn Diagnostic, default: Severity) -> serde_json::Value {
    let loc = location(d);
    serde_json::json!({
        "severity": severity_of(d, default),
        "code": d.code().map(|c| c.to_string()),
        "message": d.to_string(),
        "file": loc.as_ref().and_then(|l| l.file.clone()),
        "line": loc.as_ref().map(|l| l.line),
        "column": loc.as_ref().map(|l| l.column),
        "help": d.help().map(|h| h.to_string()),
    })
}

/// `line(d)`, then `line(r)` for each diagnostic related to `d`, joined by newlines.
fn one_per_line(d: &dyn Diagnostic, line: &dyn Fn(&dyn Diagnostic) -> String) -> String {
    let mut lines = vec![line(d)];
    lines.extend(d.related().into_iter().flatten().map(line));
    lines.join("\n")
}

/// Prints one diagnostic on stderr (errors of stderr itself are ignored: nowhere to report them).
/// Every text of it is escaped first ([`SafeDiagnostic`]): messages and excerpts quote input.
pub fn print(format: MessageFormat, d: &dyn Diagnostic, default: Severity) {
    let safe = SafeDiagnostic::new(d);
    let d: &dyn Diagnostic = &safe;
    let text = match format {
        // One line per message: the related diagnostics (the other errors of a rejected
        // input, notes) follow on their own lines; the human format draws them itself.
        MessageFormat::Short => one_per_line(d, &|x| short_line(x, default)),
        MessageFormat::Json => one_per_line(d, &|x| json_object(x, default).to_string()),
        MessageFormat::Human => {
            let theme = if io::stderr().is_terminal() {
                GraphicalTheme::unicode()
            } else {
                GraphicalTheme::unicode_nocolor()
            };
            let mut s = String::new();
            match GraphicalReportHandler::new_themed(theme).render_report(&mut s, d) {
                Ok(()) => s.trim_end().to_owned(),
                Err(_) => short_line(d, default),
            }
        }
    };
    let _ = writeln!(io::stderr(), "{text}");
}
