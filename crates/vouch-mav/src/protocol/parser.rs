//! Recursive-descent parser of the protocol language (grammar in docs/mav-monitor.md).

use super::ast::*;
use super::error::{ErrorKind, ProtocolError, Span};
use super::lexer::{Tok, Token, lex, lex_range};

pub fn parse(src: &str) -> Result<FileAst, ProtocolError> {
    let toks = lex(src)?;
    let mut p = Parser { src, toks, i: 0 };
    p.file()
}

struct Parser<'s> {
    src: &'s str,
    toks: Vec<Token>,
    i: usize,
}

type PResult<T> = Result<T, ProtocolError>;

impl<'s> Parser<'s> {
    fn peek(&self) -> &Tok {
        &self.toks[self.i].tok
    }

    fn peek_at(&self, n: usize) -> &Tok {
        &self.toks[(self.i + n).min(self.toks.len() - 1)].tok
    }

    fn span(&self) -> Span {
        self.toks[self.i].span
    }

    fn prev_span(&self) -> Span {
        self.toks[self.i.saturating_sub(1)].span
    }

    fn bump(&mut self) -> Token {
        let t = self.toks[self.i].clone();
        if self.i + 1 < self.toks.len() {
            self.i += 1;
        }
        t
    }

    fn err<T>(&self, msg: impl Into<String>) -> PResult<T> {
        Err(ProtocolError::at(ErrorKind::Syntax, self.src, self.span(), msg))
    }

    fn describe(&self) -> String {
        match self.peek() {
            Tok::Ident(s) => format!("`{s}`"),
            Tok::Num(n) => format!("number {n}"),
            Tok::Str(s) => format!("string \"{s}\""),
            Tok::Sym(s) => format!("`{s}`"),
            Tok::Eof => "end of file".into(),
        }
    }

    fn is_sym(&self, s: &str) -> bool {
        matches!(self.peek(), Tok::Sym(x) if *x == s)
    }

    fn is_kw(&self, k: &str) -> bool {
        matches!(self.peek(), Tok::Ident(x) if x == k)
    }

    fn eat_sym(&mut self, s: &str) -> bool {
        if self.is_sym(s) {
            self.bump();
            true
        } else {
            false
        }
    }

    fn eat_kw(&mut self, k: &str) -> bool {
        if self.is_kw(k) {
            self.bump();
            true
        } else {
            false
        }
    }

    fn expect_sym(&mut self, s: &str) -> PResult<Span> {
        if self.is_sym(s) {
            Ok(self.bump().span)
        } else {
            self.err(format!("expected `{s}`, found {}", self.describe()))
        }
    }

    fn expect_kw(&mut self, k: &str) -> PResult<Span> {
        if self.is_kw(k) {
            Ok(self.bump().span)
        } else {
            self.err(format!("expected `{k}`, found {}", self.describe()))
        }
    }

