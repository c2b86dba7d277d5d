//! vouch-navfn: a bit-exact Rust NavFn (ROS 2 nav2's default global planner), the nav2
//! `NavfnPlanner` layer around it, map readers (ROS map_server YAML+PGM, the JLAMP paper's
//! suite format), run-time plan checks, pictures, and the golden-format suite runner.
//!
//! Shape: `maps` (front ends, located errors) → `core` (NavFn arrays, the IR of a plan) →
//! `checks` (run-time properties of every plan) → back ends (`suite_run` text, `picture` PNG).
//! `planner` wraps the core like nav2's `NavfnPlanner` (world coordinates, swap, tolerance).
//! The reference semantics is `shared/navfn/SEMANTICS.md`; the oracle is `shared/navfn/golden`.

#[allow(unsafe_code)] // thread CPU clock through libc
pub mod bench;
pub mod campaign;
pub mod checks;
pub mod core;
pub mod maps;
pub mod picture;
pub mod planner;
pub mod suite_run;

pub use crate::core::{Algo, Cell, CoreError, NavFn, NoObserver, SearchObserver};
