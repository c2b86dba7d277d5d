//! The verification campaign (issue 7): the paper's method as one command.
//!
//! * `gen` — deterministic generators for the nine categories, `suite_io` — suite reader/writer,
//!   `ros_import` — nav2 YAML+PGM maps as suite maps;
//! * `exec` — one case with the search-trace property observer, `trace` — per-cycle trace format;
//! * `oracle` + `diff` — the oracle contract and the differential harness;
//! * `optimal` — cost model, 8-connected optimum, obtuse turns and oscillations;
//! * `transform` + `metamorphic` — grid symmetries, embedding, and the relations between runs;
//! * `runner` — the parallel campaign, `report` — JSON report, shards, merge, summary table;
//! * `pictures` — PNG of counterexamples.
//!
//! The campaign only calls the core (`crate::core`, `crate::suite_run`); it never changes a
//! NavFn result.

pub mod commands;
pub mod diff;
pub mod exec;
pub mod gen;
pub mod grid;
pub mod metamorphic;
pub mod optimal;
pub mod oracle;
pub mod pictures;
pub mod report;
pub mod rng;
pub mod ros_import;
pub mod runner;
pub mod suite_io;
pub mod trace;
pub mod transform;
