//! vouch-navfn: a bit-exact Rust NavFn (ROS 2 nav2's default global planner), the nav2
//! `NavfnPlanner` layer around it, map readers (ROS map_server YAML+PGM/PNG, the JLAMP paper's
//! suite format), run-time plan checks, pictures, the golden-format suite runner and the
//! verification campaign.
//!
//! Layers, lowest first (each module imports only from its own layer or lower ones):
//! `diag` (source spans) → `core` (NavFn arrays, the IR of a plan) → `checks` (run-time
//! properties of every plan) → `maps` (front ends, located errors, the world frame) →
//! `costmap` (nav2's inflation layer, the footprint, the body check) → `planner` (nav2's
//! `NavfnPlanner`: world coordinates, swap, tolerance) → `suite` (call sequences of the golden
//! modes, golden text) → `picture` (PNG) → `campaign`, `bagcheck` → `guarantee` (the inflation
//! radius search) → `bench` (the harness of `vouch navfn bench`, only with the `bench` feature).
//! The reference semantics is `shared/navfn/SEMANTICS.md`; the oracle is `shared/navfn/golden`.

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

pub mod bagcheck;
#[cfg(feature = "bench")]
pub mod bench;
pub mod campaign;
pub mod checks;
pub mod core;
pub mod costmap;
pub mod diag;
pub mod guarantee;
pub mod maps;
pub mod picture;
pub mod planner;
pub mod rosbag;
pub mod suite;

pub use crate::core::{Algo, Cell, CoreError, NavFn, NoObserver, SearchObserver};
