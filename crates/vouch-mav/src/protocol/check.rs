//! Checker and compiler: resolves every name of a parsed protocol file against the dialect and
//! produces the executable [`ir`](super::ir). Unknown messages, fields, enum entries, roles,
//! unbound variables and type mismatches are located errors (`vouch mav lint`).

use super::ast::{self, BinOp, ExprKind, Stmt, UnOp};
use super::error::{ProtocolError, Span};
use super::ir::*;
pub(crate) use super::typing::Ty;
use crate::dialect::{Dialect, MessageDef, MsgIndex, PrimType};

/// Field context of the step being compiled: which messages, which field slots.
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
    pub(super) proto: Option<Protocol>,
    /// Key names of the protocol being compiled (usable in reply expressions).
    pub(super) keys: Vec<String>,
    pub(super) in_reply: bool,
}

/// The monitor updates recursion variables through a fixed-size buffer (no allocation).
pub const MAX_CONTINUE_ASSIGNS: usize = 8;

pub(super) type CResult<T> = Result<T, ProtocolError>;

pub(super) fn loc_of(def: &MessageDef, name: &str) -> Option<FieldLoc> {
    let f = def.field(name)?;
    Some(FieldLoc {
        ty: f.ty,
        offset: f.offset,
        text_len: if f.ty == PrimType::Char && f.array_len > 0 {
            f.array_len
        } else {
            0
        },
        enum_name: f.enum_name.clone(),
    })
}

pub(super) fn ty_of_loc(l: &FieldLoc) -> Ty {
    if l.text_len > 0 {
        Ty::Str
    } else {
        Ty::Num {
            enum_: l.enum_name.clone(),
        }
    }
}

impl<'a> Compiler<'a> {
    pub fn new(dialect: &'a Dialect, src: &'a str, set: &'a mut ProtocolSet) -> Self {
        Compiler {
            dialect,
            src,
            set,
            proto: None,
            keys: vec![],
            in_reply: false,
        }
    }

    pub(super) fn err<T>(&self, span: Span, msg: impl Into<String>) -> CResult<T> {
        Err(ProtocolError::at(self.src, span, msg))
    }

    pub fn file(&mut self, file: &ast::FileAst) -> CResult<()> {
        for c in &file.consts {
            self.const_decl(c)?;
        }
        for p in &file.protocols {
            for c in &p.consts {
                self.const_decl(c)?;
            }
            if self.set.protocols.iter().any(|q| q.name == p.name.name) {
                return self.err(
                    p.name.span,
                    format!("protocol `{}` is defined twice", p.name.name),
                );
            }
            let proto = self.protocol(p)?;
            self.set.protocols.push(proto);
        }
        Ok(())
    }

    fn const_decl(&mut self, c: &ast::ConstDecl) -> CResult<()> {
        if self.set.consts.iter().any(|k| k.name == c.name.name) {
            return self.err(
                c.name.span,
                format!("constant `{}` is defined twice", c.name.name),
            );
        }
        let value = self.const_value(&c.value)?;
        self.set.consts.push(ConstIR {
            name: c.name.name.clone(),
            value,
        });
        Ok(())
    }

    /// Folds a constant expression (numbers, earlier constants, enum entries, arithmetic).
    fn const_value(&self, e: &ast::Expr) -> CResult<f64> {
        Ok(match &e.kind {
            ExprKind::Num(n) => *n,
            ExprKind::Name(n) => {
                if let Some(k) = self.set.consts.iter().find(|k| &k.name == n) {
                    k.value
                } else if let Some((_, v)) = self.dialect.enum_entry(n) {
                    v as f64
                } else {
                    return self.err(e.span, format!("`{n}` is not a constant or enum entry"));
                }
            }
            ExprKind::Unary(UnOp::Neg, x) => -self.const_value(x)?,
            ExprKind::Binary(op, a, b) => {
                let (a, b) = (self.const_value(a)?, self.const_value(b)?);
                match op {
                    BinOp::Add => a + b,
                    BinOp::Sub => a - b,
                    BinOp::Mul => a * b,
                    BinOp::Div => a / b,
                    _ => return self.err(e.span, "a constant must be a number"),
                }
            }
            _ => return self.err(e.span, "a constant must be a number"),
        })
    }

