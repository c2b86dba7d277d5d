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
    /// `FUNCTION(EXPR)`: a conversion (`int`, `uint16`, `float`, …) or test (`finite`, `upper`,
    /// `known`).
    Call(Ident, Box<Expr>),
    /// `"SERVO{n}_FUNCTION"`: text with whole numbers written into it.
    Interp(Vec<InterpPart>),
    Unary(UnOp, Box<Expr>),
    Binary(BinOp, Box<Expr>, Box<Expr>),
}

/// A piece of an interpolated text: literal text, or an expression between braces.
#[derive(Debug, Clone)]
pub enum InterpPart {
    Text(String),
    Expr(Expr),
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
    /// The messages sent, in order: `MSG(field = expr, …), MSG(…)`.
    pub messages: Vec<ReplyMessage>,
}

/// One message of a reply declaration.
#[derive(Debug, Clone)]
pub struct ReplyMessage {
    pub message: Ident,
    pub fields: Vec<(Ident, Expr)>,
}

/// The kinds of vehicle outputs an effect may be performed through.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputKind {
    /// A servo output (`SERVOn_…`), driven by DO_SET_SERVO and DO_REPEAT_SERVO.
    Servo,
    /// A relay, driven by DO_SET_RELAY and DO_REPEAT_RELAY.
    Relay,
    /// An RC input channel, driven by RC_CHANNELS_OVERRIDE.
    Rc,
}

/// `command MAV_CMD_X [when EXPR];` of an effect.
#[derive(Debug, Clone)]
pub struct EffectCommand {
    pub command: Ident,
    /// The arguments that make the command this effect (fields of the carrying message).
    pub when: Option<Expr>,
    pub span: Span,
}

/// `servo N when EXPR [driven when EXPR];`, `relay …`, `rc N in A..B when …` of an effect.
#[derive(Debug, Clone)]
pub struct EffectOutput {
    pub kind: OutputKind,
    /// The name of the output number in the expressions.
    pub var: Ident,
    /// Channel range (`rc` only), inclusive.
    pub range: Option<(u32, u32)>,
    /// Configuration that makes output N this effect's (parameters).
    pub when: Expr,
    /// The values that perform it (`value` = what the route sets); any value when absent.
    pub driven: Option<Expr>,
    pub span: Span,
}

/// `effect NAME { … }`: an action of the vehicle and what makes the vehicle perform it.
#[derive(Debug, Clone)]
pub struct EffectDecl {
    pub name: Ident,
    pub commands: Vec<EffectCommand>,
    pub outputs: Vec<EffectOutput>,
    pub span: Span,
}

/// `guard EFFECT by ROUTE, … (where EXPR | refuse);` in a protocol.
#[derive(Debug, Clone)]
pub struct GuardDecl {
    pub effect: Ident,
    /// Route classes: `command`, `mission`, `rc`.
    pub routes: Vec<Ident>,
    /// The precondition under which the effect may happen; `None` with `refuse`.
    pub where_: Option<Expr>,
    pub span: Span,
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
    /// `guard` declarations: steps generated for every route to an effect.
    pub guards: Vec<GuardDecl>,
    pub body: Vec<Stmt>,
    pub span: Span,
}

#[derive(Debug, Clone, Default)]
pub struct FileAst {
    pub consts: Vec<ConstDecl>,
    pub effects: Vec<EffectDecl>,
    pub protocols: Vec<ProtocolDecl>,
}

impl Expr {
    /// A name with this expression's span.
    pub fn name_at(name: &str, span: Span) -> Expr {
        Expr { kind: ExprKind::Name(name.to_string()), span }
    }

    /// A number with this expression's span.
    pub fn num_at(value: f64, span: Span) -> Expr {
        Expr { kind: ExprKind::Num(value), span }
    }

    /// `f(arg)` at `span`.
    pub fn call_at(f: &str, arg: Expr, span: Span) -> Expr {
        let f = Ident { name: f.to_string(), span };
        Expr { kind: ExprKind::Call(f, Box::new(arg)), span }
    }

    /// This expression with every name in `map` replaced by its expression (effects are
    /// instantiated per route this way: the output number, the value the route sets).
    pub fn substitute(&self, map: &[(&str, &Expr)]) -> Expr {
        let sub = |e: &Expr| Box::new(e.substitute(map));
        let kind = match &self.kind {
            ExprKind::Name(n) => match map.iter().find(|(k, _)| k == n) {
                Some((_, with)) => return (*with).clone(),
                None => ExprKind::Name(n.clone()),
            },
            ExprKind::ParamOf(a) => ExprKind::ParamOf(sub(a)),
            ExprKind::Call(f, a) => ExprKind::Call(f.clone(), sub(a)),
            ExprKind::Interp(parts) => ExprKind::Interp(
                parts
                    .iter()
                    .map(|p| match p {
                        InterpPart::Text(t) => InterpPart::Text(t.clone()),
                        InterpPart::Expr(e) => InterpPart::Expr(e.substitute(map)),
                    })
                    .collect(),
            ),
            ExprKind::Unary(op, a) => ExprKind::Unary(*op, sub(a)),
            ExprKind::Binary(op, a, b) => ExprKind::Binary(*op, sub(a), sub(b)),
            k => k.clone(),
        };
        Expr { kind, span: self.span }
    }
}
