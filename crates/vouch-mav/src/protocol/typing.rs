//! Typing and compilation of expressions and predicates (part of the compiler, see `compile`).

use super::ast::{self, BinOp, ExprKind, UnOp};
use super::compile::{CResult, Compiler, Scope, StepCx, Ty, ty_of_loc};
use super::error::{ErrorKind, ProtocolError, Span};
use super::ir::*;

impl<'a> Compiler<'a> {
    pub(super) fn expect_compatible(&self, want: &Ty, got: &Ty, span: Span) -> CResult<()> {
        let ok = match (want, got) {
            (Ty::Num { enum_: Some(a) }, Ty::Num { enum_: Some(b) }) => a == b,
            (Ty::Num { .. }, Ty::Num { .. }) => true,
            (Ty::Str, Ty::Str) | (Ty::Bool, Ty::Bool) => true,
            _ => false,
        };
        if ok {
            Ok(())
        } else {
            self.err(
                ErrorKind::Type,
                span,
                format!("type mismatch: expected {}, found {}", want.describe(), got.describe()),
            )
        }
    }

    pub(super) fn pred(
        &mut self,
        e: &ast::Expr,
        scope: &mut Scope,
        mut step: Option<&mut StepCx>,
    ) -> CResult<Pred> {
        let mut parts = vec![];
        flatten_and(e, &mut parts);
        let mut conjuncts = vec![];
        for p in parts {
            let mut shows = vec![];
            let (x, ty) = self.expr(p, scope, step.as_deref_mut(), &mut shows)?;
            if ty != Ty::Bool {
                return self.err(
                    ErrorKind::Type,
                    p.span,
                    format!("a condition must be a boolean, this is {}", ty.describe()),
                );
            }
            let text =
                self.src.get(p.span.start..p.span.start + p.span.len).unwrap_or("").to_string();
            conjuncts.push(Conjunct { expr: x, text, shows });
        }
        Ok(Pred { conjuncts })
    }

