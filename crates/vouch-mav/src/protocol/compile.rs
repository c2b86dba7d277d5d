//! The compiler's state, shared by its three parts: declarations (`check`), statements
//! (`flow`) and expressions (`typing`). Each part adds methods to [`Compiler`]; this file holds
//! what they all need, so that none of them imports another.

use super::error::{ErrorKind, ProtocolError, Span};
use super::ir::*;
use super::routes::Carriers;
use crate::dialect::{Dialect, MessageDef, MsgIndex, PrimType};

/// Field context of the step being compiled: which messages, which field slots.
#[derive(Clone)]
pub(super) struct StepCx {
    pub(super) msgs: Vec<MsgIndex>,
    pub(super) names: Vec<String>,
    pub(super) locs: Vec<Vec<FieldLoc>>,
    pub(super) label_text: String,
}

pub(super) type RecScope = (String, usize, Vec<(String, Slot)>);

#[derive(Default)]
pub(super) struct Scope {
    pub(super) vars: Vec<(String, Slot, Ty)>,
    /// Recursions in scope: name, rec id, its variables (name, slot).
    pub(super) recs: Vec<RecScope>,
}

pub(crate) struct Compiler<'a> {
    pub dialect: &'a Dialect,
    pub src: &'a str,
    pub set: &'a mut ProtocolSet,
    /// Index of the file being compiled among the loaded sources (for [`Origin`]s).
    pub(super) file: usize,
    /// The protocol under construction (taken out when it is complete).
    pub(super) proto: Protocol,
    /// The messages of the dialect that make a vehicle act (routes to effects).
    pub(super) carriers: Carriers,
    /// Key names of the protocol being compiled (usable in reply expressions).
    pub(super) keys: Vec<String>,
    pub(super) in_reply: bool,
}

pub(super) type CResult<T> = Result<T, ProtocolError>;

pub(super) fn loc_of(def: &MessageDef, name: &str) -> Option<FieldLoc> {
    let f = def.field(name)?;
    Some(FieldLoc {
        ty: f.ty,
        offset: f.offset,
        text_len: if f.ty == PrimType::Char && f.array_len > 0 { f.array_len } else { 0 },
        enum_name: f.enum_name.clone(),
    })
}

pub(super) fn ty_of_loc(l: &FieldLoc) -> Ty {
    if l.text_len > 0 { Ty::Str } else { Ty::Num { enum_: l.enum_name.clone() } }
}

/// Static type of an expression.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Ty {
    /// A number; `enum_` names the MAVLink enum its values come from, when known.
    Num {
        enum_: Option<String>,
    },
    Str,
    Bool,
}

impl Ty {
    pub(super) fn num() -> Ty {
        Ty::Num { enum_: None }
    }

    pub(super) fn describe(&self) -> String {
        match self {
            Ty::Num { enum_: Some(e) } => format!("a value of enum {e}"),
            Ty::Num { enum_: None } => "a number".into(),
            Ty::Str => "text".into(),
            Ty::Bool => "a boolean".into(),
        }
    }
}

impl<'a> Compiler<'a> {
    /// A compiler adding what it compiles from `src`, the `file`-th loaded source, to `set`.
    pub fn new(dialect: &'a Dialect, src: &'a str, file: usize, set: &'a mut ProtocolSet) -> Self {
        Compiler {
            dialect,
            src,
            set,
            file,
            proto: Protocol::default(),
            carriers: Carriers::of(dialect),
            keys: vec![],
            in_reply: false,
        }
    }

    /// Where `span` is in the file being compiled.
    pub(super) fn origin(&self, span: Span) -> Origin {
        Origin { file: self.file, span }
    }

    pub(super) fn err<T>(&self, kind: ErrorKind, span: Span, msg: impl Into<String>) -> CResult<T> {
        Err(ProtocolError::at(kind, self.src, span, msg))
    }
}
