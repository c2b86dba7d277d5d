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
            if c == b'0' && matches!(b.get(i + 1), Some(b'x') | Some(b'X')) {
                i += 2;
                while i < b.len() && b[i].is_ascii_hexdigit() {
                    i += 1;
                }
                let v = u64::from_str_radix(&src[start + 2..i], 16).map_err(|_| {
                    ProtocolError::at(
                        ErrorKind::Lex,
                        src,
                        Span::new(start, i - start),
                        "invalid hexadecimal number",
                    )
                })?;
                out.push(Token { tok: Tok::Num(v as f64), span: Span::new(start, i - start) });
                continue;
            }
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                // `1..` is not a thing here, but keep `x.y` field access unambiguous: a dot must be
                // followed by a digit to belong to the number.
                if b[i] == b'.' && !b.get(i + 1).is_some_and(u8::is_ascii_digit) {
                    break;
                }
                i += 1;
            }
            let v: f64 = src[start..i].parse().map_err(|_| {
                ProtocolError::at(
                    ErrorKind::Lex,
                    src,
                    Span::new(start, i - start),
                    "invalid number",
                )
            })?;
            out.push(Token { tok: Tok::Num(v), span: Span::new(start, i - start) });
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
                    format!("unexpected character `{ch}`"),
                ));
            }
        }
    }
    out.push(Token { tok: Tok::Eof, span: Span::new(end, 0) });
    Ok(out)
}
