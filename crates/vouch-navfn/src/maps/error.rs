//! Located errors of the map readers.

use std::path::PathBuf;

/// A map or suite file that cannot be used, with the file (and line when there is one).
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    #[error("{}: cannot read: {source}", path.display())]
    Io { path: PathBuf, source: std::io::Error },
    #[error("{}:{line}: {msg}", path.display())]
    Line { path: PathBuf, line: usize, msg: String },
    #[error("{}: {msg}", path.display())]
    File { path: PathBuf, msg: String },
}

impl MapError {
    pub fn line(path: &std::path::Path, line: usize, msg: impl Into<String>) -> Self {
        MapError::Line { path: path.to_path_buf(), line, msg: msg.into() }
    }
    pub fn file(path: &std::path::Path, msg: impl Into<String>) -> Self {
        MapError::File { path: path.to_path_buf(), msg: msg.into() }
    }
    pub fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        MapError::Io { path: path.to_path_buf(), source }
    }
}
