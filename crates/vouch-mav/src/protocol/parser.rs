//! Recursive-descent parser of the protocol language (grammar in docs/mav-monitor.md):
//! declarations and statements here, expressions in `parse_expr.rs`.

use super::ast::*;
use super::error::{ErrorKind, ProtocolError, Span};
use super::lexer::{Tok, Token, lex};

pub fn parse(src: &str) -> Result<FileAst, ProtocolError> {
    let toks = lex(src)?;
    let mut p = Parser { src, toks, i: 0 };
    p.file()
}

pub(super) struct Parser<'s> {
    pub(super) src: &'s str,
    pub(super) toks: Vec<Token>,
    pub(super) i: usize,
}

pub(super) type PResult<T> = Result<T, ProtocolError>;

impl<'s> Parser<'s> {
    pub(super) fn peek(&self) -> &Tok {
        &self.toks[self.i].tok
    }

    pub(super) fn peek_at(&self, n: usize) -> &Tok {
        &self.toks[(self.i + n).min(self.toks.len() - 1)].tok
    }

    pub(super) fn span(&self) -> Span {
        self.toks[self.i].span
    }

    pub(super) fn prev_span(&self) -> Span {
        self.toks[self.i.saturating_sub(1)].span
    }

    pub(super) fn bump(&mut self) -> Token {
        let t = self.toks[self.i].clone();
        if self.i + 1 < self.toks.len() {
            self.i += 1;
        }
        t
    }

    pub(super) fn err<T>(&self, msg: impl Into<String>) -> PResult<T> {
        Err(ProtocolError::at(ErrorKind::Syntax, self.src, self.span(), msg))
    }

    pub(super) fn describe(&self) -> String {
        match self.peek() {
            Tok::Ident(s) => format!("`{s}`"),
            Tok::Num(n) => format!("number {n}"),
            Tok::Str(s) => format!("string \"{s}\""),
            Tok::Sym(s) => format!("`{s}`"),
            Tok::Eof => "end of file".into(),
        }
    }

    pub(super) fn is_sym(&self, s: &str) -> bool {
        matches!(self.peek(), Tok::Sym(x) if *x == s)
    }

    pub(super) fn is_kw(&self, k: &str) -> bool {
        matches!(self.peek(), Tok::Ident(x) if x == k)
    }

    pub(super) fn eat_sym(&mut self, s: &str) -> bool {
        if self.is_sym(s) {
            self.bump();
            true
        } else {
            false
        }
    }

    pub(super) fn eat_kw(&mut self, k: &str) -> bool {
        if self.is_kw(k) {
            self.bump();
            true
        } else {
            false
        }
    }

    pub(super) fn expect_sym(&mut self, s: &str) -> PResult<Span> {
        if self.is_sym(s) {
            Ok(self.bump().span)
        } else {
            self.err(format!("expected `{s}`, found {}", self.describe()))
        }
    }

    pub(super) fn expect_kw(&mut self, k: &str) -> PResult<Span> {
        if self.is_kw(k) {
            Ok(self.bump().span)
        } else {
            self.err(format!("expected `{k}`, found {}", self.describe()))
        }
    }

    pub(super) fn ident(&mut self, what: &str) -> PResult<Ident> {
        match self.peek().clone() {
            Tok::Ident(name) => {
                let span = self.bump().span;
                Ok(Ident { name, span })
            }
            _ => self.err(format!("expected {what}, found {}", self.describe())),
        }
    }

    fn file(&mut self) -> PResult<FileAst> {
        let mut f = FileAst::default();
        loop {
            if matches!(self.peek(), Tok::Eof) {
                return Ok(f);
            }
            if self.is_kw("const") {
                f.consts.push(self.const_decl()?);
            } else if self.is_kw("protocol") {
                f.protocols.push(self.protocol()?);
            } else if self.is_kw("effect") {
                f.effects.push(self.effect()?);
            } else {
                return self.err(format!(
                    "expected `protocol`, `effect` or `const`, found {}",
                    self.describe()
                ));
            }
        }
    }

    fn const_decl(&mut self) -> PResult<ConstDecl> {
        self.expect_kw("const")?;
        let name = self.ident("constant name")?;
        self.expect_sym("=")?;
        let value = self.expr()?;
        self.expect_sym(";")?;
        Ok(ConstDecl { name, value })
    }

