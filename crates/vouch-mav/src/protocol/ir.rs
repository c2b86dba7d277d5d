//! Compiled protocols: names resolved to slots, fields to byte offsets, messages to dialect indices.
//! This is what the monitor executes; it knows nothing of the source text except report strings.

use super::error::Span;
use crate::dialect::{MsgIndex, PrimType};
use crate::side::Side;
use crate::vehicle_state::ParamTable;

/// The monitor updates recursion variables through a fixed-size buffer (no allocation), so one
/// `continue` updates at most this many.
pub const MAX_CONTINUE_ASSIGNS: usize = 8;

pub type StateId = usize;
pub type Slot = usize;

/// Where a field sits in the payload of one particular message.
#[derive(Debug, Clone)]
pub struct FieldLoc {
    pub ty: PrimType,
    pub offset: u16,
    /// Non-zero for a char array: its size in bytes.
    pub text_len: u16,
    pub enum_name: Option<String>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VehicleAttr {
    Armed,
    Mode,
    Alt,
    Climb,
    Type,
}

/// Built-in functions: conversions with the semantics of C on the autopilot, and tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Builtin {
    /// C conversion of a number to an integer type of `bits` bits (`int` = 32, signed): the
    /// value is truncated toward zero; NaN, infinities and values the type cannot hold are
    /// unknown (C leaves them undefined, and autopilots on different processors differ).
    Int {
        /// 8, 16 or 32.
        bits: u8,
        /// Signed (`int8`…`int32`, `int`) or unsigned (`uint8`…`uint32`).
        signed: bool,
    },
    /// Rounding to the nearest IEEE-754 single (what a `float` field holds and what float
    /// arithmetic on the autopilot computes).
    Float32,
    /// Whether a number is neither NaN nor infinite.
    Finite,
    /// Text in ASCII upper case (parameter names are matched without regard to case by
    /// ArduPilot).
    Upper,
    /// Whether a value is known (never unknown itself): `known(param.X)` is false until the
    /// vehicle reported X.
    Known,
}

impl Builtin {
    /// The function of this name, if any.
    pub fn named(name: &str) -> Option<Builtin> {
        let int = |bits, signed| Some(Builtin::Int { bits, signed });
        match name {
            "int" | "int32" => int(32, true),
            "int16" => int(16, true),
            "int8" => int(8, true),
            "uint32" => int(32, false),
            "uint16" => int(16, false),
            "uint8" => int(8, false),
            "float" => Some(Builtin::Float32),
            "finite" => Some(Builtin::Finite),
            "upper" => Some(Builtin::Upper),
            "known" => Some(Builtin::Known),
            _ => None,
        }
    }

    /// Names of all built-in functions, for error messages.
    pub const NAMES: &'static str =
        "int, int8, int16, int32, uint8, uint16, uint32, float, finite, upper, known";
}

#[derive(Debug, Clone)]
pub enum Expr {
    Num(f64),
    Str(Box<[u8]>),
    Bool(bool),
    Var(Slot),
    /// Field slot of the transition being taken (see [`LabelFields::fields`]).
    Field(usize),
    Const(usize),
    Vehicle(VehicleAttr),
    Param(usize),
    /// Last known value of the parameter whose id the text expression gives.
    ParamOf(Box<Expr>),
    /// A built-in function applied to one argument.
    Call(Builtin, Box<Expr>),
    /// Text with whole numbers written into it (`"SERVO{n}_FUNCTION"`).
    Interp(Vec<InterpIR>),
    /// Value of session key `i`.
    Key(usize),
    Not(Box<Expr>),
    Neg(Box<Expr>),
    Bin(crate::protocol::ast::BinOp, Box<Expr>, Box<Expr>),
}

/// A piece of an interpolated text.
#[derive(Debug, Clone)]
pub enum InterpIR {
    Text(Box<[u8]>),
    /// A number, written as a whole decimal number (unknown when it is not whole).
    Num(Expr),
}

/// One conjunct of a refinement, with its source text and the names whose values a report shows.
#[derive(Debug, Clone)]
pub struct Conjunct {
    pub expr: Expr,
    pub text: String,
    pub shows: Vec<(String, Expr, Option<String>)>,
}

/// A predicate split at its top-level `&&` so that reports name the conjunct that failed.
#[derive(Debug, Clone, Default)]
pub struct Pred {
    pub conjuncts: Vec<Conjunct>,
}

#[derive(Debug, Clone)]
pub struct LabelFields {
    pub msg: MsgIndex,
    /// Location of each field slot of the transition in this message.
    pub fields: Vec<FieldLoc>,
}

#[derive(Debug, Clone)]
pub enum Cont {
    End,
    Goto(StateId),
    /// Enter `rec`: assign initial values (evaluated in order), check the invariant, go to its body.
    Enter {
        rec: usize,
        assigns: Vec<(Slot, Expr)>,
        then: StateId,
    },
    /// Loop back to `rec`: assign new values (all evaluated before any is stored), check the invariant.
    Continue {
        rec: usize,
        assigns: Vec<(Slot, Expr)>,
    },
}

#[derive(Debug, Clone)]
pub struct Transition {
    pub label: String,
    pub from: usize,
    pub to: usize,
    pub msgs: Vec<LabelFields>,
    pub field_names: Vec<String>,
    pub binds: Vec<(Slot, usize)>,
    pub when: Option<Pred>,
    pub where_: Option<Pred>,
    pub cont: Cont,
    /// `from -> to : LABELS` for reports.
    pub text: String,
    /// What a failed refinement of this branch is.
    pub refusal: Refusal,
}