    fn protocol(&mut self, p: &ast::ProtocolDecl) -> CResult<Protocol> {
        if p.roles.len() != 2 {
            return self.err(
                p.name.span,
                "a protocol declares exactly two roles: `roles gcs, uav;`",
            );
        }
        let mut roles = vec![];
        for r in &p.roles {
            let kind = match r.name.as_str() {
                "gcs" | "ground" => RoleKind::Gcs,
                "uav" | "vehicle" | "autopilot" => RoleKind::Vehicle,
                _ => return self.err(r.span, format!("unknown role `{}`", r.name)).map_err(|e| {
                    e.with_help("roles are `gcs` (ground station) and `uav` (vehicle; also `vehicle`, `autopilot`)")
                }),
            };
            roles.push((r.name.clone(), kind));
        }
        if roles[0].1 == roles[1].1 {
            return self.err(
                p.roles[1].span,
                "the two roles must be a ground station and a vehicle",
            );
        }
        self.keys = p.keys.iter().map(|k| k.name.clone()).collect();
        self.proto = Some(Protocol {
            name: p.name.name.clone(),
            roles,
            keys: vec![],
            timeout_us: Some(p.timeout_ms.map(|(ms, _)| ms).unwrap_or(30_000) * 1000),
            strict: vec![],
            reply: None,
            states: vec![],
            recs: vec![],
            var_names: vec![],
            alphabet: vec![],
        });
        match p.body.first() {
            Some(Stmt::Step { .. }) | Some(Stmt::Choice { .. }) => {}
            Some(_) => {
                return self.err(
                    p.name.span,
                    "a protocol must start with a message step or a choice",
                )
            }
            None => {
                return self.err(
                    p.name.span,
                    "empty protocol: it needs at least one message step",
                )
            }
        }
        let mut scope = Scope::default();
        self.state_for(&p.body, &mut scope)?;
        for s in &p.strict {
            let from = self.role(&s.from)?;
            let to = self.role(&s.to)?;
            if from == to {
                return self.err(s.to.span, "sender and receiver must differ");
            }
            let msgs = self.messages(&s.labels)?;
            let text = format!(
                "{} -> {} : {}",
                s.from.name,
                s.to.name,
                s.labels
                    .iter()
                    .map(|l| l.name.as_str())
                    .collect::<Vec<_>>()
                    .join(" | ")
            );
            self.proto_mut().strict.push(StrictIR { from, msgs, text });
        }
        let mut proto = self.proto.take().expect("protocol under construction");
        let mut alphabet: Vec<MsgIndex> = proto
            .states
            .iter()
            .flat_map(|s| {
                s.transitions
                    .iter()
                    .flat_map(|t| t.msgs.iter().map(|m| m.msg))
            })
            .chain(proto.strict.iter().flat_map(|s| s.msgs.iter().copied()))
            .collect();
        alphabet.sort_unstable();
        alphabet.dedup();
        for k in &p.keys {
            let locs: Vec<(MsgIndex, FieldLoc)> = alphabet
                .iter()
                .filter_map(|&m| loc_of(self.dialect.message(m), &k.name).map(|l| (m, l)))
                .collect();
            if locs.is_empty() {
                return self.err(
                    k.span,
                    format!(
                        "key `{}` is a field of none of the protocol's messages",
                        k.name
                    ),
                );
            }
            proto.keys.push(KeyIR {
                name: k.name.clone(),
                locs,
            });
        }
        proto.alphabet = alphabet;
        if let Some(r) = &p.reply {
            self.proto = Some(proto);
            let reply = self.reply(r)?;
            proto = self.proto.take().expect("protocol under construction");
            proto.reply = Some(reply);
        }
        Ok(proto)
    }