    fn ident(&mut self, what: &str) -> PResult<Ident> {
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

    // Expressions, loosest first: || && comparison additive multiplicative unary atom.
    pub fn expr(&mut self) -> PResult<Expr> {
        self.binary_level(0)
    }

    fn binary_level(&mut self, level: usize) -> PResult<Expr> {
        const LEVELS: &[&[(&str, BinOp)]] = &[
            &[("||", BinOp::Or)],
            &[("&&", BinOp::And)],
            &[
                ("==", BinOp::Eq),
                ("!=", BinOp::Ne),
                ("<=", BinOp::Le),
                (">=", BinOp::Ge),
                ("<", BinOp::Lt),
                (">", BinOp::Gt),
            ],
            &[("+", BinOp::Add), ("-", BinOp::Sub)],
            &[("*", BinOp::Mul), ("/", BinOp::Div)],
        ];
        if level == LEVELS.len() {
            return self.unary();
        }
        let mut lhs = self.binary_level(level + 1)?;
        loop {
            let op = LEVELS[level].iter().find(|(s, _)| self.is_sym(s)).map(|(_, op)| *op);
            let Some(op) = op else { return Ok(lhs) };
            self.bump();
            let rhs = self.binary_level(level + 1)?;
            // Comparisons do not chain: `a < b < c` is almost always a mistake.
            if level == 2 && LEVELS[2].iter().any(|(s, _)| self.is_sym(s)) {
                return self.err("comparisons cannot be chained; use `&&`");
            }
            let span = lhs.span.to(rhs.span);
            lhs = Expr { kind: ExprKind::Binary(op, Box::new(lhs), Box::new(rhs)), span };
        }
    }

    /// The text of the string token at `sp` with its `{EXPR}` parts parsed.
    fn interpolated(&mut self, sp: Span) -> PResult<Expr> {
        let (first, end) = (sp.start + 1, sp.start + sp.len - 1);
        let text = &self.src[first..end];
        let mut parts = vec![];
        let mut lit = String::new();
        let mut i = 0;
        while i < text.len() {
            let c = text.as_bytes()[i];
            if c == b'}' {
                return Err(ProtocolError::at(
                    ErrorKind::Syntax,
                    self.src,
                    Span::new(first + i, 1),
                    "`}` without `{` in a text",
                ));
            }
            if c != b'{' {
                let ch = text[i..].chars().next().unwrap_or('?');
                lit.push(ch);
                i += ch.len_utf8();
                continue;
            }
            let Some(close) = text[i..].find('}').map(|k| i + k) else {
                return Err(ProtocolError::at(
                    ErrorKind::Syntax,
                    self.src,
                    Span::new(first + i, 1),
                    "`{` without `}` in a text",
                ));
            };
            if !lit.is_empty() {
                parts.push(InterpPart::Text(std::mem::take(&mut lit)));
            }
            let toks = lex_range(self.src, first + i + 1, first + close)?;
            let mut sub = Parser { src: self.src, toks, i: 0 };
            let e = sub.expr()?;
            if !matches!(sub.peek(), Tok::Eof) {
                return sub.err(format!("expected `}}`, found {}", sub.describe()));
            }
            parts.push(InterpPart::Expr(e));
            i = close + 1;
        }
        if !lit.is_empty() {
            parts.push(InterpPart::Text(lit));
        }
        Ok(Expr { kind: ExprKind::Interp(parts), span: sp })
    }

    fn unary(&mut self) -> PResult<Expr> {
        let sp = self.span();
        if self.eat_sym("!") {
            let e = self.unary()?;
            let span = sp.to(e.span);
            return Ok(Expr { kind: ExprKind::Unary(UnOp::Not, Box::new(e)), span });
        }
        if self.eat_sym("-") {
            let e = self.unary()?;
            let span = sp.to(e.span);
            return Ok(Expr { kind: ExprKind::Unary(UnOp::Neg, Box::new(e)), span });
        }
        self.atom()
    }

    fn atom(&mut self) -> PResult<Expr> {
        let sp = self.span();
        match self.peek().clone() {
            Tok::Num(n) => {
                self.bump();
                Ok(Expr { kind: ExprKind::Num(n), span: sp })
            }
            Tok::Str(s) => {
                self.bump();
                if s.contains('{') || s.contains('}') {
                    return self.interpolated(sp);
                }
                Ok(Expr { kind: ExprKind::Str(s), span: sp })
            }
            Tok::Sym("(") => {
                self.bump();
                let e = self.expr()?;
                self.expect_sym(")")?;
                Ok(e)
            }
            Tok::Ident(name) => {
                self.bump();
                match name.as_str() {
                    "true" => return Ok(Expr { kind: ExprKind::Bool(true), span: sp }),
                    "false" => return Ok(Expr { kind: ExprKind::Bool(false), span: sp }),
                    "param" if self.is_sym("[") => {
                        self.bump();
                        let e = self.expr()?;
                        let end = self.expect_sym("]")?;
                        return Ok(Expr { kind: ExprKind::ParamOf(Box::new(e)), span: sp.to(end) });
                    }
                    _ if self.is_sym("(") => {
                        self.bump();
                        let arg = self.expr()?;
                        let end = self.expect_sym(")")?;
                        let f = Ident { name, span: sp };
                        return Ok(Expr {
                            kind: ExprKind::Call(f, Box::new(arg)),
                            span: sp.to(end),
                        });
                    }
                    "vehicle" | "param" if self.is_sym(".") => {
                        self.bump();
                        let member = self.ident(if name == "vehicle" {
                            "vehicle attribute"
                        } else {
                            "parameter name"
                        })?;
                        let span = sp.to(member.span);
                        let kind = if name == "vehicle" {
                            ExprKind::Vehicle(member)
                        } else {
                            ExprKind::Param(member)
                        };
                        return Ok(Expr { kind, span });
                    }
                    _ => {}
                }
                Ok(Expr { kind: ExprKind::Name(name), span: sp })
            }
            _ => self.err(format!("expected an expression, found {}", self.describe())),
        }
    }
}
