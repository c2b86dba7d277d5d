//! Errors of the bag reader.

use std::path::{Path, PathBuf};

/// A bag that cannot be read, or a message in it that cannot be decoded.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum BagError {
    /// A file cannot be read.
    #[error("{}: cannot read: {source}", path.display())]
    #[diagnostic(code(navfn::E030))]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Not a rosbag2 storage file or folder.
    #[error("{}: not a rosbag2 bag: {why}", path.display())]
    #[diagnostic(code(navfn::E031))]
    NotABag {
        /// The file or folder.
        path: PathBuf,
        /// Why.
        why: String,
    },
    /// The storage is damaged (MCAP records, sqlite tables).
    #[error("{}: damaged {storage} storage: {why}", path.display())]
    #[diagnostic(code(navfn::E032))]
    Storage {
        /// The storage file.
        path: PathBuf,
        /// `MCAP` or `sqlite3`.
        storage: &'static str,
        /// What the reader reported.
        why: String,
    },
    /// A bag with no plan on the plan topic: nothing to check.
    #[error("{}: no plan recorded on {topic}: nothing to check", path.display())]
    #[diagnostic(
        code(navfn::E034),
        help("--plan-topic names the topic of the recorded plans (nav_msgs/Path)")
    )]
    NoPlans {
        /// The bag.
        path: PathBuf,
        /// The plan topic searched.
        topic: String,
    },
    /// A message that is not a valid CDR encoding of its type.
    #[error("message on {topic} at log time {log_time} ns ({type_name}): {why}")]
    #[diagnostic(code(navfn::E033))]
    Decode {
        /// Topic.
        topic: String,
        /// Type as recorded.
        type_name: String,
        /// Log time, ns.
        log_time: u64,
        /// What is wrong.
        why: String,
    },
}

impl BagError {
    /// A bag without a plan on the plan topic: nothing was checked, so nothing passed.
    pub fn no_plans(path: &Path, topic: &str) -> Self {
        BagError::NoPlans { path: path.to_path_buf(), topic: topic.to_string() }
    }

    /// A read error.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        BagError::Io { path: path.to_path_buf(), source }
    }

    /// Whether the bag could not be read at all (rather than being malformed).
    pub fn is_io(&self) -> bool {
        matches!(self, BagError::Io { .. })
    }
}
