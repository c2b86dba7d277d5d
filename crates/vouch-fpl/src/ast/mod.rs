//! The typed, resolved flight plan produced by the front end. It is plain data with spans: no
//! XML type appears here.
//!
//! What "resolved" means here (see also the fpl section of `ARCHITECTURE.md`):
//! * includes are expanded exactly as upstream's `fp_proc` does (procedure blocks renamed
//!   `Name.block`, parameters substituted, raw texts of procedure stages re-printed);
//! * `<path>` stages are expanded into `go` stages and relative waypoints (`wp_qdr`/`wp_dist`)
//!   are created and prepended to the waypoint list;
//! * the implicit `HOME` block (one `home` stage) is appended as the last block;
//! * every block reference is a [`BlockRef`] carrying the block's index, every waypoint
//!   reference a [`WpRef`] carrying the waypoint's index, and `IndexOfBlock(x)` in expressions is
//!   [`crate::expr::Expr::BlockIndex`].
//!
//! Nothing is lost: every element keeps all its attributes as written in [`Attrs`].

pub mod expanded;
pub mod outline;
mod stage;

pub use stage::*;

use serde::Serialize;

use crate::diag::Diagnostic;
use crate::expr::Expr;
use crate::ids::{BlockId, WpId};
use crate::span::{FileId, SourceMap, Span};

/// An attribute value kept exactly as written (after upstream's only processing: backslash
/// escapes; entities are *not* decoded) with the span of the value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Text {
    pub value: String,
    pub span: Span,
}

/// An attribute that upstream parses as an expression and re-prints: the raw text plus its
/// parsed (and resolved) expression. Print `expr` with [`crate::expr::print_upstream`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExprAttr {
    pub text: Text,
    pub expr: Expr,
}

/// A numeric attribute: raw text plus its value. Upstream prints some of them from the text
/// (e.g. waypoint `alt` in `WAYPOINTS_UTM`) and others from the value, so both are kept.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Num {
    pub text: Text,
    pub value: f64,
}

/// One XML attribute as written: name lower-cased (upstream compares names
/// case-insensitively), value raw. The first of duplicated attributes is the one kept.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RawAttr {
    pub name: String,
    pub value: String,
    /// Span of the whole `name="value"`.
    pub span: Span,
    /// Span of the value only (inside the quotes).
    pub value_span: Span,
    /// Upstream's tree spells the name in upper case: every attribute of a file validated
    /// against its DTD (xml-light's validation upper-cases them); attributes written without
    /// validation or made by upstream's rewrites keep lower case. Only printed texts see it.
    #[serde(skip)]
    pub upper: bool,
}

/// All attributes of an element in source order (after include/path rewriting).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Attrs(pub Vec<RawAttr>);

impl Attrs {
    /// Case-insensitive lookup (names are stored lower-case).
    pub fn get(&self, name: &str) -> Option<&RawAttr> {
        self.0.iter().find(|a| a.name.eq_ignore_ascii_case(name))
    }
}

/// A resolved reference to a block, as written (`name`) and resolved (`id`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BlockRef {
    pub name: String,
    pub id: BlockId,
    pub span: Span,
}

/// A resolved reference to a waypoint. With duplicate names (upstream does not detect them)
/// the first waypoint of that name is chosen, like upstream's lookup.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WpRef {
    pub name: String,
    pub id: WpId,
    pub span: Span,
}

/// The whole plan after includes, paths and relative waypoints are expanded and names resolved.
#[derive(Debug, Clone, Serialize)]
pub struct FlightPlan {
    /// Files read: `FileId(0)` is the main plan, then procedures in include order.
    pub sources: SourceMap,
    /// Span of the `<flight_plan>` start tag.
    pub span: Span,
    /// `<flight_plan>` attributes, typed.
    pub name: Text,
    /// Reference latitude in decimal degrees (text may be `D M S [N|S]`).
    pub lat0: Num,
    pub lon0: Num,
    pub max_dist_from_home: Num,
    pub ground_alt: Num,
    pub security_height: Num,
    /// Nominal altitude (`alt` attribute).
    pub alt: Num,
    pub wp_frame: Option<Spanned<WpFrame>>,
    pub qfu: Option<Num>,
    pub home_mode_height: Option<Num>,
    pub geofence_max_alt: Option<Num>,
    pub geofence_max_height: Option<Num>,
    /// Name of a sector (printed as `Inside<Name>`; not checked upstream).
    pub geofence_sector: Option<Text>,
    /// All `<flight_plan>` attributes as written.
    pub attrs: Attrs,
    /// `<header>` text: entity-decoded, whitespace-only lines dropped, lines joined with `\n`.
    /// With includes it is `main + "\n" + procedure` (upstream's concatenation, even when empty).
    pub header: Option<Header>,
    /// Attributes of `<waypoints>` (`utm_x0`, `utm_y0`).
    pub waypoints_attrs: Attrs,
    /// User waypoints in upstream order (relative ones first, then file order, then procedures').
    pub waypoints: Vec<Waypoint>,
    pub sectors: Vec<Sector>,
    /// `<kml file=..>` entries of `<sectors>` (ignored by the generator).
    pub kml: Vec<Text>,
    /// Variables and ABI bindings, in file order.
    pub variables: Vec<VariableDecl>,
    pub modules: Vec<Module>,
    /// The includes that were expanded (for information; their content is already merged).
    pub includes: Vec<IncludeInfo>,
    /// Global exceptions (main plan first, then procedures').
    pub exceptions: Vec<Exception>,
    /// Blocks in upstream order; the last one is the implicit `HOME` block.
    pub blocks: Vec<Block>,
    /// VFPG extension: `<forbidden_deroutes><forbidden_deroute from to [only_when]/>`.
    pub forbidden_deroutes: Vec<ForbiddenDeroute>,
    /// Non-fatal findings (duplicate attributes dropped, duplicate waypoint names, ...).
    pub warnings: Vec<Diagnostic>,
    /// The expanded `<flight_plan>` element as upstream holds it (for the dump).
    #[serde(skip)]
    pub expanded: Option<std::sync::Arc<expanded::Node>>,
}

