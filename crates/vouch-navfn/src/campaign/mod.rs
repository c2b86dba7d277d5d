//! The verification campaign: the paper's method as one command.
//!
//! * `gen` — deterministic generators for the nine categories, `suite_io` — suite reader/writer,
//!   `ros_import` — nav2 YAML+PGM maps as suite maps; `grid` — the campaign's IR;
//! * `exec` — one case with the search-trace property observer, `trace` — per-cycle trace format;
//! * `oracle` + `diff` — the oracle contract and the differential harness;
//! * `optimal` — cost model, 8-connected optimum, obtuse turns and oscillations;
//!   `optimality_stats` — their mergeable statistics;
//! * `transform` + `metamorphic` — grid symmetries, embedding, and the relations between runs;
//! * `names` — properties, relations, outcomes and finding kinds as types;
//! * `evaluate` — everything measured on one case; `runner` — the streamed, parallel campaign;
//! * `shard` — which maps and cases a shard runs; `identity` — suite fingerprints, map digests,
//!   content hash, the generator's manifest; `report` — the JSON report; `merge` — strict
//!   merging of shard reports; `summary` — the human table; `pictures` — PNG of
//!   counterexamples; `error` — what can go wrong.
//!
//! The campaign only calls the core through `crate::suite`; it never changes a NavFn result.

pub mod diff;
pub mod error;
pub mod evaluate;
pub mod exec;
pub mod generate;
pub mod grid;
pub mod identity;
pub mod merge;
pub mod metamorphic;
pub mod names;
pub mod optimal;
pub mod optimality_stats;
pub mod oracle;
pub mod pictures;
pub mod report;
pub mod rng;
pub mod ros_import;
pub mod runner;
pub mod shard;
pub mod suite_io;
pub mod summary;
pub mod trace;
pub mod transform;

pub use error::CampaignError;
