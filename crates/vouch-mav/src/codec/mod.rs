//! MAVLink wire format: checksum, frame recognition, payload views, encoder, tlog reader.

pub mod crc;
pub mod encode;
pub mod frame;
pub mod tlog;
pub mod view;

pub use encode::{EncodeError, MessageBuilder};
pub use frame::{parse_frame, CodecStats, Frame, FrameSplitter, Parse, Version};
pub use tlog::{TlogReader, TlogRecord};
pub use view::{MessageView, Value};
