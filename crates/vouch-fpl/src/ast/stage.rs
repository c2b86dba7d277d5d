//! Stages: every stage kind of the flight-plan DTD with the attributes that matter to code
//! generation, typed. Raw C texts (`fun`, `pre_call`, `nav_params`, ...) are [`Text`] and must be
//! printed verbatim; expression attributes are [`ExprAttr`] and must be re-printed with
//! [`crate::expr::print_upstream`]. All attributes as written stay available in `Stage::attrs`.

use serde::Serialize;

use super::{Attrs, BlockRef, ExprAttr, Spanned, Text, WpRef};
use crate::span::Span;

/// One stage. `span` is the element's start tag; for stages produced from a `<path>` it is the
/// path's span.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Stage {
    pub kind: StageKind,
    pub attrs: Attrs,
    pub span: Span,
    /// Set for `go` stages generated from a `<path>`.
    pub from_path: bool,
}

// Variants are kept unboxed so consumers can match and read fields directly; plans hold a few
// thousand stages at most, so the size difference does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StageKind {
    While(While),
    For(For),
    Set(Set),
    Call(Call),
    CallOnce(CallOnce),
    Deroute(Deroute),
    Return(Return),
    Go(Go),
    Stay(Stay),
    Circle(Circle),
    Heading(Heading),
    Attitude(Attitude),
    Guided(Guided),
    Follow(Follow),
    Xyz(Xyz),
    Home,
    Eight(Eight),
    Oval(Oval),
    SurveyRectangle(SurveyRectangle),
}

impl StageKind {
    /// The XML tag of this stage kind.
    pub fn tag(&self) -> &'static str {
        match self {
            StageKind::While(_) => "while",
            StageKind::For(_) => "for",
            StageKind::Set(_) => "set",
            StageKind::Call(_) => "call",
            StageKind::CallOnce(_) => "call_once",
            StageKind::Deroute(_) => "deroute",
            StageKind::Return(_) => "return",
            StageKind::Go(_) => "go",
            StageKind::Stay(_) => "stay",
            StageKind::Circle(_) => "circle",
            StageKind::Heading(_) => "heading",
            StageKind::Attitude(_) => "attitude",
            StageKind::Guided(_) => "guided",
            StageKind::Follow(_) => "follow",
            StageKind::Xyz(_) => "xyz",
            StageKind::Home => "home",
            StageKind::Eight(_) => "eight",
            StageKind::Oval(_) => "oval",
            StageKind::SurveyRectangle(_) => "survey_rectangle",
        }
    }
}

