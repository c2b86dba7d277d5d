//! vouch-mav: MAVLink dialects and codec, a refined multiparty session-type protocol language,
//! a runtime monitor that checks traffic (live or recorded) against protocols, and a guarding
//! proxy that runs the monitor between ground station and vehicle.
//!
//! Layers, lowest first (each imports only from its own or lower layers):
//!
//! 1. [`crc`] (the frame checksum) and [`side`] (which end of the link);
//! 2. [`dialect`] (XML → tables, CRC_EXTRA);
//! 3. [`codec`] (frames, splitting, views, encoder, tlog);
//! 4. [`signing`] (MAVLink 2 signatures);
//! 5. [`vehicle_state`] (what telemetry says about the vehicle);
//! 6. [`protocol`] (protocol text → checked IR);
//! 7. [`monitor`] (runs the IR on messages; reports violations);
//! 8. [`guard`] (sockets, forwarding, enforce mode, signing checks);
//! 9. `bench` (the benchmark harness behind `vouch mav bench`, only with the `bench` feature,
//!    which the CLI enables; nothing else uses it).
//!
//! Nothing here prints: results are data, errors are typed [`miette::Diagnostic`]s with codes.

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

#[cfg(feature = "bench")]
pub mod bench;
pub mod codec;
pub mod crc;
pub mod dialect;
pub mod guard;
pub mod monitor;
pub mod protocol;
pub mod side;
pub mod signing;
pub mod text;
pub mod vehicle_state;

pub use codec::{Frame, FrameSplitter, MessageBuilder, MessageView, TlogReader, Value};
pub use dialect::Dialect;
pub use monitor::{Monitor, MonitorSpec, Verdict, Violation};
pub use side::Side;
