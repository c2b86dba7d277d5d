//! vouch-fpl: the Paparazzi flight-plan (FPL) family of vouch — a compiler from flight-plan XML
//! to `flight_plan.h`, and the evidence that the C does what the plan says.
//!
//! Layers, lowest first (a module only uses its own layer or lower ones):
//!
//! * [`span`], [`ids`], [`diag`]: positions, block/waypoint ids, located diagnostics;
//! * [`expr`], [`ast`]: the expression language and the typed, resolved plan (the IR of the
//!   front end; no XML in it);
//! * [`front`]: XML → [`ast::FlightPlan`] or [`diag::Diagnostics`];
//! * [`passes`]: AST → FP → FPE → FPS (the three passes of the compiler);
//! * [`semantics`] and [`lint`], beside the IR: the reference interpreter and its exploration,
//!   mission-level warnings on the AST;
//! * [`emit`] and [`graph`], the back ends: the C header, upstream's dump, the SVG block graph;
//! * [`evidence`] and [`model_check`]: translation validation of the C against the semantics,
//!   the static work bound, model checking of the plan's state space; [`diff`], the behaviour of
//!   two versions of a plan compared on the product of their state spaces;
//! * [`pipeline`]: whole-file conveniences (parse, then compile; many plans in parallel);
//! * [`aircraft`]: Paparazzi's `conf/conf.xml` and where `gen_aircraft` writes a plan's outputs.
//!
//! Entry points: [`front::parse_file`], [`passes::compile`], [`emit::compile_plan`],
//! [`pipeline::compile_file`].

// The library never prints, exits or panics on its own: callers get data and typed errors.
// Tests (`cfg(test)`) may unwrap; an exception in library code is an `#[expect(..., reason)]`
// in place.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::print_stdout,
        clippy::print_stderr,
        clippy::exit,
        clippy::dbg_macro,
        clippy::todo,
        clippy::unimplemented
    )
)]

pub mod aircraft;
pub mod ast;
pub mod diag;
pub mod diff;
pub mod emit;
pub mod evidence;
pub mod expr;
pub mod front;
pub mod graph;
pub mod ids;
pub mod lint;
pub mod model_check;
pub mod passes;
pub mod pipeline;
pub mod semantics;
pub mod span;
