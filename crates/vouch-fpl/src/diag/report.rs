//! [`miette`] views of the diagnostics: the source file as [`miette::SourceCode`], each
//! [`Diagnostic`] and each [`Diagnostics`] as a [`miette::Diagnostic`].

use std::fmt;

use miette::{LabeledSpan, MietteError, MietteSpanContents, SourceCode, SourceSpan, SpanContents};

use super::{Diagnostic, Diagnostics, Severity};
use crate::span::{SourceFile, Span};

impl SourceCode for SourceFile {
    fn read_span<'a>(
        &'a self,
        span: &SourceSpan,
        context_lines_before: usize,
        context_lines_after: usize,
    ) -> Result<Box<dyn SpanContents<'a> + 'a>, MietteError> {
        let inner = self.text.read_span(span, context_lines_before, context_lines_after)?;
        Ok(Box::new(MietteSpanContents::new_named(
            self.path.clone(),
            inner.data(),
            *inner.span(),
            inner.line(),
            inner.column(),
            inner.line_count(),
        )))
    }
}

/// The one label of a located diagnostic: an underline of `span`, when its file is known.
pub(crate) fn underline(
    source: Option<&SourceFile>,
    span: Span,
) -> Option<Box<dyn Iterator<Item = LabeledSpan>>> {
    source?;
    Some(Box::new(std::iter::once(LabeledSpan::new_with_span(None, span.range()))))
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Diagnostic {}

impl miette::Diagnostic for Diagnostic {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(self.kind.code()))
    }

    fn severity(&self) -> Option<miette::Severity> {
        Some(match self.severity {
            Severity::Error => miette::Severity::Error,
            Severity::Warning => miette::Severity::Warning,
        })
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.help.as_ref().map(|h| Box::new(h) as Box<dyn fmt::Display>)
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.source.as_deref().map(|s| s as &dyn SourceCode)
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        underline(self.source.as_deref(), self.span?)
    }
}

impl Diagnostics {
    /// Index of the item shown first: the first error (or the first item).
    fn primary_index(&self) -> Option<usize> {
        self.items
            .iter()
            .position(|d| d.severity == Severity::Error)
            .or((!self.items.is_empty()).then_some(0))
    }

    fn primary(&self) -> Option<&Diagnostic> {
        self.primary_index().map(|i| &self.items[i])
    }
}

impl fmt::Display for Diagnostics {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.primary() {
            Some(d) => f.write_str(&d.message),
            None => f.write_str("the plan was rejected"),
        }
    }
}

impl std::error::Error for Diagnostics {}

impl miette::Diagnostic for Diagnostics {
    fn code<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.primary()?.code()
    }

    fn severity(&self) -> Option<miette::Severity> {
        Some(miette::Severity::Error)
    }

    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        self.primary()?.help()
    }

    fn source_code(&self) -> Option<&dyn SourceCode> {
        self.primary()?.source_code()
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        self.primary()?.labels()
    }

    fn related<'a>(&'a self) -> Option<Box<dyn Iterator<Item = &'a dyn miette::Diagnostic> + 'a>> {
        let primary = self.primary_index()?;
        if self.items.len() < 2 {
            return None;
        }
        Some(Box::new(
            self.items
                .iter()
                .enumerate()
                .filter(move |(i, _)| *i != primary)
                .map(|(_, d)| d as &dyn miette::Diagnostic),
        ))
    }
}
