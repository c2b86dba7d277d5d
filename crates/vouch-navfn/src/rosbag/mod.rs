//! rosbag2 recordings, the front end of `check-bag`: a bag folder (`metadata.yaml` and its
//! storage files) or one storage file, in either of rosbag2's storage formats — MCAP
//! (`mcap.rs`, through the `mcap` crate) or sqlite3 (`sqlite.rs`, through `rusqlite`) — read into
//! time-ordered raw messages of the topics asked for, and the CDR decoding of the nav2 messages
//! that matter here (`msgs.rs`, through `cdr-encoding`). Every failure is a [`BagError`] naming
//! the file, and for a message its topic and log time; nothing panics on hostile input.

mod error;
mod mcap;
pub mod msgs;
mod sqlite;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

pub use error::BagError;

/// The storage format of one rosbag2 file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Storage {
    /// `rosbag2_storage_mcap` (the default since ROS 2 Iron).
    Mcap,
    /// `rosbag2_storage_default_plugins` sqlite3 (`.db3`).
    Sqlite3,
}

/// One recorded message, still CDR-encoded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BagMessage {
    /// Topic name.
    pub topic: String,
    /// Message type as recorded (`nav_msgs/msg/Path`).
    pub type_name: String,
    /// Receive time, nanoseconds since the epoch.
    pub log_time: u64,
    /// The serialized message (CDR with its 4-byte encapsulation header).
    pub data: Vec<u8>,
}

/// The messages of the topics asked for, ordered by log time (stable for equal times).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Bag {
    /// Storage files read, with their format.
    pub files: Vec<(PathBuf, Storage)>,
    /// The messages.
    pub messages: Vec<BagMessage>,
}

/// Largest storage file read (bytes): far above a nav2 recording of maps and plans.
pub const MAX_FILE_BYTES: u64 = 4 << 30;

/// Reads a bag folder (every `.mcap` and `.db3` file in it, by name) or one storage file,
/// keeping the messages of `topics` only.
pub fn read_bag(path: &Path, topics: &BTreeSet<String>) -> Result<Bag, BagError> {
    let files = storage_files(path)?;
    let mut bag = Bag::default();
    for file in files {
        let storage = storage_of(&file)?;
        let mut messages = match storage {
            Storage::Mcap => {
                let data = read_file(&file)?;
                mcap::read_messages(&file, &data, topics)?
            }
            Storage::Sqlite3 => sqlite::read_messages(&file, topics)?,
        };
        bag.messages.append(&mut messages);
        bag.files.push((file, storage));
    }
    bag.messages.sort_by_key(|m| m.log_time);
    Ok(bag)
}

/// Reads MCAP bytes already in memory (the fuzz target's entry).
pub fn read_mcap_bytes(
    data: &[u8],
    topics: &BTreeSet<String>,
) -> Result<Vec<BagMessage>, BagError> {
    mcap::read_messages(Path::new("<memory>"), data, topics)
}

/// The storage files of a bag: the file itself, or the `.mcap`/`.db3` files of a folder.
fn storage_files(path: &Path) -> Result<Vec<PathBuf>, BagError> {
    let meta = std::fs::metadata(path).map_err(|e| BagError::io(path, e))?;
    if !meta.is_dir() {
        return Ok(vec![path.to_path_buf()]);
    }
    let mut files: Vec<PathBuf> = std::fs::read_dir(path)
        .map_err(|e| BagError::io(path, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "mcap" || x == "db3"))
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(BagError::NotABag {
            path: path.to_path_buf(),
            why: "the folder holds no .mcap or .db3 storage file".into(),
        });
    }
    Ok(files)
}

/// The format of a storage file, by its first bytes.
fn storage_of(file: &Path) -> Result<Storage, BagError> {
    use std::io::Read;
    let mut head = [0u8; 16];
    let mut f = std::fs::File::open(file).map_err(|e| BagError::io(file, e))?;
    let n = f.read(&mut head).map_err(|e| BagError::io(file, e))?;
    if head[..n].starts_with(b"\x89MCAP") {
        Ok(Storage::Mcap)
    } else if head[..n].starts_with(b"SQLite format 3\0") {
        Ok(Storage::Sqlite3)
    } else {
        Err(BagError::NotABag {
            path: file.to_path_buf(),
            why: "neither an MCAP file nor an sqlite3 database".into(),
        })
    }
}

fn read_file(file: &Path) -> Result<Vec<u8>, BagError> {
    let len = std::fs::metadata(file).map_err(|e| BagError::io(file, e))?.len();
    if len > MAX_FILE_BYTES {
        return Err(BagError::NotABag {
            path: file.to_path_buf(),
            why: format!("{len} bytes exceed the limit of {MAX_FILE_BYTES}"),
        });
    }
    std::fs::read(file).map_err(|e| BagError::io(file, e))
}
