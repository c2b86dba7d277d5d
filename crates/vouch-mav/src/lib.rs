//! vouch-mav: MAVLink dialects and codec, a refined multiparty session-type protocol language,
//! and a runtime monitor that checks traffic (live or recorded) against protocols.
//!
//! Layers, front to back: [`dialect`] (XML → tables) and [`codec`] (frames, views, encoder, tlog)
//! feed the [`monitor`], which runs protocols compiled by [`protocol`] (text → IR, checked against
//! the dialect) with the [`vehicle_state`] it tracks from telemetry.

pub mod codec;
pub mod dialect;
pub mod monitor;
pub mod protocol;
pub mod vehicle_state;

pub use codec::{Frame, FrameSplitter, MessageBuilder, MessageView, TlogReader, Value};
pub use dialect::Dialect;
pub use monitor::{Monitor, Origin, Verdict, Violation};

// Owned by mav-guard (issue 8): the guarding proxy and MAVLink 2 signing. Please keep.
pub mod guard;
pub mod signing;
