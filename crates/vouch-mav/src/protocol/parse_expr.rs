//! Expressions of the protocol language (part of the parser, see `parser`), loosest first:
//! `||`, `&&`, comparisons (not chained), `+ -`, `* /`, unary `! -`, atoms — interpolated texts
//! (`"SERVO{n}_FUNCTION"`) included.

use super::ast::*;
use super::error::{ErrorKind, ProtocolError, Span};
use super::lexer::{Tok, lex_range};
use super::parser::{PResult, Parser};

impl Parser<'_> {
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
