//! The Paparazzi expression language (`cond`, `until`, `value`, `alt`, ...), with upstream's
//! exact lexical rules, grammar (yacc precedences, `&&`/`||` on one level) and printer.
//!
//! * [`parse`] turns a text into an [`Expr`] or an [`ExprError`] with a byte offset;
//! * [`print_upstream`] prints it as upstream's generator does (fully parenthesised binary
//!   operations, `%f` floats, `$v` as `_var_v`, resolved `IndexOfBlock` as the block number);
//! * [`subst_procedure`] is upstream's procedure parameter substitution.

mod error;
mod lexer;
mod parser;
mod print;
mod subst;

pub use error::{ExprError, ExprErrorKind};
pub use lexer::{Token, TokenKind, lex};
pub use parser::parse;
pub use print::{format_g, ocaml_float_text, print_upstream};
pub use subst::{ProcEnv, subst_procedure};

use serde::Serialize;

use crate::ids::BlockId;

/// A parsed expression. Identifiers keep their spelling (`$i` keeps its `$`; a quoted
/// identifier `'a b'` is stored without its quotes, as upstream's lexer does).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Expr {
    Int(i64),
    Float(f64),
    Ident(String),
    /// `f(a, b)`; the callee is an identifier.
    Call(String, Vec<Expr>),
    /// `a[e]`; the indexed thing is an identifier.
    Index(String, Box<Expr>),
    /// `a.b` (identifier dot identifier only).
    Field(String, String),
    /// `e->f` or `e @DEREF f`.
    Deref(Box<Expr>, String),
    Binary(BinOp, Box<Expr>, Box<Expr>),
    Unary(UnOp, Box<Expr>),
    /// `IndexOfBlock(name)` after resolution: prints as the block number.
    BlockIndex {
        name: String,
        id: BlockId,
    },
}

/// Binary operators. Precedence (lowest first): `And`/`Or`; comparisons; `Add`/`Sub`;
/// `Mul`/`Div`/`Mod`/`Pow`. All left-associative.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BinOp {
    And,
    Or,
    Eq,
    Gt,
    Lt,
    Ge,
    Le,
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    Pow,
}

impl BinOp {
    /// The C text upstream prints (`@GT` prints `>`, `@AND` prints `&&`, ...).
    pub fn c_text(self) -> &'static str {
        match self {
            BinOp::And => "&&",
            BinOp::Or => "||",
            BinOp::Eq => "==",
            BinOp::Gt => ">",
            BinOp::Lt => "<",
            BinOp::Ge => ">=",
            BinOp::Le => "<=",
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
            BinOp::Mod => "%",
            BinOp::Pow => "**",
        }
    }
    /// Binding power level, 1 (loosest) to 4.
    pub fn level(self) -> u8 {
        match self {
            BinOp::And | BinOp::Or => 1,
            BinOp::Eq | BinOp::Gt | BinOp::Lt | BinOp::Ge | BinOp::Le => 2,
            BinOp::Add | BinOp::Sub => 3,
            BinOp::Mul | BinOp::Div | BinOp::Mod | BinOp::Pow => 4,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum UnOp {
    /// Unary minus, prints `-(e)`.
    Neg,
    /// `!`, prints `!(e)`; binds looser than unary minus.
    Not,
}

impl UnOp {
    pub fn c_text(self) -> &'static str {
        match self {
            UnOp::Neg => "-",
            UnOp::Not => "!",
        }
    }
}

impl Expr {
    /// Visits every sub-expression (pre-order), mutably.
    pub fn walk_mut(&mut self, f: &mut dyn FnMut(&mut Expr)) {
        f(self);
        match self {
            Expr::Call(_, args) => args.iter_mut().for_each(|a| a.walk_mut(f)),
            Expr::Index(_, e) | Expr::Deref(e, _) | Expr::Unary(_, e) => e.walk_mut(f),
            Expr::Binary(_, l, r) => {
                l.walk_mut(f);
                r.walk_mut(f);
            }
            Expr::Int(_)
            | Expr::Float(_)
            | Expr::Ident(_)
            | Expr::Field(..)
            | Expr::BlockIndex { .. } => {}
        }
    }
    /// Visits every sub-expression (pre-order).
    pub fn walk(&self, f: &mut dyn FnMut(&Expr)) {
        f(self);
        match self {
            Expr::Call(_, args) => args.iter().for_each(|a| a.walk(f)),
            Expr::Index(_, e) | Expr::Deref(e, _) | Expr::Unary(_, e) => e.walk(f),
            Expr::Binary(_, l, r) => {
                l.walk(f);
                r.walk(f);
            }
            Expr::Int(_)
            | Expr::Float(_)
            | Expr::Ident(_)
            | Expr::Field(..)
            | Expr::BlockIndex { .. } => {}
        }
    }
}
