//! Checker and compiler: resolves every name of a parsed protocol file against the dialect and
//! produces the executable [`ir`](super::ir). Unknown messages, fields, enum entries, roles,
//! unbound variables and type mismatches are located errors (`vouch mav lint`).
//!
//! This file holds the compiler's state and the declarations (constants, roles, keys, strict
//! rules, replies); statements become states in [`flow`](super::flow), expressions and
//! predicates are typed in [`typing`](super::typing).

use super::ast::{self, BinOp, ExprKind, Stmt, UnOp};
use super::compile::{CResult, Compiler, Scope, loc_of, ty_of_loc};
use super::error::ErrorKind;
use super::ir::*;
use crate::dialect::MsgIndex;
use crate::side::Side;

impl<'a> Compiler<'a> {
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
                    ErrorKind::Duplicate,
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
                ErrorKind::Duplicate,
                c.name.span,
                format!("constant `{}` is defined twice", c.name.name),
            );
        }
        let value = self.const_value(&c.value)?;
        self.set.consts.push(ConstIR { name: c.name.name.clone(), value });
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
                    return self.err(
                        ErrorKind::UnknownName,
                        e.span,
                        format!("`{n}` is not a constant or enum entry"),
                    );
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
                    _ => return self.err(ErrorKind::Type, e.span, "a constant must be a number"),
                }
            }
            _ => return self.err(ErrorKind::Type, e.span, "a constant must be a number"),
        })
    }

    #[expect(
        clippy::expect_used,
        reason = "`protocol` sets `self.proto` before compiling a body and takes it back at the end"
    )]
    fn protocol(&mut self, p: &ast::ProtocolDecl) -> CResult<Protocol> {
        if p.roles.len() != 2 {
            return self.err(
                ErrorKind::Structure,
                p.name.span,
                "a protocol declares exactly two roles: `roles gcs, uav;`",
            );
        }
        let mut roles = vec![];
        for r in &p.roles {
            let kind = match r.name.as_str() {
                "gcs" | "ground" => Side::Gcs,
                "uav" | "vehicle" | "autopilot" => Side::Vehicle,
                _ => return self.err(ErrorKind::UnknownName, r.span, format!("unknown role `{}`", r.name)).map_err(|e| {
                    e.with_help("roles are `gcs` (ground station) and `uav` (vehicle; also `vehicle`, `autopilot`)")
                }),
            };
            roles.push((r.name.clone(), kind));
        }
        if roles[0].1 == roles[1].1 {
            return self.err(
                ErrorKind::Structure,
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
            replies: vec![],
            unverifiable: self.unverifiable_policy(p)?,
            states: vec![],
            recs: vec![],
            var_names: vec![],
            alphabet: vec![],
        });
        match p.body.first() {
            Some(Stmt::Step { .. }) | Some(Stmt::Choice { .. }) => {}
            Some(_) => {
                return self.err(
                    ErrorKind::Structure,
                    p.name.span,
                    "a protocol must start with a message step or a choice",
                );
            }
            None => {
                return self.err(
                    ErrorKind::Structure,
                    p.name.span,
                    "empty protocol: it needs at least one message step",
                );
            }
        }
        let mut scope = Scope::default();
        self.state_for(&p.body, &mut scope)?;
        for s in &p.strict {
            let from = self.role(&s.from)?;
            let to = self.role(&s.to)?;
            if from == to {
                return self.err(
                    ErrorKind::Structure,
                    s.to.span,
                    "sender and receiver must differ",
                );
            }
            let msgs = self.messages(&s.labels)?;
            let text = format!(
                "{} -> {} : {}",
                s.from.name,
                s.to.name,
                s.labels.iter().map(|l| l.name.as_str()).collect::<Vec<_>>().join(" | ")
            );
            let answer = !self.proto_mut().states[0].transitions.iter().any(|t| t.from == from);
            self.proto_mut().strict.push(StrictIR { from, msgs, text, answer });
        }
        let mut proto = self.proto.take().expect("protocol under construction");
        let mut alphabet: Vec<MsgIndex> = proto
            .states
            .iter()
            .flat_map(|s| s.transitions.iter().flat_map(|t| t.msgs.iter().map(|m| m.msg)))
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
                    ErrorKind::UnknownName,
                    k.span,
                    format!("key `{}` is a field of none of the protocol's messages", k.name),
                );
            }
            proto.keys.push(KeyIR { name: k.name.clone(), locs });
        }
        proto.alphabet = alphabet;
        self.proto = Some(proto);
        for r in &p.replies {
            let reply = self.reply(r)?;
            if self.proto_mut().replies.iter().any(|q| q.to == reply.to && q.by == reply.by) {
                return self.err(
                    ErrorKind::Duplicate,
                    r.to.span,
                    format!("a second violation reply to `{}`", r.to.name),
                );
            }
            self.proto_mut().replies.push(reply);
        }
        Ok(self.proto.take().expect("protocol under construction"))
    }

    fn unverifiable_policy(&self, p: &ast::ProtocolDecl) -> CResult<UnverifiablePolicy> {
        match &p.unverifiable {
            None => Ok(UnverifiablePolicy::Drop),
            Some((policy, _)) => match policy.name.as_str() {
                "pass" => Ok(UnverifiablePolicy::Pass),
                "drop" => Ok(UnverifiablePolicy::Drop),
                other => self.err(
                    ErrorKind::Syntax,
                    policy.span,
                    format!("unverifiable frames can `pass` or `drop`, not `{other}`"),
                ),
            },
        }
    }

    #[expect(
        clippy::expect_used,
        reason = "`protocol` sets `self.proto` before compiling a body and takes it back at the end"
    )]
    pub(super) fn proto_mut(&mut self) -> &mut Protocol {
        self.proto.as_mut().expect("protocol under construction")
    }

    #[expect(
        clippy::expect_used,
        reason = "`protocol` sets `self.proto` before compiling a body and takes it back at the end"
    )]
    pub(super) fn role(&self, r: &ast::Ident) -> CResult<usize> {
        let proto = self.proto.as_ref().expect("protocol under construction");
        match proto.roles.iter().position(|(n, _)| *n == r.name) {
            Some(i) => Ok(i),
            None => self.err(
                ErrorKind::UnknownName,
                r.span,
                format!("`{}` is not a role of this protocol", r.name),
            ),
        }
    }

    pub(super) fn messages(&self, labels: &[ast::Ident]) -> CResult<Vec<MsgIndex>> {
        labels
            .iter()
            .map(|l| match self.dialect.index_of_name(&l.name) {
                Some(i) => Ok(i),
                None => self.err(
                    ErrorKind::UnknownName,
                    l.span,
                    format!("unknown message `{}` in dialect {}", l.name, self.dialect.name),
                ),
            })
            .collect()
    }

    fn reply(&mut self, r: &ast::ReplyDecl) -> CResult<ReplyIR> {
        let by = r.by.as_ref().map(|b| self.role(b)).transpose()?;
        let to = self.role(&r.to)?;
        let msg = self.messages(std::slice::from_ref(&r.message))?[0];
        let def = self.dialect.message(msg);
        let mut fields = vec![];
        self.in_reply = true;
        for (f, e) in &r.fields {
            let Some(loc) = loc_of(def, &f.name) else {
                self.in_reply = false;
                return self.err(
                    ErrorKind::UnknownName,
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
        Ok(ReplyIR { by, to, msg, fields })
    }
}
