//! Syntax tree of protocol files, straight from the parser (names unresolved, spans kept).

use super::error::Span;

#[derive(Debug, Clone)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    Or,
    And,
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
    Add,
    Sub,
    Mul,
    Div,
}

impl BinOp {
    pub fn text(self) -> &'static str {
        match self {
            BinOp::Or => "||",
            BinOp::And => "&&",
            BinOp::Eq => "==",
            BinOp::Ne => "!=",
            BinOp::Lt => "<",
            BinOp::Le => "<=",
            BinOp::Gt => ">",
            BinOp::Ge => ">=",
            BinOp::Add => "+",
            BinOp::Sub => "-",
            BinOp::Mul => "*",
            BinOp::Div => "/",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnOp {
    Not,
    Neg,
}

#[derive(Debug, Clone)]
pub enum ExprKind {
    Num(f64),
    Str(String),
    Bool(bool),
    /// A variable, a field of the current message, a constant or an enum entry.
    Name(String),
    /// `vehicle.armed`, `vehicle.mode`, `vehicle.alt`, `vehicle.climb`, `vehicle.type`.
    Vehicle(Ident),
    /// `param.NAME`: last known value of a vehicle parameter.
    Param(Ident),
    /// `param[EXPR]`: last known value of the parameter whose id is the text EXPR.
    ParamOf(Box<Expr>),
    /// `FUNCTION(EXPR)`: a conversion (`int`, `uint16`, `float`, …) or test (`finite`, `upper`).
    Call(Ident, Box<Expr>),
    Unary(UnOp, Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
}

#[derive(Debug, Clone)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TypeName {
    Int,
    Float,
    Bool,
    Str,
}

/// `A -> B : L1 | L2 (x = field, …) when … where …`
#[derive(Debug, Clone)]
pub struct StepHead {
    pub from: Ident,
    pub to: Ident,
    pub labels: Vec<Ident>,
    pub binds: Vec<(Ident, Ident)>,
    pub when: Option<Expr>,
    pub where_: Option<Expr>,
    pub span: Span,
}

#[derive(Debug, Clone)]
pub struct Branch {
    pub label: Ident,
    pub head: StepHead,
    pub body: Vec<Stmt>,
}

#[derive(Debug, Clone)]
pub struct VarDecl {
    pub name: Ident,
    pub ty: Option<TypeName>,
    pub init: Expr,
}

#[derive(Debug, Clone)]
pub enum Stmt {
    /// A step; with `block` the block is its continuation, else the following statements are.
    Step {
        head: StepHead,
        block: Option<Vec<Stmt>>,
    },
    Choice {
        branches: Vec<Branch>,
        complete_when: Option<Expr>,
        span: Span,
    },
    Rec {
        name: Ident,
        vars: Vec<VarDecl>,
        invariant: Option<Expr>,
        body: Vec<Stmt>,
    },
    Continue {
        name: Ident,
        assigns: Vec<(Ident, Expr)>,
        span: Span,
    },
    End(Span),
}

#[derive(Debug, Clone)]
pub struct ConstDecl {
    pub name: Ident,
    pub value: Expr,
}

#[derive(Debug, Clone)]
pub struct ReplyDecl {
    /// `on violation by ROLE reply …`: only when ROLE sent the violating message.
    pub by: Option<Ident>,
    pub to: Ident,
    pub message: Ident,
    pub fields: Vec<(Ident, Expr)>,
}

#[derive(Debug, Clone)]
pub struct StrictDecl {
    pub from: Ident,
    pub to: Ident,
    pub labels: Vec<Ident>,
}

#[derive(Debug, Clone)]
pub struct ProtocolDecl {
    pub name: Ident,
    pub roles: Vec<Ident>,
    pub keys: Vec<Ident>,
    pub timeout_ms: Option<(u64, Span)>,
    pub strict: Vec<StrictDecl>,
    /// `on violation reply …` declarations, in order (one per addressed role at most).
    pub replies: Vec<ReplyDecl>,
    /// `unverifiable pass;` / `unverifiable drop;`.
    pub unverifiable: Option<(Ident, Span)>,
    pub consts: Vec<ConstDecl>,
    pub body: Vec<Stmt>,
    pub span: Span,
}

#[derive(Debug, Clone, Default)]
pub struct FileAst {
    pub consts: Vec<ConstDecl>,
    pub protocols: Vec<ProtocolDecl>,
}
