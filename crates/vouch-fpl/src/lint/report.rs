//! Presentation of lint warnings: the text of `vouch fpl lint`, counts per rule, and the
//! [`miette::Diagnostic`] view used when warnings are shown beside another command's output.

use std::fmt;

use miette::{LabeledSpan, SourceCode};

use super::{Note, Rule, Warning};
use crate::ast::FlightPlan;
use crate::diag::underline;
use crate::span::Span;

fn source_line(plan: &FlightPlan, span: Span) -> Option<&str> {
    plan.sources.text(span.file).lines().nth(span.line.checked_sub(1)? as usize)
}

fn locate(plan: &FlightPlan, span: Span) -> String {
    format!("{}:{}:{}", plan.sources.path(span.file), span.line, span.col)
}

/// `file:line:col: warning[CODE]: message`, the source line with a caret, and the notes.
pub fn render(plan: &FlightPlan, warnings: &[Warning]) -> String {
    let mut s = String::new();
    for w in warnings {
        s.push_str(&format!(
            "{}: warning[{}]: {}\n",
            locate(plan, w.span),
            w.rule.code(),
            w.message
        ));
        if let Some(line) = source_line(plan, w.span) {
            s.push_str(&format!("  {:>5} | {}\n", w.span.line, line.trim_end()));
            let pad = (w.span.col as usize).saturating_sub(1);
            s.push_str(&format!("        | {}^\n", " ".repeat(pad)));
        }
        for n in &w.notes {
            s.push_str(&format!("  note: {} ({})\n", n.message, locate(plan, n.span)));
        }
    }
    s
}

/// Warnings per rule, in code order (for summaries).
pub fn counts(warnings: &[Warning]) -> Vec<(Rule, usize)> {
    Rule::ALL.iter().map(|r| (*r, warnings.iter().filter(|w| w.rule == *r).count())).collect()
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Warning {}

impl miette::Diagnostic for Warning {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(self.rule.code()))
    }

    fn severity(&self) -> Option<miette::Severity> {
        Some(miette::Severity::Warning)
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.source.as_deref().map(|s| s as &dyn SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        underline(self.source.as_deref(), self.span)
    }

    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn miette::Diagnostic> + 'a>> {
        if self.notes.is_empty() {
            return None;
        }
        Some(Box::new(self.notes.iter().map(|n| n as &dyn miette::Diagnostic)))
    }
}

impl fmt::Display for Note {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Note {}

impl miette::Diagnostic for Note {
    fn severity(&self) -> Option<miette::Severity> {
        Some(miette::Severity::Advice)
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.source.as_deref().map(|s| s as &dyn SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        underline(self.source.as_deref(), self.span)
    }
}
