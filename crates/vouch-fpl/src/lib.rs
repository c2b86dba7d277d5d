//! vouch-fpl: the Paparazzi flight-plan (FPL) family of vouch.
//!
//! * [`front`] reads flight-plan XML the way upstream Paparazzi does (tolerant reader over
//!   roxmltree, includes/procedures, paths, relative waypoints, name resolution) and produces the
//!   typed, resolved [`ast::FlightPlan`] or located [`front::Diagnostics`].
//! * [`expr`] is the Paparazzi expression language: lexer, parser and the upstream-exact printer.
//!
//! Entry point: [`front::parse_file`]. The AST contract is described in `docs/fpl-ast-contract.md`.

pub mod ast;
pub mod emit;
pub mod evidence;
pub mod expr;
pub mod front;
pub mod graph;
pub mod lint;
pub mod model_check;
pub mod passes;
pub mod semantics;
pub mod sim;
