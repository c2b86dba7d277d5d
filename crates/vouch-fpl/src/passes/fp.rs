//! FP: the flight plan as the paper's Fig. 1 structure (`flight_plan`, `fp_block`, `fp_stage`),
//! extended with every stage kind of the DTD and with the C text of each external action
//! already composed (the pre-processor's job in the VFPG architecture).
//!
//! This is the input of the three passes *and* of the reference interpreter
//! ([`crate::semantics`]). It knows nothing of XML: block references are indices, waypoints are
//! upstream indices, and every piece of C the plan runs is a [`Code`] or [`Cond`] text.

use serde::Serialize;

use crate::ast::Resume;
use crate::span::Span;

/// Index of a block (0-based, upstream numbering; the implicit `HOME` block is last).
pub type BlockIx = usize;

/// One C statement the plan executes (an external action in the paper's trace model).
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Code {
    /// The statement text, without the terminating `;`.
    pub text: String,
    /// Whether upstream prints a `;` after it (`Goto3D(..)` is the one exception).
    pub semi: bool,
}

impl Code {
    pub fn stmt(text: impl Into<String>) -> Code {
        Code { text: text.into(), semi: true }
    }
}

/// A C condition (evaluated by the oracle in the semantics).
pub type Cond = String;

#[derive(Debug, Clone, Serialize)]
pub struct Fp {
    pub blocks: Vec<FpBlock>,
    /// Global exceptions, tested at every call before the current block runs.
    pub exceptions: Vec<FpException>,
    /// VFPG extension: block changes that must not happen.
    pub forbidden: Vec<FpForbidden>,
    /// Statements of `auto_nav_init()` (ABI bindings), run once before the first call.
    pub init: Vec<Code>,
}

#[derive(Debug, Clone, Serialize)]
pub struct FpException {
    pub cond: Cond,
    pub target: BlockIx,
    /// Raw C run before the deroute.
    pub exec: Option<Code>,
    pub span: Span,
}

#[derive(Debug, Clone, Serialize)]
pub struct FpForbidden {
    pub from: BlockIx,
    pub to: BlockIx,
    pub only_when: Option<Cond>,
}

#[derive(Debug, Clone, Serialize)]
pub struct FpBlock {
    pub name: String,
    pub pre_call: Option<Code>,
    pub post_call: Option<Code>,
    pub on_enter: Option<Code>,
    pub on_exit: Option<Code>,
    pub exceptions: Vec<FpException>,
    pub stages: Vec<FpStage>,
    pub span: Span,
}

/// Stages. `While`, `Set`, `Call`, `Deroute`, `Return` and `Nav` are the paper's; `For` is kept
/// as its own kind because upstream compiles it with `int8_t` counters (quirk 3) that a
/// translation to `while` would not reproduce.
#[derive(Debug, Clone, Serialize)]
pub enum FpStage {
    While {
        cond: Cond,
        body: Vec<FpStage>,
        span: Span,
    },
    For {
        var: String,
        from: String,
        to: String,
        body: Vec<FpStage>,
        span: Span,
    },
    /// `set`: the assignment `var = value`.
    Set {
        code: Code,
        span: Span,
    },
    /// `call` / `call_once`. `loop_` true: call until it returns false (the call is a
    /// condition); false: call once (the call is code).
    Call {
        fun: String,
        loop_: bool,
        brk: bool,
        until: Option<Cond>,
        span: Span,
    },
    Deroute {
        target: BlockIx,
        span: Span,
    },
    /// `Return(x)`: back to the last block.
    Return {
        reset: Reset,
        span: Span,
    },
    Nav(Box<NavStage>),
}

/// The argument of `Return(x)`: the C text upstream prints, and its effect.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Reset {
    /// The `reset_stage` text as written (`0` when absent), printed verbatim.
    pub text: String,
    /// Where the returned-to block resumes.
    pub resume: Resume,
}

/// The kind of a navigation stage (its DTD tag is [`NavKind::tag`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum NavKind {
    Go,
    Stay,
    Circle,
    Heading,
    Attitude,
    Guided,
    Follow,
    Xyz,
    Home,
    Eight,
    Oval,
    SurveyRectangle,
}

impl NavKind {
    /// The stage's tag in the flight-plan XML.
    pub fn tag(self) -> &'static str {
        match self {
            NavKind::Go => "go",
            NavKind::Stay => "stay",
            NavKind::Circle => "circle",
            NavKind::Heading => "heading",
            NavKind::Attitude => "attitude",
            NavKind::Guided => "guided",
            NavKind::Follow => "follow",
            NavKind::Xyz => "xyz",
            NavKind::Home => "home",
            NavKind::Eight => "eight",
            NavKind::Oval => "oval",
            NavKind::SurveyRectangle => "survey_rectangle",
        }
    }
}

/// A navigation stage. Generic shape of upstream's code for `go`, `stay`, `circle`, ...:
///
/// ```text
/// [init: lines; NextStageAndBreak]            (eight, oval, survey_rectangle: own stage)
/// pre; [before]
/// if (approach) { post; NextStageAndBreakFrom(wp) } else { lines }   (go)
/// lines                                                              (others)
/// if (until) { post; NextStageAndBreak }
/// post; break
/// ```
#[derive(Debug, Clone, Serialize)]
pub struct NavStage {
    /// Which stage it is.
    pub kind: NavKind,
    /// Lines of the separate init stage (`nav_eight_init()`, survey init), if any.
    pub init: Option<Vec<Code>>,
    pub pre_call: Option<Code>,
    /// `go` without `wp`: the `waypoints[0].x/y = ...` assignments, before the approach test.
    pub before: Vec<Code>,
    /// `go`: the approach condition and the waypoint remembered as `last_wp`.
    pub approach: Option<(Cond, usize)>,
    /// The approach condition as upstream prints it, where that differs: an `exceeding_time` of
    /// several terms, of which upstream's minus sign negates only the first. Only
    /// `--upstream-compat` prints it; the semantics and the default header use `approach`.
    pub approach_upstream: Option<Cond>,
    pub lines: Vec<Code>,
    pub until: Option<Cond>,
    pub post_call: Option<Code>,
    /// `follow`, `xyz` and `home` have no until test in upstream's output.
    pub span: Span,
}

impl FpStage {
    pub fn span(&self) -> Span {
        match self {
            FpStage::While { span, .. }
            | FpStage::For { span, .. }
            | FpStage::Set { span, .. }
            | FpStage::Call { span, .. }
            | FpStage::Deroute { span, .. }
            | FpStage::Return { span, .. } => *span,
            FpStage::Nav(n) => n.span,
        }
    }
}
