//! The benchmark harness behind `vouch navfn bench` (compiled only with the crate's `bench`
//! feature, which the CLI enables; nothing else in the crate uses it). It returns figures and
//! prints nothing.
//!
//! Every figure is measured in the run. With an oracle (an external NavFn speaking the oracle
//! contract, docs/navfn-campaign.md) both sides are measured on the same inputs, alternating
//! pass by pass (vouch first in even passes, the oracle first in odd ones). Workloads, for each
//! call sequence:
//! * planning: the planning calls only (array set-up, cost input, propagation, path
//!   extraction), best of `repeat` in-process repetitions per test file, thread CPU time, summed
//!   over the files — each side in its own process answering the contract's `--time-planning`
//!   extension;
//! * whole process (parse, plan, hash, print): one test file per process and the whole folder
//!   in one process for a suite, one process per map for the scale maps; CPU time of the
//!   process;
//! * scale: random-cost maps of the given sides, corner to corner, and cases of growing
//!   length on one map (explored cells), time and peak resident set;
//! * inflation: nav2's inflation layer update on generated static layers (`inflation.rs`),
//!   against an external layer given with `inflation_oracle`.

mod inflation;
mod scale;
mod side;
mod timing;

use std::path::{Path, PathBuf};

pub use side::{Side, SideName, TimeLine, peak_rss_kb};
pub use timing::{planner_rows, time_planning};

use crate::maps::{MapError, find_test_files};
use crate::planner::PlanError;
use crate::suite::RunMode;

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// Suite to time: a test file or a folder searched for `test.txt` (raw NavFn costs).
    pub suite: Option<PathBuf>,
    /// The external implementation (a command line, split into words like a shell would).
    pub oracle: Option<String>,
    /// The `vouch` executable that answers vouch's side (normally the running one).
    pub vouch_exe: PathBuf,
    /// Call sequences to time.
    pub modes: Vec<RunMode>,
    /// Passes; the median and minimum over them are reported.
    pub passes: usize,
    /// In-process repetitions of each test file's planning per pass (the best one counts).
    pub repeat: usize,
    /// Measure whole processes too.
    pub process: bool,
    /// Sides of the random-cost scale maps (cells).
    pub scale: Vec<usize>,
    /// Where the scale maps are written (`None`: a temporary folder, removed afterwards).
    pub scale_dir: Option<PathBuf>,
    /// Seed of the random costs.
    pub seed: u64,
    /// Sides of the static layers of the inflation workload (cells).
    pub inflation: Vec<usize>,
    /// The external inflation layer (a command line, split into words like a shell would).
    pub inflation_oracle: Option<String>,
}

/// The unit of a row's samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Unit {
    /// Planning time per case, microseconds.
    #[serde(rename = "µs/case")]
    MicrosPerCase,
    /// CPU time of the processes, milliseconds.
    #[serde(rename = "ms CPU")]
    MsCpu,
    /// Planning time per plan, milliseconds.
    #[serde(rename = "ms/plan")]
    MsPerPlan,
    /// Time of one full-map inflation update, milliseconds.
    #[serde(rename = "ms/update")]
    MsPerUpdate,
}

impl Unit {
    /// How the unit is printed.
    pub fn as_str(self) -> &'static str {
        match self {
            Unit::MicrosPerCase => "µs/case",
            Unit::MsCpu => "ms CPU",
            Unit::MsPerPlan => "ms/plan",
            Unit::MsPerUpdate => "ms/update",
        }
    }
}

/// One measured workload: a sample per pass and side.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Row {
    /// What was timed.
    pub workload: String,
    /// Cases, processes, or explored cells (scale rows).
    pub count: u64,
    /// Unit of the samples.
    pub unit: Unit,
    /// vouch's samples, one per pass.
    pub vouch: Vec<f64>,
    /// The oracle's samples (empty without an oracle).
    pub oracle: Vec<f64>,
    /// Peak resident set of vouch's process, KiB.
    pub vouch_peak_rss_kb: Option<u64>,
    /// Peak resident set of the oracle's process, KiB.
    pub oracle_peak_rss_kb: Option<u64>,
    /// Peak resident set before the input was read, where the side reports it.
    pub vouch_start_rss_kb: Option<u64>,
    /// The same for the oracle.
    pub oracle_start_rss_kb: Option<u64>,
}

