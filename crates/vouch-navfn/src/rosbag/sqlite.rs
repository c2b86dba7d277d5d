//! sqlite3 storage (`.db3`, rosbag2's original default): the `topics` and `messages` tables,
//! opened read-only through `rusqlite` (SQLite compiled in).

use std::collections::BTreeSet;
use std::path::Path;

use rusqlite::{Connection, OpenFlags};

use super::{BagError, BagMessage};

pub(super) fn read_messages(
    path: &Path,
    topics: &BTreeSet<String>,
) -> Result<Vec<BagMessage>, BagError> {
    let damaged = |e: rusqlite::Error| BagError::Storage {
        path: path.to_path_buf(),
        storage: "sqlite3",
        why: e.to_string(),
    };
    let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    let db = Connection::open_with_flags(path, flags).map_err(damaged)?;
    let mut query = db
        .prepare(
            "SELECT t.name, t.type, t.serialization_format, m.timestamp, m.data \
             FROM messages m JOIN topics t ON m.topic_id = t.id ORDER BY m.timestamp, m.id",
        )
        .map_err(damaged)?;
    let mut rows = query.query([]).map_err(damaged)?;
    let mut out = Vec::new();
    while let Some(row) = rows.next().map_err(damaged)? {
        let topic: String = row.get(0).map_err(damaged)?;
        if !topics.contains(&topic) {
            continue;
        }
        let type_name: String = row.get(1).map_err(damaged)?;
        let format: String = row.get(2).map_err(damaged)?;
        let stamp: i64 = row.get(3).map_err(damaged)?;
        let log_time = u64::try_from(stamp).map_err(|_| BagError::Decode {
            topic: topic.clone(),
            type_name: type_name.clone(),
            log_time: 0,
            why: format!("negative timestamp {stamp}"),
        })?;
        if format != "cdr" {
            return Err(BagError::Decode {
                topic,
                type_name,
                log_time,
                why: format!("serialization format `{format}`, expected cdr"),
            });
        }
        let data: Vec<u8> = row.get(4).map_err(damaged)?;
        out.push(BagMessage { topic, type_name, log_time, data });
    }
    Ok(out)
}
