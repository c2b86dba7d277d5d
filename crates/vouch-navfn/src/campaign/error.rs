//! Errors of the campaign: suites that cannot be read or generated, cases that cannot run, an
//! oracle that fails, reports that cannot be written.

use std::path::PathBuf;

use crate::campaign::shard::ShardError;
use crate::campaign::suite_io::SuiteIoError;
use crate::maps::MapError;
use crate::suite::CaseError;

/// Why a campaign command stopped.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum CampaignError {
    /// A suite, map or test file that cannot be used.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Map(#[from] MapError),
    /// A suite that cannot be read or written.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Suite(#[from] SuiteIoError),
    /// Generator options that cannot be met.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Gen(#[from] GenError),
    /// A case that cannot run.
    #[error("{map}: {source}")]
    #[diagnostic(code(navfn::E050))]
    Case {
        /// `category/map`.
        map: String,
        /// Why.
        source: CaseError,
    },
    /// The oracle failed or answered in a form that does not parse.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Oracle(#[from] OracleError),
    /// vouch's own side of the oracle contract did not parse (a bug, never an input problem).
    #[error("vouch's own oracle output did not parse: {0}")]
    #[diagnostic(code(navfn::E051))]
    Own(String),
    /// A suite folder that does not match its manifest, or a share run in a way that cannot
    /// cover it.
    #[error("{}: {msg}", dir.display())]
    #[diagnostic(code(navfn::E055))]
    Share {
        /// The suite folder.
        dir: PathBuf,
        /// What does not match.
        msg: String,
    },
    /// A shard specification that cannot be used.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Shard(#[from] ShardError),
    /// An output file (picture, per-case records) that cannot be written.
    #[error("{}: {source}", path.display())]
    #[diagnostic(code(navfn::E052))]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

impl From<CaseError> for CampaignError {
    fn from(source: CaseError) -> Self {
        CampaignError::Case { map: String::new(), source }
    }
}

impl CampaignError {
    /// Whether the cause lies outside the input: a file that cannot be read or written, an
    /// oracle that cannot be run or answers outside the contract, generator options (as
    /// opposed to input that was read and rejected).
    pub fn is_io(&self) -> bool {
        match self {
            CampaignError::Map(m) => m.is_io(),
            CampaignError::Suite(s) => s.is_io(),
            CampaignError::Write { .. } => true,
            CampaignError::Oracle(_) | CampaignError::Gen(_) | CampaignError::Shard(_) => true,
            _ => false,
        }
    }
}

/// Generator options that cannot be met.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum GenError {
    /// A category that does not exist.
    #[error("unknown category `{name}` (expected one of: {expected})")]
    #[diagnostic(code(navfn::E070))]
    UnknownCategory {
        /// The name given.
        name: String,
        /// The categories that exist.
        expected: String,
    },
    /// A size range outside 5 ≤ min ≤ max ≤ 4096.
    #[error("bad size range {0}..{1}: sizes must satisfy 5 <= min <= max <= 4096")]
    #[diagnostic(code(navfn::E071))]
    BadSize(u32, u32),
}

/// An oracle that cannot be run or whose answer cannot be read.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum OracleError {
    /// The command cannot be started.
    #[error("cannot start oracle `{cmd}`: {source}")]
    #[diagnostic(code(navfn::E080))]
    Spawn {
        /// The command.
        cmd: String,
        /// Why.
        source: std::io::Error,
    },
    /// The command exited with a failure.
    #[error("oracle `{cmd}` failed on {file} with {status}: {stderr}")]
    #[diagnostic(code(navfn::E081))]
    Failed {
        /// The command.
        cmd: String,
        /// The test file.
        file: String,
        /// Its exit status.
        status: String,
        /// The first lines of its stderr.
        stderr: String,
        /// What to try, when the call asked for more than the basic contract.
        #[help]
        hint: Option<String>,
    },
    /// The answer does not follow the contract.
    #[error("oracle `{cmd}` on {file}: {msg}")]
    #[diagnostic(code(navfn::E082))]
    Output {
        /// The command.
        cmd: String,
        /// The test file.
        file: String,
        /// What did not parse (with its line).
        msg: String,
    },
}