impl Row {
    fn new(workload: String, count: u64, unit: Unit) -> Row {
        Row {
            workload,
            count,
            unit,
            vouch: Vec::new(),
            oracle: Vec::new(),
            vouch_peak_rss_kb: None,
            oracle_peak_rss_kb: None,
            vouch_start_rss_kb: None,
            oracle_start_rss_kb: None,
        }
    }
}

/// Why a benchmark stopped.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum BenchError {
    /// A suite or map could not be read.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Input(#[from] MapError),
    /// The planner refused the planner request.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Plan(#[from] PlanError),
    /// No test file below the suite path.
    #[error("no test.txt below {}", .0.display())]
    #[diagnostic(code(navfn::E090))]
    NoTestFiles(PathBuf),
    /// The oracle command line does not split into words.
    #[error("oracle command `{0}` is empty or has an unbalanced quote")]
    #[diagnostic(code(navfn::E091))]
    OracleCommand(String),
    /// A side failed on a target.
    #[error("{} failed on {}: {message}", side.as_str(), target.display())]
    #[diagnostic(code(navfn::E092))]
    Side {
        /// Which side.
        side: SideName,
        /// The test file or folder.
        target: PathBuf,
        /// What happened (exit status and the first lines of its stderr).
        message: String,
    },
    /// The inflation workload's layer could not be built.
    #[error("inflation layer: {0}")]
    #[diagnostic(code(navfn::E094))]
    Inflation(String),
    /// A generated input could not be written.
    #[error("{}: {source}", path.display())]
    #[diagnostic(code(navfn::E093))]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
}

impl BenchError {
    fn io(path: &Path, source: std::io::Error) -> BenchError {
        BenchError::Io { path: path.to_path_buf(), source }
    }
}

/// Median of the samples (NaN for none).
pub fn median(samples: &[f64]) -> f64 {
    let mut s = samples.to_vec();
    s.sort_by(f64::total_cmp);
    match s.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => s[n / 2],
        n => (s[n / 2 - 1] + s[n / 2]) / 2.0,
    }
}

/// Minimum of the samples (infinity for none).
pub fn minimum(samples: &[f64]) -> f64 {
    samples.iter().copied().fold(f64::INFINITY, f64::min)
}

/// Runs every workload of `cfg`; `note` receives a line at the start of each.
pub fn run(cfg: &BenchConfig, note: &mut dyn FnMut(String)) -> Result<Vec<Row>, BenchError> {
    let oracle = cfg.oracle.as_deref().map(Side::oracle).transpose()?;
    let mut b = Bench { cfg, vouch: Side::vouch(&cfg.vouch_exe), oracle, rows: Vec::new() };
    if let Some(suite) = &cfg.suite {
        b.suite_rows(suite, note)?;
    }
    if !cfg.scale.is_empty() {
        b.scale_rows(note)?;
    }
    if !cfg.inflation.is_empty() {
        b.inflation_rows(note)?;
    }
    Ok(b.rows)
}

/// A fresh private folder (mode 0700, a name no other user can predict or plant) for generated
/// inputs, removed when dropped.
fn private_dir() -> Result<tempfile::TempDir, BenchError> {
    tempfile::Builder::new()
        .prefix("vouch-bench-")
        .tempdir()
        .map_err(|e| BenchError::io(&std::env::temp_dir(), e))
}

struct Bench<'a> {
    cfg: &'a BenchConfig,
    vouch: Side,
    oracle: Option<Side>,
    rows: Vec<Row>,
}

/// The contract's `--mode`/`--algo` arguments of a sequence.
fn contract_args(mode: RunMode) -> Vec<String> {
    mode.args().iter().map(|s| s.to_string()).collect()
}