impl FlightPlan {
    pub fn block(&self, id: BlockId) -> &Block {
        &self.blocks[id.0]
    }
    pub fn waypoint(&self, id: WpId) -> &Waypoint {
        &self.waypoints[id.0]
    }
    /// Block index by exact name.
    pub fn block_id(&self, name: &str) -> Option<BlockId> {
        self.blocks.iter().position(|b| b.name.value == name).map(BlockId)
    }
    /// First waypoint of that exact name.
    pub fn waypoint_id(&self, name: &str) -> Option<WpId> {
        self.waypoints.iter().position(|w| w.name.value == name).map(WpId)
    }
}

/// A value with the span it was read from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Spanned<T> {
    pub value: T,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WpFrame {
    Utm,
    Ltp,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Header {
    pub text: String,
    pub span: Span,
}

/// How a waypoint came to exist.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WaypointOrigin {
    /// Written in the main plan.
    Plan,
    /// Written in an included procedure (`include` = the include's `name`).
    Procedure { include: String },
    /// Created from a stage's `wp_qdr`/`wp_dist` (or `from_qdr`/`from_dist`).
    Relative { base: String, qdr: f64, dist: f64 },
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Waypoint {
    pub name: Text,
    /// Local coordinates in metres. For relative waypoints the text is OCaml float text.
    pub x: Option<Num>,
    pub y: Option<Num>,
    /// Geographic coordinates in decimal degrees (text may be `D M S [N|S|E|W]`).
    pub lat: Option<Num>,
    pub lon: Option<Num>,
    /// Absolute altitude; upstream prints its *text* in `WAYPOINTS_UTM`.
    pub alt: Option<Num>,
    /// Height above ground.
    pub height: Option<Num>,
    pub origin: WaypointOrigin,
    pub attrs: Attrs,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sector {
    pub name: Text,
    pub color: Option<Text>,
    /// `type` attribute (dynamic sectors); upstream's header generator rejects it.
    pub sector_type: Option<Text>,
    pub corners: Vec<WpRef>,
    pub attrs: Attrs,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VariableDecl {
    Var(Variable),
    Abi(AbiBinding),
}

/// `<variable>`: `type` and `init` are raw C texts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Variable {
    pub var: Text,
    pub var_type: Option<Text>,
    pub init: Option<Text>,
    /// Settings attributes (shortname, min, max, step, unit, ...) are in `attrs`.
    pub attrs: Attrs,
    pub span: Span,
}

/// `<abi_binding name vars|handler id>`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AbiBinding {
    pub name: Text,
    /// `vars` split on commas, blanks trimmed (`_` = ignored field). Exactly one of
    /// `vars`/`handler` is present (checked by the front end).
    pub vars: Option<Vec<String>>,
    pub vars_text: Option<Text>,
    pub handler: Option<Text>,
    /// Raw `id`; upstream default is `ABI_BROADCAST`.
    pub id: Option<Text>,
    pub attrs: Attrs,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Module {
    pub name: Text,
    pub module_type: Option<Text>,
    pub configures: Vec<NameValue>,
    pub defines: Vec<NameValue>,
    pub attrs: Attrs,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NameValue {
    pub name: Text,
    pub value: Option<Text>,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IncludeInfo {
    /// The include's `name` (the prefix of its blocks).
    pub name: Text,
    pub procedure: Text,
    /// The file that was read.
    pub file: FileId,
    pub args: Vec<NameValue>,
    /// `<with from to>` pairs.
    pub withs: Vec<NameValue>,
    pub span: Span,
}

/// `<exception cond deroute [exec]>`, global or per block.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Exception {
    pub cond: ExprAttr,
    pub deroute: BlockRef,
    /// Raw C text run before the deroute (not in the DTD; accepted where upstream accepts it).
    pub exec: Option<Text>,
    pub attrs: Attrs,
    pub span: Span,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Block {
    pub name: Text,
    pub id: BlockId,
    /// Raw C texts.
    pub pre_call: Option<Text>,
    pub post_call: Option<Text>,
    pub on_enter: Option<Text>,
    pub on_exit: Option<Text>,
    /// GCS-only attributes, raw.
    pub strip_button: Option<Text>,
    pub strip_icon: Option<Text>,
    pub group: Option<Text>,
    pub key: Option<Text>,
    pub description: Option<Text>,
    /// Block-level exceptions, in order, wherever they appeared among the stages.
    pub exceptions: Vec<Exception>,
    pub stages: Vec<Stage>,
    /// `None` for main-plan blocks, `Some(include name)` for procedure blocks.
    pub procedure: Option<String>,
    /// True only for the implicit `HOME` block appended by the front end (as upstream does).
    pub implicit: bool,
    pub attrs: Attrs,
    pub span: Span,
}

/// VFPG extension: a block change from `from` to `to` that must not happen (when
/// `only_when` is given: must not happen while it holds).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForbiddenDeroute {
    pub from: BlockRef,
    pub to: BlockRef,
    pub only_when: Option<ExprAttr>,
    pub attrs: Attrs,
    pub span: Span,
}
