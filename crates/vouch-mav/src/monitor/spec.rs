//! The one way to build a monitor from files: a dialect (or the embedded default), protocol
//! files (or the standard library) and constant overrides. `vouch mav check`, `lint` and `guard`
//! all go through [`MonitorSpec::build`], so they accept and reject the same inputs.

use std::path::PathBuf;
use std::sync::Arc;

use super::Monitor;
use crate::dialect::{Dialect, DialectError, load_dialect_file};
use crate::protocol::{ProtocolError, load_protocols, stdlib};
use crate::text::escape_controls;

/// Where a monitor's dialect and protocols come from.
#[derive(Clone, Debug, Default)]
pub struct MonitorSpec {
    /// A MAVLink XML dialect file (its includes relative to it); `None` = the embedded default
    /// (ardupilotmega with its includes).
    pub dialect: Option<PathBuf>,
    /// Protocol files; when empty, the standard library.
    pub protocols: Vec<PathBuf>,
    /// Also load the standard library when protocol files are given.
    pub with_stdlib: bool,
    /// New values of declared protocol constants, by name.
    pub overrides: Vec<(String, f64)>,
}

/// Why a monitor could not be built.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum LoadError {
    /// The dialect could not be loaded.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Dialect(#[from] DialectError),
    /// A protocol file cannot be read.
    #[error("cannot read protocol file {}: {source}", escape_controls(&path.display().to_string()))]
    #[diagnostic(code(mav::M001))]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A protocol file is not text (UTF-8): another format, or damaged.
    #[error("protocol file {path} is not UTF-8 text (first bad byte at offset {offset})")]
    #[diagnostic(code(mav::M002))]
    NotText {
        /// The file, control characters escaped.
        path: String,
        /// Offset of the first byte that is not UTF-8.
        offset: usize,
    },
    /// A protocol file was rejected (located).
    #[error(transparent)]
    #[diagnostic(transparent)]
    Protocol(Box<ProtocolError>),
}

impl LoadError {
    /// Whether a file could not be read (an I/O problem, not rejected content).
    pub fn is_io(&self) -> bool {
        match self {
            LoadError::Dialect(d) => d.is_io(),
            LoadError::Read { .. } => true,
            LoadError::NotText { .. } | LoadError::Protocol(_) => false,
        }
    }
}

impl From<ProtocolError> for LoadError {
    fn from(e: ProtocolError) -> Self {
        LoadError::Protocol(Box::new(e))
    }
}

impl MonitorSpec {
    /// The dialect this spec names.
    pub fn load_dialect(&self) -> Result<Arc<Dialect>, DialectError> {
        match &self.dialect {
            Some(p) => load_dialect_file(p),
            None => Dialect::default_dialect(),
        }
        .map(Arc::new)
    }

    /// The protocol sources, `(file name, text)`: the standard library first when it is used.
    pub fn sources(&self) -> Result<Vec<(String, String)>, LoadError> {
        let mut sources = if self.protocols.is_empty() || self.with_stdlib {
            stdlib::sources()
        } else {
            Vec::new()
        };
        for p in &self.protocols {
            let bytes =
                std::fs::read(p).map_err(|source| LoadError::Read { path: p.clone(), source })?;
            let text = String::from_utf8(bytes).map_err(|e| LoadError::NotText {
                path: escape_controls(&p.display().to_string()).into_owned(),
                offset: e.utf8_error().valid_up_to(),
            })?;
            sources.push((p.display().to_string(), text));
        }
        Ok(sources)
    }

    /// Loads the dialect and compiles the protocols into a monitor.
    pub fn build(&self) -> Result<Monitor, LoadError> {
        let dialect = self.load_dialect()?;
        let sources = self.sources()?;
        let set = load_protocols(&dialect, &sources, &self.overrides)?;
        Ok(Monitor::new(dialect, set))
    }
}
