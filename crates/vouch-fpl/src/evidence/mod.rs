//! Per-plan evidence: translation validation of the compiled C against the reference
//! semantics ([`validate`], through the C driver of [`cdriver`]) and the static bound on the work
//! of one call ([`wcet`]).

pub mod cdriver;
pub mod cstate;
pub mod validate;
pub mod wcet;
