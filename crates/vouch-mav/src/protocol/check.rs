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
        for e in &file.effects {
            self.effect_decl(e)?;
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

    fn protocol(&mut self, p: &ast::ProtocolDecl) -> CResult<Protocol> {
        let roles = self.roles(p)?;
        self.keys = p.keys.iter().map(|k| k.name.clone()).collect();
        self.proto = Protocol {
            name: p.name.name.clone(),
            roles,
            timeout_us: Some(p.timeout_ms.map(|(ms, _)| ms).unwrap_or(30_000) * 1000),
            unverifiable: self.unverifiable_policy(p)?,
            ..Protocol::default()
        };
        if p.guards.is_empty() {
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
                        "empty protocol: it needs at least one message step or a `guard`",
                    );
                }
            }
            let mut scope = Scope::default();
            self.state_for(&p.body, &mut scope)?;
        } else {
            if let Some(s) = p.body.first() {
                return self.err(
                    ErrorKind::Structure,
                    super::flow::stmt_span(s),
                    "a protocol with `guard` has no steps of its own: put them in another protocol",
                );
            }
            self.proto.states.push(State::default());
            for g in &p.guards {
                self.guard(g)?;
            }
        }
        for s in &p.strict {
            self.strict(s)?;
        }
        self.alphabet_and_keys(p)?;
        for r in &p.replies {
            self.reply_decl(r)?;
        }
        Ok(std::mem::take(&mut self.proto))
    }

    /// The two roles: a ground station and a vehicle.
    fn roles(&self, p: &ast::ProtocolDecl) -> CResult<Vec<(String, Side)>> {
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
                _ => {
                    return self
                        .err(ErrorKind::UnknownName, r.span, format!("unknown role `{}`", r.name))
                        .map_err(|e| {
                            e.with_help(
                                "roles are `gcs` (ground station) and `uav` (vehicle; also \
                                 `vehicle`, `autopilot`)",
                            )
                        });
                }
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
        Ok(roles)
    }

    fn strict(&mut self, s: &ast::StrictDecl) -> CResult<()> {
        let from = self.role(&s.from)?;
        let to = self.role(&s.to)?;
        if from == to {
            return self.err(ErrorKind::Structure, s.to.span, "sender and receiver must differ");
        }
        let msgs = self.messages(&s.labels)?;
        let text = format!(
            "{} -> {} : {}",
            s.from.name,
            s.to.name,
            s.labels.iter().map(|l| l.name.as_str()).collect::<Vec<_>>().join(" | ")
        );
        let answer = !self.proto.states[0].transitions.iter().any(|t| t.from == from);
        self.proto.strict.push(StrictIR { from, msgs, text, answer });
        Ok(())
    }

    /// Every message the protocol mentions, and where its keys are in each of them.
    fn alphabet_and_keys(&mut self, p: &ast::ProtocolDecl) -> CResult<()> {
        let proto = &self.proto;
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
            self.proto.keys.push(KeyIR { name: k.name.clone(), locs });
        }
        self.proto.alphabet = alphabet;
        Ok(())
    }

    /// `on violation [by ROLE] reply ROLE : MSG(…), …;` (one declaration per addressed role).
    fn reply_decl(&mut self, r: &ast::ReplyDecl) -> CResult<()> {
        let by = r.by.as_ref().map(|b| self.role(b)).transpose()?;
        let to = self.role(&r.to)?;
        if self.proto.replies.iter().any(|q| q.to == to && q.by == by) {
            return self.err(
                ErrorKind::Duplicate,
                r.to.span,
                format!("a second violation reply to `{}`", r.to.name),
            );
        }
        for m in &r.messages {
            let reply = self.reply(by, to, m)?;
            self.proto.replies.push(reply);
        }
        Ok(())
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

    pub(super) fn role(&self, r: &ast::Ident) -> CResult<usize> {
        match self.proto.roles.iter().position(|(n, _)| *n == r.name) {
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

    fn reply(&mut self, by: Option<usize>, to: usize, m: &ast::ReplyMessage) -> CResult<ReplyIR> {
        let msg = self.messages(std::slice::from_ref(&m.message))?[0];
        let def = self.dialect.message(msg);
        let mut fields = vec![];
        for (f, e) in &m.fields {
            let Some(loc) = loc_of(def, &f.name) else {
                return self.err(
                    ErrorKind::UnknownName,
                    f.span,
                    format!("message {} has no field `{}`", def.name, f.name),
                );
            };
            let (mut scope, mut shows) = (Scope::default(), vec![]);
            self.in_reply = true;
            let compiled = self.expr(e, &mut scope, None, &mut shows);
            self.in_reply = false;
            let (x, ty) = compiled?;
            self.expect_compatible(&ty_of_loc(&loc), &ty, e.span)?;
            fields.push((f.name.clone(), x));
        }
        Ok(ReplyIR { by, to, msg, fields })
    }
}
