//! Typing and compilation of expressions and predicates (part of the compiler, see `compile`).

use super::ast::{self, BinOp, ExprKind, InterpPart, UnOp};
use super::compile::{CResult, Compiler, Scope, StepCx, Ty, ty_of_loc};
use super::error::{ErrorKind, ProtocolError, Span};
use super::ir::*;

/// Names whose values a violation report shows, with their compiled expression and enum.
pub(super) type Shows = Vec<(String, Expr, Option<String>)>;

/// Parameter ids have at most 16 characters (PARAM_VALUE.param_id).
const PARAM_ID_LEN: usize = 16;
/// The numbers a parameter family (`param["SERVO{n}_FUNCTION"]`) is tracked for: the autopilots
/// number outputs, relays and RC channels from 0 or 1 up to 32 at most.
pub(super) const FAMILY_INDICES: std::ops::RangeInclusive<u32> = 0..=32;

fn show(shows: &mut Shows, name: &str, x: &Expr, t: &Ty) {
    if !shows.iter().any(|(s, _, _)| s == name) {
        let en = match t {
            Ty::Num { enum_ } => enum_.clone(),
            _ => None,
        };
        shows.push((name.to_string(), x.clone(), en));
    }
}

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
            let x = self.condition(p, scope, step.as_deref_mut(), &mut shows)?;
            conjuncts.push(Conjunct { expr: x, text: self.text_of(p.span), shows });
        }
        Ok(Pred { conjuncts })
    }

    /// A boolean expression (a condition).
    pub(super) fn condition(
        &mut self,
        e: &ast::Expr,
        scope: &mut Scope,
        step: Option<&mut StepCx>,
        shows: &mut Shows,
    ) -> CResult<Expr> {
        let (x, ty) = self.expr(e, scope, step, shows)?;
        if ty != Ty::Bool {
            return self.err(
                ErrorKind::Type,
                e.span,
                format!("a condition must be a boolean, this is {}", ty.describe()),
            );
        }
        Ok(x)
    }

    /// The source text of a span (for reports).
    pub(super) fn text_of(&self, span: Span) -> String {
        self.src.get(span.start..span.start + span.len).unwrap_or("").to_string()
    }

    /// Compiles an expression, resolving names: variables in scope, fields of the current
    /// message, session keys (replies only), constants, enum entries — in that order.
    pub(super) fn expr(
        &mut self,
        e: &ast::Expr,
        scope: &mut Scope,
        mut step: Option<&mut StepCx>,
        shows: &mut Shows,
    ) -> CResult<(Expr, Ty)> {
        Ok(match &e.kind {
            ExprKind::Num(n) => (Expr::Num(*n), Ty::num()),
            ExprKind::Str(s) => (Expr::Str(s.as_bytes().into()), Ty::Str),
            ExprKind::Bool(b) => (Expr::Bool(*b), Ty::Bool),
            ExprKind::Name(n) => {
                let r = self.name(n, e.span, scope, step)?;
                show(shows, n, &r.0, &r.1);
                r
            }
            ExprKind::Vehicle(m) => {
                let (attr, ty) = self.vehicle_attr(m)?;
                let x = Expr::Vehicle(attr);
                show(shows, &format!("vehicle.{}", m.name), &x, &ty);
                (x, ty)
            }
            ExprKind::Param(m) => {
                if m.name.len() > PARAM_ID_LEN {
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
                let x = self.param_of(a, scope, step, shows)?;
                show(shows, &format!("param[{}]", self.text_of(a.span)), &x, &Ty::num());
                (x, Ty::num())
            }
            ExprKind::Interp(parts) => (self.interpolation(parts, scope, step, shows)?, Ty::Str),
            ExprKind::Call(f, a) => self.call(f, a, scope, step, shows)?,
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

    /// A name: a variable in scope, in a reply a session variable or key, a field of the current
    /// message, a constant or an enum entry.
    fn name(
        &mut self,
        n: &str,
        span: Span,
        scope: &mut Scope,
        step: Option<&mut StepCx>,
    ) -> CResult<(Expr, Ty)> {
        let label = step.as_ref().map(|st| st.label_text.clone());
        if let Some((_, slot, ty)) = scope.vars.iter().rev().find(|(v, _, _)| v == n) {
            return Ok((Expr::Var(*slot), ty.clone()));
        }
        if self.in_reply
            && let Some(slot) = self.proto.var_names.iter().rposition(|v| v == n)
        {
            return Ok((Expr::Var(slot), Ty::num()));
        }
        if self.in_reply
            && let Some(i) = self.keys.iter().position(|k| k == n)
        {
            let loc = self.proto.keys.get(i).and_then(|k| k.locs.first());
            return Ok((Expr::Key(i), loc.map_or_else(Ty::num, |(_, l)| ty_of_loc(l))));
        }
        if let Some(st) = step
            && st.msgs.iter().any(|&m| self.dialect.message(m).field(n).is_some())
        {
            let (slot, ty) = self.field_slot(st, n, span)?;
            return Ok((Expr::Field(slot), ty));
        }
        if let Some(i) = self.set.consts.iter().position(|k| k.name == n) {
            return Ok((Expr::Const(i), Ty::num()));
        }
        if let Some((en, v)) = self.dialect.enum_entry(n) {
            return Ok((Expr::Num(v as f64), Ty::Num { enum_: Some(en.to_string()) }));
        }
        let help = match &label {
            Some(label) => format!(
                "not a variable in scope, a field of {label}, a constant or an enum entry of the dialect"
            ),
            None => {
                "not a variable in scope, a constant or an enum entry of the dialect".to_string()
            }
        };
        Err(ProtocolError::at(
            ErrorKind::UnknownName,
            self.src,
            span,
            format!("unbound name `{n}`"),
        )
        .with_help(help))
    }

    fn vehicle_attr(&self, m: &ast::Ident) -> CResult<(VehicleAttr, Ty)> {
        Ok(match m.name.as_str() {
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
        })
    }

    /// `param[EXPR]`. A constant id is looked up at load time; an interpolated id with one
    /// number in it (`"SERVO{n}_FUNCTION"`) makes the whole family tracked.
    fn param_of(
        &mut self,
        a: &ast::Expr,
        scope: &mut Scope,
        step: Option<&mut StepCx>,
        shows: &mut Shows,
    ) -> CResult<Expr> {
        let (x, t) = self.expr(a, scope, step, shows)?;
        self.expect_compatible(&Ty::Str, &t, a.span)?;
        match &x {
            Expr::Str(id) if id.len() <= PARAM_ID_LEN => {
                let name = String::from_utf8_lossy(id).into_owned();
                return Ok(Expr::Param(self.set.params.intern(&name)));
            }
            Expr::Interp(parts) => {
                if let [InterpIR::Text(prefix), InterpIR::Num(_), InterpIR::Text(suffix)] =
                    &parts[..]
                {
                    self.track_family(prefix, suffix);
                } else if let [InterpIR::Text(prefix), InterpIR::Num(_)] = &parts[..] {
                    self.track_family(prefix, &[]);
                }
            }
            _ => {}
        }
        Ok(Expr::ParamOf(Box::new(x)))
    }

    fn track_family(&mut self, prefix: &[u8], suffix: &[u8]) {
        for i in FAMILY_INDICES {
            let name = format!(
                "{}{i}{}",
                String::from_utf8_lossy(prefix),
                String::from_utf8_lossy(suffix)
            );
            if name.len() <= PARAM_ID_LEN {
                self.set.params.intern(&name);
            }
        }
    }

    /// `"…{EXPR}…"`: the numbers are written as whole decimal numbers. Folded to a text when every
    /// part is a literal.
    fn interpolation(
        &mut self,
        parts: &[InterpPart],
        scope: &mut Scope,
        mut step: Option<&mut StepCx>,
        shows: &mut Shows,
    ) -> CResult<Expr> {
        let mut out: Vec<InterpIR> = vec![];
        for p in parts {
            match p {
                InterpPart::Text(t) => out.push(InterpIR::Text(t.as_bytes().into())),
                InterpPart::Expr(e) => {
                    let (x, t) = self.expr(e, scope, step.as_deref_mut(), shows)?;
                    self.expect_compatible(&Ty::num(), &t, e.span)?;
                    match x {
                        Expr::Num(v) if v.fract() == 0.0 && v.abs() < 1e15 => {
                            out.push(InterpIR::Text(format!("{}", v as i64).into_bytes().into()))
                        }
                        x => out.push(InterpIR::Num(x)),
                    }
                }
            }
        }
        // Adjacent texts are merged, so that a folded number joins its neighbours.
        let mut merged: Vec<InterpIR> = vec![];
        for p in out {
            match (merged.last_mut(), p) {
                (Some(InterpIR::Text(a)), InterpIR::Text(b)) => {
                    let mut v = a.to_vec();
                    v.extend_from_slice(&b);
                    *a = v.into();
                }
                (_, p) => merged.push(p),
            }
        }
        Ok(match &merged[..] {
            [] => Expr::Str(Box::default()),
            [InterpIR::Text(t)] => Expr::Str(t.clone()),
            _ => Expr::Interp(merged),
        })
    }

    fn call(
        &mut self,
        f: &ast::Ident,
        a: &ast::Expr,
        scope: &mut Scope,
        step: Option<&mut StepCx>,
        shows: &mut Shows,
    ) -> CResult<(Expr, Ty)> {
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
            Builtin::Int { .. } | Builtin::Float32 => (Some(Ty::num()), Ty::num()),
            Builtin::Finite => (Some(Ty::num()), Ty::Bool),
            Builtin::Upper => (Some(Ty::Str), Ty::Str),
            Builtin::Known => (None, Ty::Bool),
        };
        if let Some(arg) = arg {
            self.expect_compatible(&arg, &t, a.span)?;
        }
        Ok((Expr::Call(b, Box::new(x)), result))
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
