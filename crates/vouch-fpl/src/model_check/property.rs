//! The property language of `vouch fpl check --property`:
//!
//! ```text
//! property := "always" "eventually" F | "eventually" "always" F
//!           | "always" F | "eventually" F | "never" F
//! F        := F "||" F | F "&&" F | "!" F | "(" F ")" | atom       (also: or, and, not)
//! atom     := block(NAME) | last_block(NAME) | stage(N) | true | false
//! ```
//!
//! Temporal operators are universal over all runs (every infinite sequence of calls, with
//! conditions free): `always F` holds when F holds in every reachable state; `eventually F`
//! when every run reaches F; `always eventually F` when every run visits F infinitely often;
//! `eventually always F` when every run ends up staying in F.

use miette::SourceSpan;
use serde::Serialize;

use crate::semantics::trace::Observation;

/// A property text that does not parse, with the place where it went wrong.
#[derive(Debug, Clone, thiserror::Error, miette::Diagnostic)]
#[error("property: {message}")]
#[diagnostic(code(fpl::E042))]
pub struct PropertyError {
    /// What is wrong.
    pub message: String,
    /// The property as given.
    #[source_code]
    pub text: String,
    /// Where in the text.
    #[label("here")]
    pub at: SourceSpan,
}

/// The atoms that name a part of the state.
#[derive(Clone, Copy)]
enum Atom {
    Block,
    LastBlock,
    Stage,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StateFormula {
    True,
    False,
    /// `block(NAME)`, resolved to an index.
    Block(usize),
    LastBlock(usize),
    Stage(usize),
    Not(Box<StateFormula>),
    And(Box<StateFormula>, Box<StateFormula>),
    Or(Box<StateFormula>, Box<StateFormula>),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Temporal {
    Always,
    Eventually,
    AlwaysEventually,
    EventuallyAlways,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Property {
    pub temporal: Temporal,
    pub formula: StateFormula,
}

impl StateFormula {
    /// Whether the formula names the last block (the state graph must then keep it).
    pub fn uses_last_block(&self) -> bool {
        match self {
            StateFormula::LastBlock(_) => true,
            StateFormula::Not(f) => f.uses_last_block(),
            StateFormula::And(a, b) | StateFormula::Or(a, b) => {
                a.uses_last_block() || b.uses_last_block()
            }
            _ => false,
        }
    }

    pub fn holds(&self, o: &Observation) -> bool {
        match self {
            StateFormula::True => true,
            StateFormula::False => false,
            StateFormula::Block(b) => o.block == *b,
            StateFormula::LastBlock(b) => o.last_block == *b,
            StateFormula::Stage(s) => o.stage == *s,
            StateFormula::Not(f) => !f.holds(o),
            StateFormula::And(a, b) => a.holds(o) && b.holds(o),
            StateFormula::Or(a, b) => a.holds(o) || b.holds(o),
        }
    }
}

/// Nesting limit of `!` and parentheses (the parser recurses on them).
const MAX_DEPTH: usize = 200;

struct Parser<'a> {
    s: &'a str,
    pos: usize,
    blocks: &'a [String],
    depth: usize,
}

impl<'a> Parser<'a> {
    fn ws(&mut self) {
        while self.s[self.pos..].starts_with(char::is_whitespace) {
            self.pos += self.s[self.pos..].chars().next().map(char::len_utf8).unwrap_or(1);
        }
    }
    fn eat(&mut self, tok: &str) -> bool {
        self.ws();
        let rest = &self.s[self.pos..];
        let word = tok.chars().all(|c| c.is_ascii_alphabetic() || c == '_');
        if let Some(tail) = rest.strip_prefix(tok) {
            let after = tail.chars().next();
            if word && after.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') {
                return false;
            }
            self.pos += tok.len();
            return true;
        }
        false
    }
    fn err<T>(&self, msg: impl Into<String>) -> Result<T, PropertyError> {
        self.err_at(self.pos, msg)
    }
    fn err_at<T>(&self, at: usize, msg: impl Into<String>) -> Result<T, PropertyError> {
        let len = self.s.get(at..).and_then(|r| r.chars().next()).map_or(0, char::len_utf8);
        Err(PropertyError { message: msg.into(), text: self.s.to_string(), at: (at, len).into() })
    }
    fn or(&mut self) -> Result<StateFormula, PropertyError> {
        let mut f = self.and()?;
        while self.eat("||") || self.eat("or") {
            f = StateFormula::Or(Box::new(f), Box::new(self.and()?));
        }
        Ok(f)
    }
    fn and(&mut self) -> Result<StateFormula, PropertyError> {
        let mut f = self.unary()?;
        while self.eat("&&") || self.eat("and") {
            f = StateFormula::And(Box::new(f), Box::new(self.unary()?));
        }
        Ok(f)
    }
    fn unary(&mut self) -> Result<StateFormula, PropertyError> {
        if self.depth >= MAX_DEPTH {
            return self.err(format!("nested more than {MAX_DEPTH} levels deep"));
        }
        if self.eat("!") || self.eat("not") {
            self.depth += 1;
            let f = self.unary()?;
            self.depth -= 1;
            return Ok(StateFormula::Not(Box::new(f)));
        }
        if self.eat("(") {
            self.depth += 1;
            let f = self.or()?;
            self.depth -= 1;
            if !self.eat(")") {
                return self.err("expected ')'");
            }
            return Ok(f);
        }
        if self.eat("true") {
            return Ok(StateFormula::True);
        }
        if self.eat("false") {
            return Ok(StateFormula::False);
        }
        for (kw, atom) in
            [("last_block", Atom::LastBlock), ("block", Atom::Block), ("stage", Atom::Stage)]
        {
            if self.eat(kw) {
                return self.atom(atom);
            }
        }
        self.err("expected block(NAME), last_block(NAME), stage(N), true, false, '!' or '('")
    }
    /// The parenthesised argument of an atom, resolved.
    fn atom(&mut self, atom: Atom) -> Result<StateFormula, PropertyError> {
        if !self.eat("(") {
            return self.err("expected '('");
        }
        let start = self.pos;
        let rest = &self.s[self.pos..];
        let Some(end) = rest.find(')') else { return self.err("expected ')'") };
        let arg = rest[..end].trim().trim_matches(|c| c == '\'' || c == '"').to_string();
        self.pos += end + 1;
        if let Atom::Stage = atom {
            return match arg.parse() {
                Ok(n) => Ok(StateFormula::Stage(n)),
                Err(_) => self.err_at(start, format!("stage({arg}): not a number")),
            };
        }
        let Some(b) = self.blocks.iter().position(|n| *n == arg) else {
            let known = self.blocks.join(", ");
            return self.err_at(start, format!("unknown block '{arg}' (blocks: {known})"));
        };
        Ok(match atom {
            Atom::LastBlock => StateFormula::LastBlock(b),
            _ => StateFormula::Block(b),
        })
    }
}

/// Parses a property against the plan's block names.
pub fn parse(text: &str, blocks: &[String]) -> Result<Property, PropertyError> {
    let mut p = Parser { s: text, pos: 0, blocks, depth: 0 };
    let temporal = if p.eat("always") {
        if p.eat("eventually") { Temporal::AlwaysEventually } else { Temporal::Always }
    } else if p.eat("eventually") {
        if p.eat("always") { Temporal::EventuallyAlways } else { Temporal::Eventually }
    } else if p.eat("never") {
        let f = p.or()?;
        p.ws();
        if p.pos != text.len() {
            return p.err("unexpected text");
        }
        return Ok(Property {
            temporal: Temporal::Always,
            formula: StateFormula::Not(Box::new(f)),
        });
    } else {
        return p.err("a property starts with always, eventually or never");
    };
    let formula = p.or()?;
    p.ws();
    if p.pos != text.len() {
        return p.err("unexpected text");
    }
    Ok(Property { temporal, formula })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blocks() -> Vec<String> {
        vec!["Take off".into(), "Land".into()]
    }

    #[test]
    fn parses_the_language() {
        let p = parse("always eventually block(Land)", &blocks()).expect("parses");
        assert_eq!(
            p,
            Property { temporal: Temporal::AlwaysEventually, formula: StateFormula::Block(1) }
        );
        let p = parse("never (block('Take off') && !stage(2)) or last_block(Land)", &blocks())
            .expect("parses");
        assert_eq!(p.temporal, Temporal::Always);
        let o = Observation { block: 0, stage: 1, last_block: 0, last_stage: 0 };
        // in Take off at stage 1 (not 2), last block not Land: the inner formula holds, never fails
        assert!(!p.formula.holds(&o));
        let p = parse("eventually always true", &blocks()).expect("parses");
        assert_eq!(p.temporal, Temporal::EventuallyAlways);
        assert!(parse("always block(Nowhere)", &blocks()).is_err());
        assert!(parse("always stage(x)", &blocks()).is_err());
        assert!(parse("always block(Land) extra", &blocks()).is_err());
        assert!(parse("alwaysblock(Land)", &blocks()).is_err());
        let deep = format!("always {}true", "!".repeat(100_000));
        let e = parse(&deep, &blocks()).expect_err("too deep");
        assert!(e.message.contains("nested"), "{}", e.message);
        let e = parse("always block(Nowhere)", &blocks()).expect_err("unknown");
        assert_eq!(e.at.offset(), 13, "points at the argument");
    }
}
