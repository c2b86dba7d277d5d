//! Parser reproducing upstream's yacc grammar: binary operators on four left-associative
//! levels (`&& ||` < `== > < >= <=` < `+ -` < `* / % **`), prefix `!` looser than unary `-`,
//! postfix `->field` tightest; primaries are numbers, identifiers, `a.b`, `f(args)`, `a[e]` and
//! parenthesised expressions. The whole text must be one expression (trailing tokens are an
//! error, as with upstream's end-of-input token).

use super::error::{ExprError, ExprErrorKind};
use super::lexer::{Token, TokenKind, lex};
use super::{BinOp, Expr, UnOp};

/// Parses one expression.
pub fn parse(text: &str) -> Result<Expr, ExprError> {
    let tokens = lex(text)?;
    let mut p = Parser { toks: &tokens, pos: 0, text };
    let e = p.expr(1)?;
    if p.pos < tokens.len() {
        return Err(p.unexpected());
    }
    Ok(e)
}

/// Nesting limit: keeps hostile inputs (fuzzing) from overflowing the stack.
const MAX_DEPTH: usize = 200;

struct Parser<'a> {
    toks: &'a [Token],
    pos: usize,
    text: &'a str,
}

fn binop(k: &TokenKind) -> Option<BinOp> {
    Some(match k {
        TokenKind::And => BinOp::And,
        TokenKind::Or => BinOp::Or,
        TokenKind::EqEq => BinOp::Eq,
        TokenKind::Gt => BinOp::Gt,
        TokenKind::Lt => BinOp::Lt,
        TokenKind::Ge => BinOp::Ge,
        TokenKind::Le => BinOp::Le,
        TokenKind::Plus => BinOp::Add,
        TokenKind::Minus => BinOp::Sub,
        TokenKind::Star => BinOp::Mul,
        TokenKind::Slash => BinOp::Div,
        TokenKind::Percent => BinOp::Mod,
        TokenKind::Pow => BinOp::Pow,
        _ => return None,
    })
}

impl<'a> Parser<'a> {
    fn peek(&self) -> Option<&'a TokenKind> {
        self.toks.get(self.pos).map(|t| &t.kind)
    }

    fn unexpected(&self) -> ExprError {
        match self.toks.get(self.pos) {
            Some(t) => ExprError {
                kind: ExprErrorKind::Parsing,
                message: format!("unexpected token '{}'", &self.text[t.start..t.end]),
                start: t.start,
                end: t.end,
            },
            None => ExprError {
                kind: ExprErrorKind::Parsing,
                message: if self.text.trim().is_empty() {
                    "empty expression".to_string()
                } else {
                    "unexpected end of expression".to_string()
                },
                start: self.text.len(),
                end: self.text.len(),
            },
        }
    }

    fn depth_error(&self) -> ExprError {
        let at = self.toks.get(self.pos).map(|t| t.start).unwrap_or(0);
        ExprError {
            kind: ExprErrorKind::Parsing,
            message: "expression nested too deeply".into(),
            start: at,
            end: at,
        }
    }

    fn expect(&mut self, k: TokenKind) -> Result<(), ExprError> {
        if self.peek() == Some(&k) {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.unexpected())
        }
    }

    fn ident(&mut self) -> Result<String, ExprError> {
        match self.peek() {
            Some(TokenKind::Ident(s)) => {
                self.pos += 1;
                Ok(s.clone())
            }
            _ => Err(self.unexpected()),
        }
    }

    /// Precedence climbing: parses operators of level >= `min`.
    fn expr(&mut self, min: u8) -> Result<Expr, ExprError> {
        self.expr_at(min, 0)
    }

    fn expr_at(&mut self, min: u8, depth: usize) -> Result<Expr, ExprError> {
        if depth > MAX_DEPTH {
            return Err(self.depth_error());
        }
        let mut lhs = self.unary(depth + 1)?;
        // Left-associative chains build depth without recursing here; count it too, since
        // printing, walking and dropping the tree recurse.
        let mut chain = 0;
        while let Some(op) = self.peek().and_then(binop) {
            if op.level() < min {
                break;
            }
            chain += 1;
            if depth + chain > MAX_DEPTH {
                return Err(self.depth_error());
            }
            self.pos += 1;
            let rhs = self.expr_at(op.level() + 1, depth + 1)?;
            lhs = Expr::Binary(op, Box::new(lhs), Box::new(rhs));
        }
        Ok(lhs)
    }

    fn unary(&mut self, depth: usize) -> Result<Expr, ExprError> {
        if depth > MAX_DEPTH {
            return Err(self.depth_error());
        }
        match self.peek() {
            Some(TokenKind::Minus) => {
                self.pos += 1;
                Ok(Expr::Unary(UnOp::Neg, Box::new(self.unary(depth + 1)?)))
            }
            Some(TokenKind::Not) => {
                self.pos += 1;
                Ok(Expr::Unary(UnOp::Not, Box::new(self.unary(depth + 1)?)))
            }
            _ => self.postfix(depth),
        }
    }

    fn postfix(&mut self, depth: usize) -> Result<Expr, ExprError> {
        let mut e = self.primary(depth)?;
        let mut chain = 0;
        while self.peek() == Some(&TokenKind::Deref) {
            chain += 1;
            if depth + chain > MAX_DEPTH {
                return Err(self.depth_error());
            }
            self.pos += 1;
            let f = self.ident()?;
            e = Expr::Deref(Box::new(e), f);
        }
        Ok(e)
    }

    fn primary(&mut self, depth: usize) -> Result<Expr, ExprError> {
        match self.peek() {
            Some(TokenKind::Int(v)) => {
                self.pos += 1;
                Ok(Expr::Int(*v))
            }
            Some(TokenKind::Float(v)) => {
                self.pos += 1;
                Ok(Expr::Float(*v))
            }
            Some(TokenKind::LParen) => {
                self.pos += 1;
                let e = self.expr_at(1, depth + 1)?;
                self.expect(TokenKind::RParen)?;
                Ok(e)
            }
            Some(TokenKind::Ident(name)) => {
                self.pos += 1;
                match self.peek() {
                    Some(TokenKind::Dot) => {
                        self.pos += 1;
                        let f = self.ident()?;
                        Ok(Expr::Field(name.clone(), f))
                    }
                    Some(TokenKind::LParen) => {
                        self.pos += 1;
                        let mut args = Vec::new();
                        if self.peek() != Some(&TokenKind::RParen) {
                            args.push(self.expr_at(1, depth + 1)?);
                            while self.peek() == Some(&TokenKind::Comma) {
                                self.pos += 1;
                                args.push(self.expr_at(1, depth + 1)?);
                            }
                        }
                        self.expect(TokenKind::RParen)?;
                        Ok(Expr::Call(name.clone(), args))
                    }
                    Some(TokenKind::LBracket) => {
                        self.pos += 1;
                        let e = self.expr_at(1, depth + 1)?;
                        self.expect(TokenKind::RBracket)?;
                        Ok(Expr::Index(name.clone(), Box::new(e)))
                    }
                    _ => Ok(Expr::Ident(name.clone())),
                }
            }
            _ => Err(self.unexpected()),
        }
    }
}
