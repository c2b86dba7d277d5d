//! The three-pass compiler of the VFPG paper (§III-A), each pass with its own IR:
//!
//! ```text
//! AST --lower--> FP --extend--> FPE --size::verify--> FPS --emit--> C
//! ```
//!
//! * [`lower`]: composes the C text of every stage (the paper's pre-processor);
//! * [`extend`]: numbers stages, flattens `while`/`for` bodies, splits two-step navigation
//!   stages into init + main, adds the loop-back (`END_WHILE`) stages;
//! * [`size`]: checks ≤ 256 blocks, ≤ 256 stages per block and consecutive numbering, and
//!   returns [`size::Fps`], whose block and stage numbers are `u8` newtypes that only this pass
//!   can create: an ill-sized plan has no FPS value;
//! * generation is [`crate::emit`], which only accepts an FPS.

pub mod extend;
pub mod fp;
pub mod lower;
pub mod size;

use serde::Serialize;

use crate::ast::FlightPlan;
use crate::diag::{Diagnostic, Diagnostics, ErrorKind};
use crate::span::{SourceMap, Span};

/// A compile-time error of the back end, located in the plan when possible.
#[derive(Debug, Clone, Serialize)]
pub struct CompileError {
    pub message: String,
    pub span: Option<Span>,
    pub kind: CompileErrorKind,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum CompileErrorKind {
    /// Attributes that cannot produce code (upstream's generator-level failures).
    Generation,
    /// More than 256 blocks or stages, or numbering not consecutive (size verification).
    Size,
    /// The Paparazzi home lacks the geoid grid or `conf/abi.xml` (or they are broken).
    Environment,
    /// A flight-plan variable that cannot become a setting.
    Settings,
}

impl CompileError {
    pub fn new(message: impl Into<String>, span: Span) -> Self {
        CompileError {
            message: message.into(),
            span: Some(span),
            kind: CompileErrorKind::Generation,
        }
    }
    pub fn size(message: impl Into<String>, span: Option<Span>) -> Self {
        CompileError { message: message.into(), span, kind: CompileErrorKind::Size }
    }
    /// A problem with the Paparazzi home's data (no span: it is not in the plan).
    pub fn environment(message: impl Into<String>) -> Self {
        CompileError { message: message.into(), span: None, kind: CompileErrorKind::Environment }
    }
    /// A variable that cannot become a setting.
    pub fn settings(message: impl Into<String>, span: Span) -> Self {
        CompileError { message: message.into(), span: Some(span), kind: CompileErrorKind::Settings }
    }
    /// As located diagnostics over the plan's sources (for rendering with a source excerpt).
    pub fn to_diagnostics(&self, sources: &SourceMap) -> Diagnostics {
        let kind = match self.kind {
            CompileErrorKind::Generation => ErrorKind::Generation,
            CompileErrorKind::Size => ErrorKind::TooLarge,
            CompileErrorKind::Environment => ErrorKind::Environment,
            CompileErrorKind::Settings => ErrorKind::Settings,
        };
        Diagnostics::new(
            vec![Diagnostic::error(kind, self.message.clone(), self.span)],
            sources.clone(),
        )
    }
}

impl std::fmt::Display for CompileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for CompileError {}

/// Runs lower, extend and size verification.
pub fn compile(plan: &FlightPlan) -> Result<size::Fps, CompileError> {
    let fp = lower::lower(plan)?;
    let fpe = extend::extend(&fp);
    size::verify(fpe)
}