/// What a message whose refinement fails is: a violation, or (for a branch that only selects
/// messages whose safety depends on vehicle configuration the monitor has not seen) unverifiable.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Refusal {
    #[default]
    Violation,
    Unverifiable,
}

#[derive(Debug, Clone, Default)]
pub struct State {
    pub transitions: Vec<Transition>,
    /// A session idle in this state counts as completed (not abandoned) when this holds.
    pub complete_when: Option<Pred>,
}

#[derive(Debug, Clone)]
pub struct Rec {
    pub name: String,
    pub invariant: Option<Pred>,
    /// State of the first step of the body, where `continue` returns.
    pub entry: StateId,
}

#[derive(Debug, Clone)]
pub struct KeyIR {
    pub name: String,
    /// Location of the key field per message index (absent = the message carries no such key).
    pub locs: Vec<(MsgIndex, FieldLoc)>,
}

#[derive(Debug, Clone)]
pub struct StrictIR {
    pub from: usize,
    pub msgs: Vec<MsgIndex>,
    pub text: String,
    /// The rule's sender opens no session of the protocol: its messages answer an opener, and
    /// one outside a session answers an opener that was not seen (unverifiable, not a
    /// violation).
    pub answer: bool,
}

/// What the guard in enforce mode does with a frame the monitor cannot verify (an answer to a
/// session whose opener it did not see).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum UnverifiablePolicy {
    /// Forward it (and report it as unverifiable).
    Pass,
    /// Drop it like a violation (fail closed). The default.
    #[default]
    Drop,
}

#[derive(Debug, Clone)]
pub struct ReplyIR {
    /// Sent only when this role sent the violating message (`on violation by ROLE reply …`).
    pub by: Option<usize>,
    pub to: usize,
    pub msg: MsgIndex,
    pub fields: Vec<(String, Expr)>,
}

#[derive(Debug, Clone, Default)]
pub struct Protocol {
    pub name: String,
    pub roles: Vec<(String, Side)>,
    pub keys: Vec<KeyIR>,
    pub timeout_us: Option<u64>,
    pub strict: Vec<StrictIR>,
    /// Messages sent in answer to a violation (each to its role).
    pub replies: Vec<ReplyIR>,
    pub unverifiable: UnverifiablePolicy,
    /// State 0 is the start state: its transitions open sessions.
    pub states: Vec<State>,
    pub recs: Vec<Rec>,
    pub var_names: Vec<String>,
    /// Every message index the protocol mentions (steps and strict rules).
    pub alphabet: Vec<MsgIndex>,
    /// The routes to actions that its steps check (for the route check of `vouch mav lint`).
    pub covers: Vec<Route>,
}

/// Where a declaration is: its file (index among the loaded sources) and span.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Origin {
    pub file: usize,
    pub span: Span,
}

/// How a route brings the vehicle to act.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RouteClass {
    /// A command performed when it arrives (COMMAND_LONG, COMMAND_INT).
    Command,
    /// An item of an uploaded mission, performed when the mission reaches it (MISSION_ITEM,
    /// MISSION_ITEM_INT).
    Mission,
    /// An RC input channel overridden from the ground (RC_CHANNELS_OVERRIDE).
    Rc,
}

impl RouteClass {
    /// The word of the protocol language (`guard E by command, mission, rc`).
    pub fn word(self) -> &'static str {
        match self {
            RouteClass::Command => "command",
            RouteClass::Mission => "mission",
            RouteClass::Rc => "rc",
        }
    }
}

/// One route to an action: a message from the ground and, for messages that carry a MAV_CMD, the
/// command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Route {
    pub class: RouteClass,
    pub msg: MsgIndex,
    pub command: Option<u32>,
}

/// A route to an effect compiled against its carrier message: the selector of the messages that
/// perform the effect, and for outputs the selector of those whose output configuration is not
/// known (unverifiable) with the conjunct that says so.
#[derive(Debug, Clone)]
pub struct EffectRoute {
    pub route: Route,
    /// `MAV_CMD_…` or `RC_CHANNELS_OVERRIDE`, for branch labels.
    pub label: String,
    /// Field slots used by the selectors (names, locations in the carrier).
    pub field_names: Vec<String>,
    pub fields: Vec<FieldLoc>,
    pub effect: Pred,
    pub unknown: Option<(Pred, Pred)>,
    /// The effect clause this route comes from.
    pub origin: Origin,
}

/// An effect: every route by which the vehicle can be made to perform it, compiled.
#[derive(Debug, Clone)]
pub struct EffectIR {
    pub name: String,
    pub routes: Vec<EffectRoute>,
    pub origin: Origin,
}

/// Routes that must be guarded because something loaded guards part of them: a command that a
/// protocol checks on one carrier (all carriers of that command), or a route of an effect.
#[derive(Debug, Clone)]
pub struct Demand {
    /// What is guarded: `MAV_CMD_…` or `effect NAME`.
    pub subject: String,
    pub routes: Vec<Route>,
    /// Where the need comes from (a step that checks the command, an effect clause).
    pub origin: Origin,
}

/// A constant: its name, value and where it was declared (file-level or protocol-level).
#[derive(Debug, Clone)]
pub struct ConstIR {
    pub name: String,
    pub value: f64,
}

/// All loaded protocols plus the tables shared by them.
#[derive(Debug, Clone, Default)]
pub struct ProtocolSet {
    pub protocols: Vec<Protocol>,
    pub consts: Vec<ConstIR>,
    pub params: ParamTable,
    pub effects: Vec<EffectIR>,
    /// Routes the loaded declarations say must be guarded (checked by [`super::routes`]).
    pub demands: Vec<Demand>,
}