    fn proto_mut(&mut self) -> &mut Protocol {
        self.proto.as_mut().expect("protocol under construction")
    }

    fn role(&self, r: &ast::Ident) -> CResult<usize> {
        let proto = self.proto.as_ref().expect("protocol under construction");
        match proto.roles.iter().position(|(n, _)| *n == r.name) {
            Some(i) => Ok(i),
            None => self.err(
                r.span,
                format!("`{}` is not a role of this protocol", r.name),
            ),
        }
    }

    fn messages(&self, labels: &[ast::Ident]) -> CResult<Vec<MsgIndex>> {
        labels
            .iter()
            .map(|l| match self.dialect.index_of_name(&l.name) {
                Some(i) => Ok(i),
                None => self.err(
                    l.span,
                    format!(
                        "unknown message `{}` in dialect {}",
                        l.name, self.dialect.name
                    ),
                ),
            })
            .collect()
    }

    fn reply(&mut self, r: &ast::ReplyDecl) -> CResult<ReplyIR> {
        let to = self.role(&r.to)?;
        let msg = self.messages(std::slice::from_ref(&r.message))?[0];
        let def = self.dialect.message(msg);
        let mut fields = vec![];
        self.in_reply = true;
        for (f, e) in &r.fields {
            let Some(loc) = loc_of(def, &f.name) else {
                self.in_reply = false;
                return self.err(
                    f.span,
                    format!("message {} has no field `{}`", def.name, f.name),
                );
            };
            let mut scope = Scope::default();
            let mut shows = vec![];
            let (x, ty) = self.expr(e, &mut scope, None, &mut shows)?;
            self.expect_compatible(&ty_of_loc(&loc), &ty, e.span)?;
            fields.push((f.name.clone(), x));
        }
        self.in_reply = false;
        Ok(ReplyIR { to, msg, fields })
    }

    fn new_var(&mut self, name: &str) -> Slot {
        let p = self.proto_mut();
        p.var_names.push(name.to_string());
        p.var_names.len() - 1
    }

