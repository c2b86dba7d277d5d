//! MCAP storage (`rosbag2_storage_mcap`): every message of the wanted topics, whose channel
//! says `cdr`. Read with the `mcap` crate's streaming reader (chunks decompressed as they come,
//! CRCs checked).

use std::collections::BTreeSet;
use std::path::Path;

use super::{BagError, BagMessage};

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
    let mut out = Vec::new();
    for message in ::mcap::MessageStream::new(data).map_err(damaged)? {
        let message = message.map_err(damaged)?;
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
                why: format!("message encoding `{}`, expected cdr", channel.message_encoding),
            });
        }
        out.push(BagMessage {
            topic: channel.topic.clone(),
            type_name,
            log_time: message.log_time,
            data: message.data.into_owned(),
        });
    }
    Ok(out)
}
