//! Errors of the expression lexer and parser.

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum ExprErrorKind {
    /// A character no lexical rule accepts (or an out-of-range number).
    Lexing,
    /// Tokens that do not form an expression.
    Parsing,
}

/// An error in an expression, with the byte range (in the expression text) of the offending
/// character or token.
#[derive(Debug, Clone, PartialEq)]
pub struct ExprError {
    pub kind: ExprErrorKind,
    pub message: String,
    pub start: usize,
    pub end: usize,
}

impl std::fmt::Display for ExprError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for ExprError {}
