//! Lexer with upstream's lexical rules (ocamllex longest match): blanks are space, tab and
//! newline only (a carriage return is an error); `/* */` comments; integers, floats without
//! exponent (`1.5e3` is `1.5` then the identifier `e3`); identifiers with an optional `$`;
//! single-quoted identifiers; C operators plus their `@` spellings. `<`, `<=`, `!=`, `&`, `|`
//! and string literals are not lexed.

use super::error::{ExprError, ExprErrorKind};

#[derive(Debug, Clone, PartialEq)]
pub enum TokenKind {
    Int(i64),
    Float(f64),
    Ident(String),
    Comma,
    Dot,
    Semicolon,
    Colon,
    LParen,
    RParen,
    LBrace,
    RBrace,
    LBracket,
    RBracket,
    Deref,
    EqEq,
    And,
    Or,
    Gt,
    Lt,
    Ge,
    Le,
    Percent,
    Plus,
    Assign,
    Minus,
    Pow,
    Star,
    Slash,
    Not,
}

/// A token with its byte range in the lexed text.
#[derive(Debug, Clone, PartialEq)]
pub struct Token {
    pub kind: TokenKind,
    pub start: usize,
    pub end: usize,
}

/// Fixed spellings, longest first where one is a prefix of another.
const FIXED: &[(&str, TokenKind)] = &[
    ("@DEREF", TokenKind::Deref),
    ("@AND", TokenKind::And),
    ("@OR", TokenKind::Or),
    ("@GEQ", TokenKind::Ge),
    ("@LEQ", TokenKind::Le),
    ("@GT", TokenKind::Gt),
    ("@LT", TokenKind::Lt),
    ("->", TokenKind::Deref),
    ("==", TokenKind::EqEq),
    ("&&", TokenKind::And),
    ("||", TokenKind::Or),
    (">=", TokenKind::Ge),
    ("**", TokenKind::Pow),
    (">", TokenKind::Gt),
    ("%", TokenKind::Percent),
    ("+", TokenKind::Plus),
    ("=", TokenKind::Assign),
    ("-", TokenKind::Minus),
    ("*", TokenKind::Star),
    ("/", TokenKind::Slash),
    ("!", TokenKind::Not),
    (",", TokenKind::Comma),
    (".", TokenKind::Dot),
    (";", TokenKind::Semicolon),
    (":", TokenKind::Colon),
    ("(", TokenKind::LParen),
    (")", TokenKind::RParen),
    ("{", TokenKind::LBrace),
    ("}", TokenKind::RBrace),
    ("[", TokenKind::LBracket),
    ("]", TokenKind::RBracket),
];

/// Length of the longest C comment starting at `s` (which begins with `/*`), following the
/// upstream regular expression `"/*" ([^*] | '*' [^/])* '*'* '/'` with longest-match
/// semantics; `None` when no prefix matches (then `/` is a division).
fn comment_len(s: &[u8]) -> Option<usize> {
    // NFA states: in_body (A), after_pair_star (P), in_stars (S). A reaches S by epsilon.
    let (mut a, mut p, mut st) = (true, false, true);
    let mut last = None;
    for (i, &c) in s.iter().enumerate().skip(2) {
        let na = (a && c != b'*') || (p && c != b'/');
        let np = a && c == b'*';
        let ns_star = st && c == b'*';
        if st && c == b'/' {
            last = Some(i + 1);
        }
        a = na;
        p = np;
        st = ns_star || na;
        if !a && !p && !st {
            break;
        }
    }
    last
}

fn is_ident_start(c: u8) -> bool {
    c.is_ascii_alphabetic() || c == b'_'
}
fn is_ident_char(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// Splits `text` into tokens, or reports the first character no rule accepts.
pub fn lex(text: &str) -> Result<Vec<Token>, ExprError> {
    let b = text.as_bytes();
    let mut i = 0;
    let mut out = Vec::new();
    while i < b.len() {
        let c = b[i];
        if c == b' ' || c == b'\t' || c == b'\n' {
            i += 1;
            continue;
        }
        if c == b'/'
            && b.get(i + 1) == Some(&b'*')
            && let Some(n) = comment_len(&b[i..])
        {
            i += n;
            continue;
        }
        let start = i;
        if c.is_ascii_digit() {
            while i < b.len() && b[i].is_ascii_digit() {
                i += 1;
            }
            if i < b.len() && b[i] == b'.' {
                i += 1;
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
                let v: f64 = text[start..i].parse().map_err(|_| bad_number(start, i))?;
                out.push(Token { kind: TokenKind::Float(v), start, end: i });
            } else {
                let v: i64 = text[start..i].parse().map_err(|_| bad_number(start, i))?;
                out.push(Token { kind: TokenKind::Int(v), start, end: i });
            }
            continue;
        }
        if is_ident_start(c) || (c == b'$' && b.get(i + 1).is_some_and(|&d| is_ident_start(d))) {
            i += 1;
            while i < b.len() && is_ident_char(b[i]) {
                i += 1;
            }
            out.push(Token { kind: TokenKind::Ident(text[start..i].to_string()), start, end: i });
            continue;
        }
        if c == b'\''
            && let Some(close) = b[i + 1..].iter().position(|&d| d == b'\'')
            && close > 0
        {
            let end = i + 1 + close + 1;
            let name = text[i + 1..end - 1].to_string();
            out.push(Token { kind: TokenKind::Ident(name), start, end });
            i = end;
            continue;
        }
        if let Some((s, k)) = FIXED.iter().find(|(s, _)| b[i..].starts_with(s.as_bytes())) {
            i += s.len();
            out.push(Token { kind: k.clone(), start, end: i });
            continue;
        }
        let ch = text[i..].chars().next().unwrap_or('?');
        return Err(ExprError {
            kind: ExprErrorKind::Lexing,
            message: format!("unexpected char {ch:?}"),
            start: i,
            end: i + ch.len_utf8(),
        });
    }
    Ok(out)
}

fn bad_number(start: usize, end: usize) -> ExprError {
    ExprError {
        kind: ExprErrorKind::Lexing,
        message: "number out of range".to_string(),
        start,
        end,
    }
}

#[cfg(test)]
mod tests {
    use super::comment_len;

    /// Expected lengths are the longest prefixes matched by upstream's regular expression
    /// `"/*" ([^*] | '*' [^/])* '*'* '/'`, computed independently with a regex engine.
    #[test]
    fn comment_regex_longest_match() {
        for (s, want) in [
            ("/**/", Some(4)),
            ("/*/", Some(3)),
            ("/* a */ + /* b */", Some(7)),
            ("/* a / b", Some(6)),
            ("/* a **/ b */", Some(13)),
            ("/* x *", None),
            ("/*", None),
            ("/* a */", Some(7)),
        ] {
            assert_eq!(comment_len(s.as_bytes()), want, "{s:?}");
        }
    }
}
