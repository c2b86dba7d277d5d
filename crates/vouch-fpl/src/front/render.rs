//! Rendering of diagnostics with miette (source snippet with a label under the span).

use miette::{
    GraphicalReportHandler, GraphicalTheme, LabeledSpan, MietteDiagnostic, NamedSource, Report,
};

use super::diag::{Diagnostic, Severity};
use crate::ast::SourceMap;

pub(crate) fn render_one(d: &Diagnostic, sources: &SourceMap, color: bool) -> String {
    let sev = match d.severity {
        Severity::Error => "error",
        Severity::Warning => "warning",
    };
    let mut head = String::new();
    if let (Some(f), Some(l), Some(c)) = (&d.file, d.line, d.col) {
        head.push_str(&format!("{f}:{l}:{c}: "));
    }
    head.push_str(&format!("{sev}[{:?}]: {}\n", d.kind, d.message));
    let Some(span) = d.span else {
        return head;
    };
    let Some(file) = sources.get(span.file) else {
        return head;
    };
    let mut md = MietteDiagnostic::new(d.message.clone())
        .with_label(LabeledSpan::at(span.range(), format!("{:?}", d.kind)));
    if let Some(h) = &d.help {
        md = md.with_help(h.clone());
    }
    md = md.with_severity(match d.severity {
        Severity::Error => miette::Severity::Error,
        Severity::Warning => miette::Severity::Warning,
    });
    let report =
        Report::new(md).with_source_code(NamedSource::new(file.path.clone(), file.text.clone()));
    let theme = if color { GraphicalTheme::unicode() } else { GraphicalTheme::unicode_nocolor() };
    let mut s = String::new();
    if GraphicalReportHandler::new_themed(theme).render_report(&mut s, report.as_ref()).is_ok() {
        head.push_str(&s);
    }
    head
}
