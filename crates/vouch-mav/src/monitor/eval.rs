//! Evaluation of compiled expressions with three-valued logic: a value the monitor has not seen
//! (a parameter never reported, an altitude before the first GLOBAL_POSITION_INT) is `Unknown`,
//! and a refinement that is not known to hold is treated as failing.

use crate::codec::view::read_prim;
use crate::protocol::ast::BinOp;
use crate::protocol::ir::{Builtin, Expr, FieldLoc, InterpIR, Pred, VehicleAttr};
use crate::vehicle_state::VehicleState;

/// Text values are compared on at most this many bytes (param_id has 16).
pub const TEXT_MAX: usize = 32;

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Val {
    Num(f64),
    Text([u8; TEXT_MAX], u8),
    Bool(bool),
    Unknown,
}

impl Val {
    pub fn text(bytes: &[u8]) -> Val {
        let n = bytes.len().min(TEXT_MAX);
        let mut b = [0u8; TEXT_MAX];
        b[..n].copy_from_slice(&bytes[..n]);
        Val::Text(b, n as u8)
    }

    pub fn render(&self, enum_name: Option<&str>, dialect: &crate::dialect::Dialect) -> String {
        match self {
            Val::Num(v) => {
                let base = if v.fract() == 0.0 && v.abs() < 1e15 {
                    format!("{}", *v as i64)
                } else {
                    format!("{v}")
                };
                match enum_name.and_then(|e| {
                    (v.fract() == 0.0 && *v >= 0.0)
                        .then(|| dialect.enum_value_name(e, *v as u64))
                        .flatten()
                }) {
                    Some(n) => format!("{base} ({n})"),
                    None => base,
                }
            }
            Val::Text(b, n) => format!("{:?}", String::from_utf8_lossy(&b[..usize::from(*n)])),
            Val::Bool(b) => b.to_string(),
            Val::Unknown => "unknown".into(),
        }
    }
}

/// Everything an expression may read.
pub struct Env<'a> {
    pub payload: &'a [u8],
    pub fields: &'a [FieldLoc],
    pub vars: &'a [Val],
    pub consts: &'a [f64],
    pub keys: &'a [Val],
    pub vehicle: Option<&'a VehicleState>,
    /// Names of the tracked parameters, indexed like [`VehicleState::params`].
    pub param_names: &'a [String],
}

/// Reads a field at its precomputed location.
#[inline]
pub fn read_loc(payload: &[u8], loc: &FieldLoc) -> Val {
    if loc.text_len > 0 {
        let start = usize::from(loc.offset).min(payload.len());
        let end = (usize::from(loc.offset) + usize::from(loc.text_len)).min(payload.len());
        let s = &payload[start..end];
        let s = match s.iter().position(|&b| b == 0) {
            Some(n) => &s[..n],
            None => s,
        };
        Val::text(s)
    } else {
        Val::Num(read_prim(payload, loc.ty, usize::from(loc.offset)).as_f64())
    }
}

pub fn eval(e: &Expr, env: &Env) -> Val {
    match e {
        Expr::Num(n) => Val::Num(*n),
        Expr::Str(s) => Val::text(s),
        Expr::Bool(b) => Val::Bool(*b),
        Expr::Var(s) => env.vars.get(*s).copied().unwrap_or(Val::Unknown),
        Expr::Field(i) => {
            env.fields.get(*i).map(|l| read_loc(env.payload, l)).unwrap_or(Val::Unknown)
        }
        Expr::Const(i) => env.consts.get(*i).map(|v| Val::Num(*v)).unwrap_or(Val::Unknown),
        Expr::Key(i) => env.keys.get(*i).copied().unwrap_or(Val::Unknown),
        Expr::Vehicle(a) => {
            let Some(v) = env.vehicle else {
                return Val::Unknown;
            };
            let num = |x: Option<f64>| x.map(Val::Num).unwrap_or(Val::Unknown);
            match a {
                VehicleAttr::Armed => v.armed.map(Val::Bool).unwrap_or(Val::Unknown),
                VehicleAttr::Mode => num(v.custom_mode.map(f64::from)),
                VehicleAttr::Alt => num(v.alt_m),
                VehicleAttr::Climb => num(v.climb_ms),
                VehicleAttr::Type => num(v.mav_type.map(f64::from)),
            }
        }
        Expr::Param(i) => match env.vehicle.and_then(|v| v.params.get(*i).copied().flatten()) {
            Some(x) => Val::Num(x),
            None => Val::Unknown,
        },
        Expr::ParamOf(id) => match eval(id, env) {
            Val::Text(b, n) => {
                let id = &b[..usize::from(n)];
                let slot =
                    env.param_names.iter().position(|p| p.as_bytes().eq_ignore_ascii_case(id));
                match slot.and_then(|i| env.vehicle?.params.get(i).copied().flatten()) {
                    Some(x) => Val::Num(x),
                    None => Val::Unknown,
                }
            }
            _ => Val::Unknown,
        },
        Expr::Call(f, a) => call(*f, eval(a, env)),
        Expr::Interp(parts) => interpolate(parts, env),
        Expr::Not(a) => match eval(a, env) {
            Val::Bool(b) => Val::Bool(!b),
            _ => Val::Unknown,
        },
        Expr::Neg(a) => match eval(a, env) {
            Val::Num(x) => Val::Num(-x),
            _ => Val::Unknown,
        },
        Expr::Bin(op, a, b) => bin(*op, a, b, env),
    }
}

