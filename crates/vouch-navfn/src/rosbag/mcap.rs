//! MCAP storage (`rosbag2_storage_mcap`): every message of the wanted topics, whose channel
//! says `cdr`. Read with the `mcap` crate's sans-I/O message reader (chunks decompressed as they
//! come, CRCs checked) and a record length limit, so that a corrupt length field cannot make
//! the reader allocate more than [`MAX_RECORD_BYTES`].

use std::collections::BTreeSet;
use std::path::Path;

use ::mcap::sans_io::{LinearReaderOptions, MessageReadEvent, MessageReader};

use super::{BagError, BagMessage};
use crate::maps::MAX_CELLS;

/// Largest record (or decompressed chunk) accepted: a grid of [`MAX_CELLS`] cells and change.
pub const MAX_RECORD_BYTES: usize = MAX_CELLS + (1 << 20);

pub(super) fn read_messages(
    path: &Path,
    data: &[u8],
    topics: &BTreeSet<String>,
) -> Result<Vec<BagMessage>, BagError> {
    let damaged = |e: ::mcap::McapError| BagError::Storage {
        path: path.to_path_buf(),
        storage: "MCAP",
        why: e.to_string(),
    };
    let options = LinearReaderOptions::default().with_record_length_limit(MAX_RECORD_BYTES);
    let mut reader = MessageReader::new_with_options(options);
    let mut rest = data;
    let mut out = Vec::new();
    while let Some(event) = reader.next_event() {
        match event.map_err(damaged)? {
            MessageReadEvent::ReadRequest(want) => {
                let n = want.min(rest.len());
                reader.insert(n).copy_from_slice(&rest[..n]);
                reader.notify_read(n);
                rest = &rest[n..];
            }
            MessageReadEvent::Message(message) => {
                let channel = &message.channel;
                if !topics.contains(&channel.topic) {
                    continue;
                }
                let type_name = channel.schema.as_ref().map(|s| s.name.clone()).unwrap_or_default();
                if channel.message_encoding != "cdr" {
                    return Err(BagError::Decode {
                        topic: channel.topic.clone(),
                        type_name,
                        log_time: message.log_time,
                        why: format!(
                            "message encoding `{}`, expected cdr",
                            channel.message_encoding
                        ),
                    });
                }
                out.push(BagMessage {
                    topic: channel.topic.clone(),
                    type_name,
                    log_time: message.log_time,
                    data: message.data.into_owned(),
                });
            }
        }
    }
    Ok(out)
}