    fn protocol(&mut self) -> PResult<ProtocolDecl> {
        let start = self.expect_kw("protocol")?;
        let name = self.ident("protocol name")?;
        self.expect_sym("{")?;
        let mut d = ProtocolDecl {
            name,
            roles: vec![],
            keys: vec![],
            timeout_ms: None,
            strict: vec![],
            replies: vec![],
            unverifiable: None,
            consts: vec![],
            guards: vec![],
            body: vec![],
            span: start,
        };
        // Header clauses come first, in any order.
        while self.header_clause(&mut d)? {}
        d.body = self.stmts()?;
        let end = self.expect_sym("}")?;
        d.span = d.span.to(end);
        Ok(d)
    }

    /// One header clause of a protocol into `d`; `false` when the next token starts no clause.
    fn header_clause(&mut self, d: &mut ProtocolDecl) -> PResult<bool> {
        if self.eat_kw("roles") {
            d.roles = self.ident_list("role name")?;
        } else if self.eat_kw("key") {
            d.keys = self.ident_list("field name")?;
        } else if self.is_kw("timeout") {
            d.timeout_ms = Some(self.timeout()?);
        } else if self.eat_kw("strict") {
            let from = self.ident("role")?;
            self.expect_sym("->")?;
            let to = self.ident("role")?;
            self.expect_sym(":")?;
            let labels = self.labels()?;
            d.strict.push(StrictDecl { from, to, labels });
        } else if self.is_kw("on") {
            d.replies.push(self.reply_decl()?);
            return Ok(true);
        } else if self.is_kw("unverifiable") {
            let sp = self.bump().span;
            let policy = self.ident("`pass` or `drop`")?;
            d.unverifiable = Some((policy, sp));
        } else if self.is_kw("const") {
            d.consts.push(self.const_decl()?);
            return Ok(true);
        } else if self.is_kw("guard") {
            d.guards.push(self.guard_decl()?);
        } else {
            return Ok(false);
        }
        self.expect_sym(";")?;
        Ok(true)
    }

    /// `timeout N (s|ms)` (without the `;`), in milliseconds with its span.
    fn timeout(&mut self) -> PResult<(u64, Span)> {
        self.expect_kw("timeout")?;
        let sp = self.span();
        let n = match self.peek().clone() {
            Tok::Num(n) if n >= 0.0 => {
                self.bump();
                n
            }
            _ => return self.err("expected a duration such as `8 s` or `500 ms`"),
        };
        let unit = self.ident("time unit `s` or `ms`")?;
        let ms = match unit.name.as_str() {
            "s" => n * 1000.0,
            "ms" => n,
            _ => {
                return Err(ProtocolError::at(
                    ErrorKind::Syntax,
                    self.src,
                    unit.span,
                    "time unit must be `s` or `ms`",
                ));
            }
        };
        Ok((ms as u64, sp.to(unit.span)))
    }

    /// `on violation [by ROLE] reply ROLE : MSG(f = e, …), MSG(…);`
    fn reply_decl(&mut self) -> PResult<ReplyDecl> {
        self.expect_kw("on")?;
        self.expect_kw("violation")?;
        let by = if self.eat_kw("by") { Some(self.ident("role")?) } else { None };
        self.expect_kw("reply")?;
        let to = self.ident("role")?;
        self.expect_sym(":")?;
        let mut messages = vec![];
        loop {
            let message = self.ident("message name")?;
            self.expect_sym("(")?;
            let mut fields = vec![];
            if !self.is_sym(")") {
                loop {
                    let f = self.ident("field name")?;
                    self.expect_sym("=")?;
                    fields.push((f, self.expr()?));
                    if !self.eat_sym(",") {
                        break;
                    }
                }
            }
            self.expect_sym(")")?;
            messages.push(ReplyMessage { message, fields });
            if !self.eat_sym(",") {
                break;
            }
        }
        self.expect_sym(";")?;
        Ok(ReplyDecl { by, to, messages })
    }

