//! The protocol language: refined multiparty session types over MAVLink messages.
//!
//! Front: [`lexer`] and [`parser`] build an [`ast`]. The compiler resolves it against a dialect
//! and produces the [`ir`] that the monitor runs; its parts are `compile` (its state), `check`
//! (declarations), `flow` (statements) and `typing` (expressions). Errors are located and typed
//! ([`ProtocolError`], [`ErrorKind`]).

pub mod ast;
mod check;
mod compile;
mod effect;
pub mod error;
mod flow;
pub mod ir;
pub mod lexer;
mod parse_expr;
pub mod parser;
pub mod routes;
pub mod stdlib;
mod typing;

pub use error::{ErrorDetails, ErrorKind, ProtocolError, Span};
pub use ir::ProtocolSet;

use crate::dialect::Dialect;

/// Parses and checks protocol sources (`(file name, text)`), all into one set. `overrides`
/// replaces the values of declared constants (`--set NAME=VALUE`).
pub fn load_protocols(
    dialect: &Dialect,
    sources: &[(String, String)],
    overrides: &[(String, f64)],
) -> Result<ProtocolSet, ProtocolError> {
    let mut set = ProtocolSet::default();
    for (file, (name, text)) in sources.iter().enumerate() {
        let ast = parser::parse(text).map_err(|e| e.in_file(name, text))?;
        if ast.protocols.is_empty() && ast.effects.is_empty() {
            // Nothing to check is no success: an empty or commented-out file is refused.
            return Err(ProtocolError::at(
                ErrorKind::Structure,
                text,
                Span::new(0, 0),
                "the file declares no protocol and no effect".to_string(),
            )
            .in_file(name, text));
        }
        let mut c = compile::Compiler::new(dialect, text, file, &mut set);
        c.file(&ast).map_err(|e| e.in_file(name, text))?;
    }
    for (name, value) in overrides {
        match set.consts.iter_mut().find(|k| &k.name == name) {
            Some(k) => k.value = *value,
            None => {
                let known: Vec<&str> = set.consts.iter().map(|k| k.name.as_str()).collect();
                return Err(ProtocolError::named(
                    ErrorKind::Override,
                    "--set",
                    name,
                    Span::new(0, name.len()),
                    format!("no constant `{name}` is declared"),
                )
                .with_help(format!("declared constants: {}", known.join(", "))));
            }
        }
    }
    Ok(set)
}

/// Checks protocol sources without keeping the result (`vouch mav lint`).
pub fn lint(dialect: &Dialect, sources: &[(String, String)]) -> Result<ProtocolSet, ProtocolError> {
    load_protocols(dialect, sources, &[])
}
