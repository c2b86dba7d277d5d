//! Compiled protocols: names resolved to slots, fields to byte offsets, messages to dialect indices.
//! This is what the monitor executes; it knows nothing of the source text except report strings.

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
            _ => None,
        }
    }

    /// Names of all built-in functions, for error messages.
    pub const NAMES: &'static str =
        "int, int8, int16, int32, uint8, uint16, uint32, float, finite, upper";
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
    /// Value of session key `i`.
    Key(usize),
    Not(Box<Expr>),
    Neg(Box<Expr>),
    Bin(crate::protocol::ast::BinOp, Box<Expr>, Box<Expr>),
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum UnverifiablePolicy {
    /// Forward it (and report it as unverifiable).
    Pass,
    /// Drop it like a violation (fail closed). The default.
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

#[derive(Debug, Clone)]
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
}