    /// Continuation of the statements `stmts`, compiled in the context of the step just taken.
    fn seq(
        &mut self,
        stmts: &[Stmt],
        scope: &mut Scope,
        mut step: Option<&mut StepCx>,
    ) -> CResult<Cont> {
        let Some(first) = stmts.first() else {
            return Ok(Cont::End);
        };
        let trailing = |this: &Self, what: &str| -> CResult<()> {
            if let Some(next) = stmts.get(1) {
                return this.err(
                    stmt_span(next),
                    format!("unreachable: nothing can follow {what}"),
                );
            }
            Ok(())
        };
        match first {
            Stmt::End(_) => {
                trailing(self, "`end`")?;
                Ok(Cont::End)
            }
            Stmt::Continue { name, assigns, .. } => {
                trailing(self, "`continue`")?;
                let Some((_, rec, vars)) = scope
                    .recs
                    .iter()
                    .rev()
                    .find(|(n, _, _)| *n == name.name)
                    .cloned()
                else {
                    return self.err(
                        name.span,
                        format!("`continue {}` outside of `rec {}`", name.name, name.name),
                    );
                };
                if assigns.len() > MAX_CONTINUE_ASSIGNS {
                    return self.err(name.span, format!("at most {MAX_CONTINUE_ASSIGNS} variables can be updated by one `continue`"));
                }
                let mut out = vec![];
                for (v, e) in assigns {
                    let Some((_, slot)) = vars.iter().find(|(n, _)| *n == v.name) else {
                        return self.err(
                            v.span,
                            format!("`{}` is not a variable of `rec {}`", v.name, name.name),
                        );
                    };
                    let want = scope
                        .vars
                        .iter()
                        .rev()
                        .find(|(_, s, _)| s == slot)
                        .map(|(_, _, t)| t.clone());
                    let mut shows = vec![];
                    let (x, ty) = self.expr(e, scope, step.as_deref_mut(), &mut shows)?;
                    if let Some(want) = want {
                        self.expect_compatible(&want, &ty, e.span)?;
                    }
                    out.push((*slot, x));
                }
                Ok(Cont::Continue { rec, assigns: out })
            }
            Stmt::Rec {
                name,
                vars,
                invariant,
                body,
            } => {
                trailing(
                    self,
                    "a `rec` block (end its body with `end` or `continue`)",
                )?;
                let rec = self.proto_mut().recs.len();
                self.proto_mut().recs.push(Rec {
                    name: name.name.clone(),
                    invariant: None,
                    entry: 0,
                });
                let mut assigns = vec![];
                let mut rec_vars = vec![];
                let mark = scope.vars.len();
                for v in vars {
                    let mut shows = vec![];
                    let (x, ty) = self.expr(&v.init, scope, step.as_deref_mut(), &mut shows)?;
                    let ty = match v.ty {
                        None => ty,
                        Some(t) => {
                            let want = match t {
                                ast::TypeName::Int | ast::TypeName::Float => Ty::num(),
                                ast::TypeName::Bool => Ty::Bool,
                                ast::TypeName::Str => Ty::Str,
                            };
                            self.expect_compatible(&want, &ty, v.init.span)?;
                            ty
                        }
                    };
                    let slot = self.new_var(&v.name.name);
                    assigns.push((slot, x));
                    rec_vars.push((v.name.name.clone(), slot, ty));
                }
                for (n, s, t) in &rec_vars {
                    scope.vars.push((n.clone(), *s, t.clone()));
                }
                scope.recs.push((
                    name.name.clone(),
                    rec,
                    rec_vars.iter().map(|(n, s, _)| (n.clone(), *s)).collect(),
                ));
                if let Some(inv) = invariant {
                    let pred = self.pred(inv, scope, None)?;
                    self.proto_mut().recs[rec].invariant = Some(pred);
                }
                match body.first() {
                    Some(Stmt::Step { .. }) | Some(Stmt::Choice { .. }) => {}
                    _ => {
                        return self.err(
                            name.span,
                            "the body of a `rec` must start with a message step or a choice",
                        )
                    }
                }
                let then = self.state_for(body, scope)?;
                self.proto_mut().recs[rec].entry = then;
                scope.recs.pop();
                scope.vars.truncate(mark);
                Ok(Cont::Enter { rec, assigns, then })
            }
            Stmt::Step { .. } | Stmt::Choice { .. } => {
                Ok(Cont::Goto(self.state_for(stmts, scope)?))
            }
        }
    }

    /// A state whose transitions are the step or choice at the head of `stmts`.
    fn state_for(&mut self, stmts: &[Stmt], scope: &mut Scope) -> CResult<StateId> {
        let id = self.proto_mut().states.len();
        self.proto_mut().states.push(State::default());
        let mut transitions = vec![];
        let mut complete = None;
        match &stmts[0] {
            Stmt::Step { head, block } => {
                let rest = match block {
                    Some(b) => {
                        if let Some(next) = stmts.get(1) {
                            return self.err(
                                stmt_span(next),
                                "unreachable: a step with a block is followed by its block only",
                            );
                        }
                        &b[..]
                    }
                    None => &stmts[1..],
                };
                let label = head.labels[0].name.to_ascii_lowercase();
                transitions.push(self.transition(label, head, rest, scope)?);
            }
            Stmt::Choice {
                branches,
                complete_when,
                ..
            } => {
                if let Some(next) = stmts.get(1) {
                    return self.err(
                        stmt_span(next),
                        "unreachable: put what follows a choice into its branches",
                    );
                }
                for b in branches {
                    if transitions
                        .iter()
                        .any(|t: &Transition| t.label == b.label.name)
                    {
                        return self.err(
                            b.label.span,
                            format!("branch label `{}` used twice", b.label.name),
                        );
                    }
                    transitions.push(self.transition(
                        b.label.name.clone(),
                        &b.head,
                        &b.body,
                        scope,
                    )?);
                }
                if let Some(c) = complete_when {
                    complete = Some(self.pred(c, scope, None)?);
                }
            }
            other => return self.err(stmt_span(other), "expected a message step or a choice here"),
        }
        let st = &mut self.proto_mut().states[id];
        st.transitions = transitions;
        st.complete_when = complete;
        Ok(id)
    }

