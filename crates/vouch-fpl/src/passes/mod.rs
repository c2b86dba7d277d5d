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

use crate::ast::{Block, FlightPlan, Stage, StageKind};
use crate::diag::{Diagnostic, Diagnostics, ErrorKind};
use crate::expr::{Expr, UnOp};
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
    /// A geofence limit below the ground, security or home-mode altitude.
    Geofence,
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
    /// A geofence limit below what the plan needs.
    pub fn geofence(message: impl Into<String>, span: Span) -> Self {
        CompileError { message: message.into(), span: Some(span), kind: CompileErrorKind::Geofence }
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
            CompileErrorKind::Geofence => ErrorKind::Geofence,
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

/// An integer `for` bound must fit the loop's `static int8_t` counter (`from - 1` too):
/// upstream wraps it silently (`to="200"` runs zero times), so vouch refuses to emit a drop-in
/// header for it (the reference semantics models the wrap, so the plan can still be run and
/// validated).
pub fn for_bounds(blocks: &[Block]) -> Result<(), CompileError> {
    fn literal(e: &Expr) -> Option<i64> {
        match e {
            Expr::Int(v) => Some(*v),
            Expr::Unary(UnOp::Neg, x) => literal(x).map(|v| -v),
            _ => None,
        }
    }
    fn walk(stages: &[Stage]) -> Result<(), CompileError> {
        for s in stages {
            match &s.kind {
                StageKind::While(w) => walk(&w.body)?,
                StageKind::For(f) => {
                    for (bound, lo) in [(&f.from, -127), (&f.to, -128)] {
                        if let Some(v) = literal(&bound.expr).filter(|v| *v < lo || *v > 127) {
                            return Err(CompileError::size(
                                format!(
                                    "for bound {v} does not fit the loop counter (int8_t: {lo}..127); \
                                     upstream wraps it silently"
                                ),
                                Some(bound.text.span),
                            ));
                        }
                    }
                    walk(&f.body)?;
                }
                _ => {}
            }
        }
        Ok(())
    }
    blocks.iter().try_for_each(|b| walk(&b.stages))
}
