//! Per-plan evidence: translation validation of the compiled C against the reference
//! semantics ([`validate`]), the static bound on one call ([`wcet`]), and the exploration engine
//! they share with the model checker ([`explore`]).

pub mod cdriver;
pub mod commands;
pub mod explore;
pub mod validate;
pub mod wcet;