    /// Compiles an expression, resolving names: variables in scope, fields of the current
    /// message, session keys (replies only), constants, enum entries — in that order.
    pub(super) fn expr(
        &mut self,
        e: &ast::Expr,
        scope: &mut Scope,
        mut step: Option<&mut StepCx>,
        shows: &mut Vec<(String, Expr, Option<String>)>,
    ) -> CResult<(Expr, Ty)> {
        let show = |shows: &mut Vec<(String, Expr, Option<String>)>, n: &str, x: &Expr, t: &Ty| {
            if !shows.iter().any(|(s, _, _)| s == n) {
                let en = match t {
                    Ty::Num { enum_ } => enum_.clone(),
                    _ => None,
                };
                shows.push((n.to_string(), x.clone(), en));
            }
        };
        Ok(match &e.kind {
            ExprKind::Num(n) => (Expr::Num(*n), Ty::num()),
            ExprKind::Str(s) => (Expr::Str(s.as_bytes().into()), Ty::Str),
            ExprKind::Bool(b) => (Expr::Bool(*b), Ty::Bool),
            ExprKind::Name(n) => {
                let r = if let Some((_, slot, ty)) =
                    scope.vars.iter().rev().find(|(v, _, _)| v == n)
                {
                    (Expr::Var(*slot), ty.clone())
                } else if self.in_reply
                    && self.proto.as_ref().is_some_and(|p| p.var_names.contains(n))
                {
                    let slot = self
                        .proto
                        .as_ref()
                        .and_then(|p| p.var_names.iter().rposition(|v| v == n))
                        .unwrap_or(0);
                    (Expr::Var(slot), Ty::num())
                } else if let Some(i) =
                    self.keys.iter().position(|k| k == n).filter(|_| self.in_reply)
                {
                    let loc = self.proto.as_ref().and_then(|p| p.keys.get(i)?.locs.first());
                    (Expr::Key(i), loc.map_or_else(Ty::num, |(_, l)| ty_of_loc(l)))
                } else if let Some(st) = step.as_deref_mut().filter(|st| {
                    st.msgs.iter().any(|&m| self.dialect.message(m).field(n).is_some())
                }) {
                    let (slot, ty) = self.field_slot(st, n, e.span)?;
                    (Expr::Field(slot), ty)
                } else if let Some(i) = self.set.consts.iter().position(|k| &k.name == n) {
                    (Expr::Const(i), Ty::num())
                } else if let Some((en, v)) = self.dialect.enum_entry(n) {
                    return Ok((Expr::Num(v as f64), Ty::Num { enum_: Some(en.to_string()) }));
                } else {
                    let mut err = ProtocolError::at(
                        ErrorKind::UnknownName,
                        self.src,
                        e.span,
                        format!("unbound name `{n}`"),
                    );
                    err = err.with_help(match &step {
                        Some(st) => format!(
                            "not a variable in scope, a field of {}, a constant or an enum entry of the dialect",
                            st.label_text
                        ),
                        None => "not a variable in scope, a constant or an enum entry of the dialect".to_string(),
                    });
                    return Err(err);
                };
                show(shows, n, &r.0, &r.1);
                r
            }
            ExprKind::Vehicle(m) => {
                let (attr, ty) = match m.name.as_str() {
                    "armed" => (VehicleAttr::Armed, Ty::Bool),
                    "mode" => (VehicleAttr::Mode, Ty::num()),
                    "alt" => (VehicleAttr::Alt, Ty::num()),
                    "climb" => (VehicleAttr::Climb, Ty::num()),
                    "type" => (VehicleAttr::Type, Ty::Num { enum_: Some("MAV_TYPE".into()) }),
                    _ => {
                        return Err(ProtocolError::at(
                            ErrorKind::UnknownName,
                            self.src,
                            m.span,
                            format!("unknown vehicle attribute `{}`", m.name),
                        )
                        .with_help("vehicle attributes: armed, mode, alt, climb, type"));
                    }
                };
                let x = Expr::Vehicle(attr);
                show(shows, &format!("vehicle.{}", m.name), &x, &ty);
                (x, ty)
            }
            ExprKind::Param(m) => {
                if m.name.len() > 16 {
                    return self.err(
                        ErrorKind::Limit,
                        m.span,
                        "parameter names have at most 16 characters",
                    );
                }
                let x = Expr::Param(self.set.params.intern(&m.name));
                show(shows, &format!("param.{}", m.name), &x, &Ty::num());
                (x, Ty::num())
            }
            ExprKind::ParamOf(a) => {
                let (x, t) = self.expr(a, scope, step, shows)?;
                self.expect_compatible(&Ty::Str, &t, a.span)?;
                (Expr::ParamOf(Box::new(x)), Ty::num())
            }
            ExprKind::Call(f, a) => {
                let Some(b) = Builtin::named(&f.name) else {
                    return Err(ProtocolError::at(
                        ErrorKind::UnknownName,
                        self.src,
                        f.span,
                        format!("unknown function `{}`", f.name),
                    )
                    .with_help(format!("functions: {}", Builtin::NAMES)));
                };
                let (x, t) = self.expr(a, scope, step, shows)?;
                let (arg, result) = match b {
                    Builtin::Int { .. } | Builtin::Float32 => (Ty::num(), Ty::num()),
                    Builtin::Finite => (Ty::num(), Ty::Bool),
                    Builtin::Upper => (Ty::Str, Ty::Str),
                };
                self.expect_compatible(&arg, &t, a.span)?;
                (Expr::Call(b, Box::new(x)), result)
            }
            ExprKind::Unary(op, a) => {
                let (x, t) = self.expr(a, scope, step, shows)?;
                match op {
                    UnOp::Not => {
                        self.expect_compatible(&Ty::Bool, &t, a.span)?;
                        (Expr::Not(Box::new(x)), Ty::Bool)
                    }
                    UnOp::Neg => {
                        self.expect_compatible(&Ty::num(), &t, a.span)?;
                        (Expr::Neg(Box::new(x)), Ty::num())
                    }
                }
            }
            ExprKind::Binary(op, a, b) => {
                let (xa, ta) = self.expr(a, scope, step.as_deref_mut(), shows)?;
                let (xb, tb) = self.expr(b, scope, step, shows)?;
                let ty = self.binary_type(*op, &ta, &tb, e.span)?;
                (Expr::Bin(*op, Box::new(xa), Box::new(xb)), ty)
            }
        })
    }

    fn binary_type(&self, op: BinOp, a: &Ty, b: &Ty, span: Span) -> CResult<Ty> {
        let mismatch = || {
            self.err(
                ErrorKind::Type,
                span,
                format!(
                    "type mismatch: `{}` between {} and {}",
                    op.text(),
                    a.describe(),
                    b.describe()
                ),
            )
        };
        match op {
            BinOp::And | BinOp::Or => {
                if *a == Ty::Bool && *b == Ty::Bool {
                    Ok(Ty::Bool)
                } else {
                    mismatch()
                }
            }
            BinOp::Eq | BinOp::Ne => match (a, b) {
                (Ty::Num { enum_: Some(x) }, Ty::Num { enum_: Some(y) }) if x != y => mismatch(),
                (Ty::Num { .. }, Ty::Num { .. }) | (Ty::Str, Ty::Str) | (Ty::Bool, Ty::Bool) => {
                    Ok(Ty::Bool)
                }
                _ => mismatch(),
            },
            BinOp::Lt | BinOp::Le | BinOp::Gt | BinOp::Ge => match (a, b) {
                (Ty::Num { enum_: Some(x) }, Ty::Num { enum_: Some(y) }) if x != y => mismatch(),
                (Ty::Num { .. }, Ty::Num { .. }) => Ok(Ty::Bool),
                _ => mismatch(),
            },
            BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div => match (a, b) {
                (Ty::Num { .. }, Ty::Num { .. }) => Ok(Ty::num()),
                _ => mismatch(),
            },
        }
    }
}

pub(super) fn flatten_and<'e>(e: &'e ast::Expr, out: &mut Vec<&'e ast::Expr>) {
    match &e.kind {
        ExprKind::Binary(BinOp::And, a, b) => {
            flatten_and(a, out);
            flatten_and(b, out);
        }
        _ => out.push(e),
    }
}