    /// `guard EFFECT by ROUTE, … (where EXPR | refuse)` (without the `;`).
    fn guard_decl(&mut self) -> PResult<GuardDecl> {
        let start = self.expect_kw("guard")?;
        let effect = self.ident("effect name")?;
        self.expect_kw("by")?;
        let routes = self.ident_list("route (`command`, `mission` or `rc`)")?;
        let where_ = if self.eat_kw("where") {
            Some(self.expr()?)
        } else if self.eat_kw("refuse") {
            None
        } else {
            return self
                .err(format!("expected `where CONDITION` or `refuse`, found {}", self.describe()));
        };
        Ok(GuardDecl { effect, routes, where_, span: start.to(self.prev_span()) })
    }

    /// `effect NAME { (command … | servo … | relay … | rc …)* }`
    fn effect(&mut self) -> PResult<EffectDecl> {
        let start = self.expect_kw("effect")?;
        let name = self.ident("effect name")?;
        self.expect_sym("{")?;
        let mut d = EffectDecl { name, commands: vec![], outputs: vec![], span: start };
        while !self.is_sym("}") {
            let sp = self.span();
            if self.eat_kw("command") {
                let command = self.ident("MAV_CMD entry")?;
                let when = if self.eat_kw("when") { Some(self.expr()?) } else { None };
                d.commands.push(EffectCommand { command, when, span: sp.to(self.prev_span()) });
            } else {
                d.outputs.push(self.effect_output()?);
            }
            self.expect_sym(";")?;
        }
        let end = self.expect_sym("}")?;
        d.span = d.span.to(end);
        Ok(d)
    }

    /// `servo N when EXPR [driven when EXPR]`, `relay …`, `rc N in A..B when …`.
    fn effect_output(&mut self) -> PResult<EffectOutput> {
        let sp = self.span();
        let kind = match self.peek() {
            Tok::Ident(k) if k == "servo" => OutputKind::Servo,
            Tok::Ident(k) if k == "relay" => OutputKind::Relay,
            Tok::Ident(k) if k == "rc" => OutputKind::Rc,
            _ => {
                return self.err(format!(
                    "expected `command`, `servo`, `relay` or `rc`, found {}",
                    self.describe()
                ));
            }
        };
        self.bump();
        let var = self.ident("name of the output number")?;
        let range = if kind == OutputKind::Rc {
            self.expect_kw("in")?;
            let lo = self.whole_number("first channel")?;
            self.expect_sym("..")?;
            let hi = self.whole_number("last channel")?;
            Some((lo, hi))
        } else {
            None
        };
        self.expect_kw("when")?;
        let when = self.expr()?;
        let driven = if self.eat_kw("driven") {
            self.expect_kw("when")?;
            Some(self.expr()?)
        } else {
            None
        };
        Ok(EffectOutput { kind, var, range, when, driven, span: sp.to(self.prev_span()) })
    }

    fn whole_number(&mut self, what: &str) -> PResult<u32> {
        match self.peek().clone() {
            Tok::Num(n) if n.fract() == 0.0 && (0.0..=255.0).contains(&n) => {
                self.bump();
                Ok(n as u32)
            }
            _ => self.err(format!(
                "expected {what} (a whole number up to 255), found {}",
                self.describe()
            )),
        }
    }

    fn ident_list(&mut self, what: &str) -> PResult<Vec<Ident>> {
        let mut v = vec![self.ident(what)?];
        while self.eat_sym(",") {
            v.push(self.ident(what)?);
        }
        Ok(v)
    }

    fn labels(&mut self) -> PResult<Vec<Ident>> {
        let mut v = vec![self.ident("message name")?];
        while self.eat_sym("|") {
            v.push(self.ident("message name")?);
        }
        Ok(v)
    }

    /// Statements up to a closing `}` (not consumed).
    fn stmts(&mut self) -> PResult<Vec<Stmt>> {
        let mut out = vec![];
        while !self.is_sym("}") && !matches!(self.peek(), Tok::Eof) {
            out.push(self.stmt()?);
        }
        Ok(out)
    }

    fn block(&mut self) -> PResult<Vec<Stmt>> {
        self.expect_sym("{")?;
        let s = self.stmts()?;
        self.expect_sym("}")?;
        Ok(s)
    }