impl Bench<'_> {
    fn passes(&self) -> usize {
        self.cfg.passes.max(1)
    }

    /// The sides of a pass in the order they run: alternating, so that neither always goes
    /// first.
    fn pass_order(&self, pass: usize) -> Vec<&Side> {
        match &self.oracle {
            Some(o) if pass % 2 == 1 => vec![o, &self.vouch],
            Some(o) => vec![&self.vouch, o],
            None => vec![&self.vouch],
        }
    }

    /// Planning, one-file-per-process and whole-folder rows for every mode.
    fn suite_rows(&mut self, suite: &Path, note: &mut dyn FnMut(String)) -> Result<(), BenchError> {
        let files = find_test_files(suite, "test.txt")?;
        if files.is_empty() {
            return Err(BenchError::NoTestFiles(suite.to_path_buf()));
        }
        let n = files.len();
        for &mode in &self.cfg.modes {
            let args = contract_args(mode);
            let name = mode.name();
            note(format!("bench: {name}: planning, {n} files"));
            let (row, _) = self.planning(format!("planning {name} ({n} files)"), &args, &files)?;
            self.rows.push(row);
            if !self.cfg.process {
                continue;
            }
            if let Some(equal) = self.same_answers(&args, &files)? {
                note(format!("bench: {name}: CASE/PATH lines identical on {equal} of {n} files"));
            }
            note(format!("bench: {name}: whole processes"));
            let label = format!("process {name}, one file per process ({n})");
            let row = self.process(label, &args, &files)?;
            self.rows.push(row);
            let label = format!("process {name}, whole folder in one process");
            let row = self.process(label, &args, &[suite.to_path_buf()])?;
            self.rows.push(row);
        }
        Ok(())
    }

    /// On how many targets both sides printed the same CASE/PATH lines (`None` without an
    /// oracle).
    fn same_answers(
        &self,
        args: &[String],
        targets: &[PathBuf],
    ) -> Result<Option<usize>, BenchError> {
        let Some(o) = &self.oracle else { return Ok(None) };
        let mut equal = 0;
        for t in targets {
            equal += (self.vouch.answer_lines(args, t)? == o.answer_lines(args, t)?) as usize;
        }
        Ok(Some(equal))
    }

    /// Planning time per case (µs), interleaved passes; returns the row and vouch's last lines.
    fn planning(
        &self,
        label: String,
        args: &[String],
        files: &[PathBuf],
    ) -> Result<(Row, Vec<TimeLine>), BenchError> {
        let mut row = Row::new(label, 0, Unit::MicrosPerCase);
        let mut last = Vec::new();
        for pass in 0..self.passes() {
            for side in self.pass_order(pass) {
                let mut lines = Vec::new();
                for f in files {
                    lines.extend(side.time_planning(args, self.cfg.repeat.max(1), f)?);
                }
                let total_ns: f64 = lines.iter().map(|t| t.best_ns).sum();
                let cases: u64 = lines.iter().map(|t| t.cases).sum();
                let rss = lines.iter().map(|t| t.maxrss_kb).max().unwrap_or(0);
                let start = lines.iter().filter_map(|t| t.start_rss_kb).min();
                let per_case_us = total_ns / 1e3 / cases.max(1) as f64;
                if side.name == SideName::Vouch {
                    row.count = cases;
                    row.vouch.push(per_case_us);
                    row.vouch_peak_rss_kb = Some(row.vouch_peak_rss_kb.unwrap_or(0).max(rss));
                    row.vouch_start_rss_kb = start;
                    last = lines;
                } else {
                    row.oracle.push(per_case_us);
                    row.oracle_peak_rss_kb = Some(row.oracle_peak_rss_kb.unwrap_or(0).max(rss));
                    row.oracle_start_rss_kb = start;
                }
            }
        }
        Ok((row, last))
    }

    /// Whole-process CPU time (ms) of one process per target, summed, interleaved passes.
    fn process(
        &self,
        label: String,
        args: &[String],
        targets: &[PathBuf],
    ) -> Result<Row, BenchError> {
        let mut row = Row::new(label, targets.len() as u64, Unit::MsCpu);
        for pass in 0..self.passes() {
            for side in self.pass_order(pass) {
                let mut total = 0.0;
                for t in targets {
                    total += side.process_cpu(args, t)?;
                }
                match side.name {
                    SideName::Vouch => row.vouch.push(total * 1e3),
                    SideName::Oracle => row.oracle.push(total * 1e3),
                }
            }
        }
        Ok(row)
    }

    /// Random-cost maps: time and peak memory against map size and against explored cells,
    /// and whole processes, one per map.
    fn scale_rows(&mut self, note: &mut dyn FnMut(String)) -> Result<(), BenchError> {
        let mut sides = self.cfg.scale.clone();
        sides.retain(|&s| s >= 3);
        sides.sort_unstable();
        sides.dedup();
        let explore = sides.iter().copied().filter(|&s| s <= 2000).max();
        // without --scale-dir the maps go to a fresh private directory
        let temporary = match &self.cfg.scale_dir {
            Some(_) => None,
            None => Some(private_dir()?),
        };
        let root = match &temporary {
            Some(t) => t.path().to_path_buf(),
            None => self.cfg.scale_dir.clone().unwrap_or_default(),
        };
        scale::generate(&root, &sides, explore, self.cfg.seed)
            .and_then(|(by_size, by_distance)| self.scale_workloads(&by_size, &by_distance, note))
    }

    /// The inflation update on generated static layers, vouch and the external layer
    /// alternating.
    fn inflation_rows(&mut self, note: &mut dyn FnMut(String)) -> Result<(), BenchError> {
        let oracle = match &self.cfg.inflation_oracle {
            Some(cmd) => Some(
                shlex::split(cmd)
                    .filter(|w| !w.is_empty())
                    .ok_or_else(|| BenchError::OracleCommand(cmd.clone()))?,
            ),
            None => None,
        };
        let dir = private_dir()?;
        let settings = (self.passes(), self.cfg.repeat, self.cfg.seed);
        let rows =
            inflation::rows(dir.path(), &self.cfg.inflation, oracle.as_deref(), settings, note)?;
        self.rows.extend(rows);
        Ok(())
    }

    fn scale_workloads(
        &mut self,
        by_size: &[scale::ScaleInput],
        by_distance: &[scale::ScaleInput],
        note: &mut dyn FnMut(String),
    ) -> Result<(), BenchError> {
        for &mode in &self.cfg.modes {
            let args = contract_args(mode);
            let name = mode.name();
            for input in by_size.iter().chain(by_distance) {
                note(format!("bench: scale {name} {}", input.label));
                let files = [input.test.clone()];
                let (mut row, lines) =
                    self.planning(format!("scale {name} {}", input.label), &args, &files)?;
                // one case per file: µs per case → ms per plan
                for s in row.vouch.iter_mut().chain(row.oracle.iter_mut()) {
                    *s /= 1e3;
                }
                row.unit = Unit::MsPerPlan;
                row.count = lines.iter().filter_map(|t| t.explored).sum();
                self.rows.push(row);
            }
            if !self.cfg.process {
                continue;
            }
            for input in by_size {
                let files = [input.test.clone()];
                if let Some(equal) = self.same_answers(&args, &files)? {
                    let same = if equal == 1 { "identical" } else { "DIFFERENT" };
                    note(format!("bench: scale {name} {}: CASE/PATH lines {same}", input.label));
                }
                note(format!("bench: process {name} {}", input.label));
                let label = format!("process {name} {}, one process per map", input.label);
                let row = self.process(label, &args, &files)?;
                self.rows.push(row);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::{median, minimum};

    #[test]
    fn median_and_minimum() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&[]).is_nan());
        assert_eq!(minimum(&[3.0, 1.0, 2.0]), 1.0);
    }
}
