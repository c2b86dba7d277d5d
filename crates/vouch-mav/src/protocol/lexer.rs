//! Tokens of the protocol language, each with its byte span for located errors.

use super::error::{ErrorKind, ProtocolError, Span};

#[derive(Debug, Clone, PartialEq)]
pub enum Tok {
    Ident(String),
    Num(f64),
    Str(String),
    /// Punctuation and operators, spelled as in the source (`->`, `==`, `{`, …).
    Sym(&'static str),
    Eof,
}

#[derive(Debug, Clone)]
pub struct Token {
    pub tok: Tok,
    pub span: Span,
}

const SYMS: &[&str] = &[
    "->", "==", "!=", "<=", ">=", "&&", "||", "=>", "..", "{", "}", "(", ")", "[", "]", ",", ";",
    ":", "|", "=", "<", ">", "!", "+", "-", "*", "/", ".",
];

pub fn lex(src: &str) -> Result<Vec<Token>, ProtocolError> {
    lex_range(src, 0, src.len())
}

/// Tokens of `src[start..end]` (e.g. the expression between the braces of an interpolated text),
/// with spans into the whole of `src`.
pub fn lex_range(src: &str, start: usize, end: usize) -> Result<Vec<Token>, ProtocolError> {
    let b = &src.as_bytes()[..end];
    let mut i = start;
    let mut out = Vec::new();
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        // Comments: `//` or `#` to the end of the line.
        if c == b'#' || (c == b'/' && b.get(i + 1) == Some(&b'/')) {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        let start = i;
        if c.is_ascii_alphabetic() || c == b'_' {
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            out.push(Token {
                tok: Tok::Ident(src[start..i].to_string()),
                span: Span::new(start, i - start),
            });
            continue;
        }
        if c.is_ascii_digit() {
            let (tok, next) = number(src, b, start)?;
            out.push(tok);
            i = next;
            continue;
        }
        if c == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' && b[i] != b'\n' {
                i += 1;
            }
            if i >= b.len() || b[i] != b'"' {
                return Err(ProtocolError::at(
                    ErrorKind::Lex,
                    src,
                    Span::new(start, i - start),
                    "unterminated string",
                ));
            }
            i += 1;
            out.push(Token {
                tok: Tok::Str(src[start + 1..i - 1].to_string()),
                span: Span::new(start, i - start),
            });
            continue;
        }
        let rest = &src[i..end];
        match SYMS.iter().find(|s| rest.starts_with(**s)) {
            Some(s) => {
                i += s.len();
                out.push(Token { tok: Tok::Sym(s), span: Span::new(start, s.len()) });
            }
            None => {
                let ch = rest.chars().next().unwrap_or('?');
                return Err(ProtocolError::at(
                    ErrorKind::Lex,
                    src,
                    Span::new(start, ch.len_utf8()),
                    // Escaped: the character may be a control character that must not reach a terminal.
                    format!("unexpected character `{}`", ch.escape_debug()),
                ));
            }
        }
    }
    out.push(Token { tok: Tok::Eof, span: Span::new(end, 0) });
    Ok(out)
}

/// The number starting at `start` (decimal, or hexadecimal after `0x`) and the index after it.
fn number(src: &str, b: &[u8], start: usize) -> Result<(Token, usize), ProtocolError> {
    let mut i = start;
    let bad = |i: usize, what: &str| {
        ProtocolError::at(ErrorKind::Lex, src, Span::new(start, i - start), what.to_string())
    };
    if b[i] == b'0' && matches!(b.get(i + 1), Some(b'x') | Some(b'X')) {
        i += 2;
        while i < b.len() && b[i].is_ascii_hexdigit() {
            i += 1;
        }
        let v = u64::from_str_radix(&src[start + 2..i], 16)
            .map_err(|_| bad(i, "invalid hexadecimal number"))?;
        return Ok((Token { tok: Tok::Num(v as f64), span: Span::new(start, i - start) }, i));
    }
    while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
        // A dot belongs to the number only when a digit follows: `1..16` is a range, and `x.y`
        // stays a member access.
        if b[i] == b'.' && !b.get(i + 1).is_some_and(u8::is_ascii_digit) {
            break;
        }
        i += 1;
    }
    let v: f64 = src[start..i].parse().map_err(|_| bad(i, "invalid number"))?;
    Ok((Token { tok: Tok::Num(v), span: Span::new(start, i - start) }, i))
}