/// A built-in function on a value; anything it is not defined for is unknown.
pub fn call(f: Builtin, v: Val) -> Val {
    match (f, v) {
        (Builtin::Known, v) => Val::Bool(v != Val::Unknown),
        (Builtin::Int { bits, signed }, Val::Num(x)) => {
            let t = x.trunc();
            let (lo, hi) = if signed {
                (-(2f64.powi(i32::from(bits) - 1)), 2f64.powi(i32::from(bits) - 1) - 1.0)
            } else {
                (0.0, 2f64.powi(i32::from(bits)) - 1.0)
            };
            // NaN fails both comparisons: unknown, like infinities and out-of-range values.
            if t >= lo && t <= hi {
                Val::Num(t + 0.0) // -0.0 → 0
            } else {
                Val::Unknown
            }
        }
        (Builtin::Float32, Val::Num(x)) => Val::Num(f64::from(x as f32)),
        (Builtin::Finite, Val::Num(x)) => Val::Bool(x.is_finite()),
        (Builtin::Upper, Val::Text(mut b, n)) => {
            b[..usize::from(n)].make_ascii_uppercase();
            Val::Text(b, n)
        }
        _ => Val::Unknown,
    }
}

/// Text with whole numbers written into it; unknown when a number is unknown or not whole, or
/// the text is longer than [`TEXT_MAX`].
fn interpolate(parts: &[InterpIR], env: &Env) -> Val {
    let mut buf = [0u8; TEXT_MAX];
    let mut n = 0;
    for p in parts {
        let mut digits = [0u8; 24];
        let piece: &[u8] = match p {
            InterpIR::Text(t) => t,
            InterpIR::Num(e) => match eval(e, env) {
                Val::Num(x) if x.fract() == 0.0 && x.abs() < 1e15 => {
                    let len = write_whole(x as i64, &mut digits);
                    &digits[..len]
                }
                _ => return Val::Unknown,
            },
        };
        let Some(dst) = buf.get_mut(n..n + piece.len()) else { return Val::Unknown };
        dst.copy_from_slice(piece);
        n += piece.len();
    }
    Val::Text(buf, n as u8)
}

/// `v` in decimal into `out`; the number of bytes written.
fn write_whole(v: i64, out: &mut [u8; 24]) -> usize {
    let mut tmp = [0u8; 24];
    let mut k = 0;
    let mut m = v.unsigned_abs();
    loop {
        tmp[k] = b'0' + (m % 10) as u8;
        k += 1;
        m /= 10;
        if m == 0 {
            break;
        }
    }
    let mut len = 0;
    if v < 0 {
        out[0] = b'-';
        len = 1;
    }
    for i in (0..k).rev() {
        out[len] = tmp[i];
        len += 1;
    }
    len
}

fn bin(op: BinOp, a: &Expr, b: &Expr, env: &Env) -> Val {
    // Short-circuit with three-valued logic: false && unknown = false, true || unknown = true.
    match op {
        BinOp::And => {
            return match (eval(a, env), eval(b, env)) {
                (Val::Bool(false), _) | (_, Val::Bool(false)) => Val::Bool(false),
                (Val::Bool(true), Val::Bool(true)) => Val::Bool(true),
                _ => Val::Unknown,
            };
        }
        BinOp::Or => {
            return match (eval(a, env), eval(b, env)) {
                (Val::Bool(true), _) | (_, Val::Bool(true)) => Val::Bool(true),
                (Val::Bool(false), Val::Bool(false)) => Val::Bool(false),
                _ => Val::Unknown,
            };
        }
        _ => {}
    }
    let (x, y) = (eval(a, env), eval(b, env));
    match (x, y) {
        (Val::Num(x), Val::Num(y)) => match op {
            BinOp::Eq => Val::Bool(x == y),
            BinOp::Ne => Val::Bool(x != y),
            BinOp::Lt => Val::Bool(x < y),
            BinOp::Le => Val::Bool(x <= y),
            BinOp::Gt => Val::Bool(x > y),
            BinOp::Ge => Val::Bool(x >= y),
            BinOp::Add => Val::Num(x + y),
            BinOp::Sub => Val::Num(x - y),
            BinOp::Mul => Val::Num(x * y),
            BinOp::Div => Val::Num(x / y),
            BinOp::And | BinOp::Or => Val::Unknown,
        },
        (Val::Text(a, n), Val::Text(b, m)) => {
            let eq = a[..usize::from(n)] == b[..usize::from(m)];
            match op {
                BinOp::Eq => Val::Bool(eq),
                BinOp::Ne => Val::Bool(!eq),
                _ => Val::Unknown,
            }
        }
        (Val::Bool(a), Val::Bool(b)) => match op {
            BinOp::Eq => Val::Bool(a == b),
            BinOp::Ne => Val::Bool(a != b),
            _ => Val::Unknown,
        },
        _ => Val::Unknown,
    }
}

/// Index of the first conjunct that is not known to hold, or `None` when all hold.
#[inline]
pub fn first_failing(p: &Pred, env: &Env) -> Option<usize> {
    p.conjuncts.iter().position(|c| eval(&c.expr, env) != Val::Bool(true))
}

/// Whether a selector (`when`) holds; unknown counts as not selected.
#[inline]
pub fn holds(p: &Pred, env: &Env) -> bool {
    first_failing(p, env).is_none()
}