/// Attributes shared by the navigation stages (absent ones are `None`).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct NavCommon {
    /// Raw C texts, printed followed by `;`.
    pub pre_call: Option<Text>,
    pub post_call: Option<Text>,
    /// Raw prefix of the navigation macros (`t` in GENERATOR_FACTS; default `Nav`).
    pub nav_type: Option<Text>,
    /// Raw extra macro arguments (`NP`).
    pub nav_params: Option<Text>,
    pub until: Option<ExprAttr>,
    /// Raw; upstream default `-1.` [2024-10].
    pub max_speed: Option<Text>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VMode {
    Alt,
    Climb,
    Throttle,
    Glide,
    Xyz,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum HMode {
    Route,
    Direct,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Pitch {
    /// `pitch="auto"`.
    Auto(Span),
    Expr(ExprAttr),
}

/// Inputs of upstream's "vmode lines".
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Vertical {
    /// `None` = default (`alt`).
    pub vmode: Option<Spanned<VMode>>,
    pub alt: Option<ExprAttr>,
    pub height: Option<ExprAttr>,
    pub climb: Option<ExprAttr>,
    pub throttle: Option<ExprAttr>,
    pub pitch: Option<Pitch>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct While {
    /// `None` means always true (upstream prints `TRUE`).
    pub cond: Option<ExprAttr>,
    pub body: Vec<Stage>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct For {
    /// Loop variable name as written (`$v` in expressions prints `_var_v`).
    pub var: Text,
    pub from: ExprAttr,
    pub to: ExprAttr,
    pub body: Vec<Stage>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Set {
    /// Raw left-hand side.
    pub var: Text,
    pub value: ExprAttr,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Call {
    /// Raw C text.
    pub fun: Text,
    pub until: Option<ExprAttr>,
    /// `loop` (TRUE/FALSE, case-insensitive; upstream default TRUE).
    pub loop_: Option<Spanned<bool>>,
    /// `break` (TRUE/FALSE; default FALSE).
    pub break_: Option<Spanned<bool>>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CallOnce {
    pub fun: Text,
    pub break_: Option<Spanned<bool>>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Deroute {
    pub block: BlockRef,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Return {
    /// Raw C argument of `Return(x)`; upstream default `0`.
    pub reset_stage: Option<Text>,
}

/// Where `Return(x)` resumes the block it returns to. The runtime restarts the block when `x`
/// equals 1 (`TRUE` is 1); any other value resumes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Resume {
    /// At the stage where the block was left (`reset_stage` absent or not 1).
    SavedStage,
    /// At the block's first stage (`reset_stage` is 1 or `TRUE`).
    FirstStage,
}

impl Return {
    /// The argument printed in `Return(x)` (`0` when the attribute is absent).
    pub fn reset_text(&self) -> &str {
        self.reset_stage.as_ref().map_or("0", |t| t.value.as_str())
    }

    /// What the argument does. Only a plain literal is known at compile time; any other C text
    /// is taken as "not 1", as the reference semantics does.
    pub fn resume(&self) -> Resume {
        let t = self.reset_text().trim();
        let literal_one =
            t.starts_with(|c: char| c.is_ascii_digit() || c == '-') && t.parse::<i64>() == Ok(1);
        if literal_one || t == "TRUE" || t == "true" {
            Resume::FirstStage
        } else {
            Resume::SavedStage
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Go {
    /// Target; `None` only when the stage gives `x`/`y` instead (upstream then uses waypoint 0).
    pub wp: Option<WpRef>,
    pub x: Option<ExprAttr>,
    pub y: Option<ExprAttr>,
    pub from: Option<WpRef>,
    pub hmode: Option<Spanned<HMode>>,
    pub vertical: Vertical,
    /// Raw texts; at most one of the two is present (checked).
    pub approaching_time: Option<Text>,
    pub exceeding_time: Option<Text>,
    pub common: NavCommon,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Stay {
    pub wp: WpRef,
    pub hmode: Option<Spanned<HMode>>,
    pub vertical: Vertical,
    pub common: NavCommon,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Circle {
    pub wp: WpRef,
    pub radius: ExprAttr,
    pub vertical: Vertical,
    pub common: NavCommon,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Heading {
    pub course: ExprAttr,
    pub vertical: Vertical,
    pub common: NavCommon,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Attitude {
    pub roll: ExprAttr,
    pub vertical: Vertical,
    pub common: NavCommon,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Guided {
    /// Raw texts.
    pub commands: Text,
    pub flags: Option<Text>,
    pub common: NavCommon,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Follow {
    /// Raw texts.
    pub ac_id: Text,
    pub distance: Text,
    pub height: Text,
    pub common: NavCommon,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Xyz {
    /// Upstream default 100.
    pub radius: Option<ExprAttr>,
    pub vertical: Vertical,
    pub common: NavCommon,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Eight {
    pub center: WpRef,
    pub turn_around: WpRef,
    pub radius: ExprAttr,
    pub vertical: Vertical,
    pub common: NavCommon,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Oval {
    pub p1: WpRef,
    pub p2: WpRef,
    pub radius: ExprAttr,
    pub vertical: Vertical,
    pub common: NavCommon,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Orientation {
    NS,
    WE,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SurveyRectangle {
    pub wp1: WpRef,
    pub wp2: WpRef,
    pub grid: ExprAttr,
    /// Upstream default NS.
    pub orientation: Option<Spanned<Orientation>>,
    pub common: NavCommon,
}