    fn stmt(&mut self) -> PResult<Stmt> {
        if self.is_kw("end") {
            let sp = self.bump().span;
            self.expect_sym(";")?;
            return Ok(Stmt::End(sp));
        }
        if self.is_kw("continue") {
            let sp = self.bump().span;
            let name = self.ident("recursion variable")?;
            let assigns = self.assigns()?;
            self.expect_sym(";")?;
            return Ok(Stmt::Continue { name, assigns, span: sp.to(self.prev_span()) });
        }
        if self.is_kw("rec") {
            self.bump();
            let name = self.ident("recursion variable")?;
            self.expect_sym("(")?;
            let mut vars = vec![];
            if !self.is_sym(")") {
                loop {
                    let n = self.ident("variable name")?;
                    let ty = if self.eat_sym(":") { Some(self.type_name()?) } else { None };
                    self.expect_sym("=")?;
                    vars.push(VarDecl { name: n, ty, init: self.expr()? });
                    if !self.eat_sym(",") {
                        break;
                    }
                }
            }
            self.expect_sym(")")?;
            let invariant = if self.eat_kw("where") { Some(self.expr()?) } else { None };
            let body = self.block()?;
            return Ok(Stmt::Rec { name, vars, invariant, body });
        }
        if self.is_kw("choice") {
            let sp = self.bump().span;
            self.expect_sym("{")?;
            let mut branches = vec![];
            let mut complete_when = None;
            while !self.is_sym("}") {
                if self.is_kw("complete") {
                    self.bump();
                    self.expect_kw("when")?;
                    complete_when = Some(self.expr()?);
                    self.expect_sym(";")?;
                    continue;
                }
                let label = self.ident("branch label")?;
                self.expect_sym(":")?;
                let head = self.step_head()?;
                let body = self.block()?;
                branches.push(Branch { label, head, body });
            }
            let end = self.expect_sym("}")?;
            if branches.is_empty() {
                return Err(ProtocolError::at(
                    ErrorKind::Syntax,
                    self.src,
                    sp,
                    "a choice needs at least one branch",
                ));
            }
            return Ok(Stmt::Choice { branches, complete_when, span: sp.to(end) });
        }
        if matches!(self.peek(), Tok::Ident(_)) && matches!(self.peek_at(1), Tok::Sym("->")) {
            let head = self.step_head()?;
            if self.is_sym("{") {
                let block = self.block()?;
                return Ok(Stmt::Step { head, block: Some(block) });
            }
            self.expect_sym(";")?;
            return Ok(Stmt::Step { head, block: None });
        }
        self.err(format!(
            "expected a step `A -> B : MSG`, `choice`, `rec`, `continue` or `end`, found {}",
            self.describe()
        ))
    }

    fn type_name(&mut self) -> PResult<TypeName> {
        let t = self.ident("type (int, float, bool, str)")?;
        Ok(match t.name.as_str() {
            "int" => TypeName::Int,
            "float" => TypeName::Float,
            "bool" => TypeName::Bool,
            "str" => TypeName::Str,
            _ => {
                return Err(ProtocolError::at(
                    ErrorKind::Syntax,
                    self.src,
                    t.span,
                    "unknown type: expected int, float, bool or str",
                ));
            }
        })
    }

    fn assigns(&mut self) -> PResult<Vec<(Ident, Expr)>> {
        self.expect_sym("(")?;
        let mut v = vec![];
        if !self.is_sym(")") {
            loop {
                let n = self.ident("variable name")?;
                self.expect_sym("=")?;
                v.push((n, self.expr()?));
                if !self.eat_sym(",") {
                    break;
                }
            }
        }
        self.expect_sym(")")?;
        Ok(v)
    }

    fn step_head(&mut self) -> PResult<StepHead> {
        let from = self.ident("sender role")?;
        self.expect_sym("->")?;
        let to = self.ident("receiver role")?;
        self.expect_sym(":")?;
        let labels = self.labels()?;
        let mut binds = vec![];
        if self.eat_sym("(") {
            if !self.is_sym(")") {
                loop {
                    let v = self.ident("variable name")?;
                    self.expect_sym("=")?;
                    let f = self.ident("field name")?;
                    binds.push((v, f));
                    if !self.eat_sym(",") {
                        break;
                    }
                }
            }
            self.expect_sym(")")?;
        }
        let when = if self.eat_kw("when") { Some(self.expr()?) } else { None };
        let where_ = if self.eat_kw("where") { Some(self.expr()?) } else { None };
        let span = from.span.to(self.prev_span());
        Ok(StepHead { from, to, labels, binds, when, where_, span })
    }
}
