//! MAVLink wire format: frame headers, splitting received bytes into frames, payload
//! views, encoder, tlog reader.

pub mod encode;
pub mod frame;
pub mod split;
pub mod tlog;
pub mod view;

pub use encode::{EncodeError, MessageBuilder};
pub use frame::{CodecStats, Frame, FrameRef, InvalidKind, Parse, Version, parse_frame};
pub use split::{FrameSplitter, Piece, StreamSplitter};
pub use tlog::{TlogReader, TlogRecord};
pub use view::{MessageView, Value};