    fn transition(
        &mut self,
        label: String,
        head: &ast::StepHead,
        rest: &[Stmt],
        scope: &mut Scope,
    ) -> CResult<Transition> {
        let from = self.role(&head.from)?;
        let to = self.role(&head.to)?;
        if from == to {
            return self.err(head.to.span, "sender and receiver must differ");
        }
        let msgs = self.messages(&head.labels)?;
        let label_text = head
            .labels
            .iter()
            .map(|l| l.name.as_str())
            .collect::<Vec<_>>()
            .join(" | ");
        let mut step = StepCx {
            msgs: msgs.clone(),
            names: vec![],
            locs: vec![vec![]; msgs.len()],
            label_text: label_text.clone(),
        };
        let mark = scope.vars.len();
        let mut binds = vec![];
        for (v, f) in &head.binds {
            let (fslot, ty) = self.field_slot(&mut step, &f.name, f.span)?;
            let slot = self.new_var(&v.name);
            scope.vars.push((v.name.clone(), slot, ty));
            binds.push((slot, fslot));
        }
        let when = match &head.when {
            Some(e) => Some(self.pred(e, scope, Some(&mut step))?),
            None => None,
        };
        let where_ = match &head.where_ {
            Some(e) => Some(self.pred(e, scope, Some(&mut step))?),
            None => None,
        };
        let cont = self.seq(rest, scope, Some(&mut step))?;
        scope.vars.truncate(mark);
        let msgs = msgs
            .iter()
            .zip(step.locs)
            .map(|(&msg, fields)| LabelFields { msg, fields })
            .collect();
        Ok(Transition {
            label,
            from,
            to,
            msgs,
            field_names: step.names,
            binds,
            when,
            where_,
            cont,
            text: format!("{} -> {} : {}", head.from.name, head.to.name, label_text),
        })
    }

    /// Slot of field `name` in the current step; the field must exist in every alternative message.
    pub(super) fn field_slot(
        &self,
        step: &mut StepCx,
        name: &str,
        span: Span,
    ) -> CResult<(usize, Ty)> {
        if let Some(i) = step.names.iter().position(|n| n == name) {
            return Ok((i, ty_of_loc(&step.locs[0][i])));
        }
        let mut locs = vec![];
        for &m in &step.msgs {
            let def = self.dialect.message(m);
            match loc_of(def, name) {
                Some(l) => locs.push(l),
                None => {
                    return self.err(span, format!("message {} has no field `{name}`", def.name))
                }
            }
        }
        let ty = ty_of_loc(&locs[0]);
        if locs.iter().any(|l| ty_of_loc(l) != ty) {
            return self.err(
                span,
                format!("field `{name}` has different types in {}", step.label_text),
            );
        }
        step.names.push(name.to_string());
        for (i, l) in locs.into_iter().enumerate() {
            step.locs[i].push(l);
        }
        Ok((step.names.len() - 1, ty))
    }
}

fn stmt_span(s: &Stmt) -> Span {
    match s {
        Stmt::Step { head, .. } => head.span,
        Stmt::Choice { span, .. } => *span,
        Stmt::Rec { name, .. } => name.span,
        Stmt::Continue { span, .. } => *span,
        Stmt::End(s) => *s,
    }
}
