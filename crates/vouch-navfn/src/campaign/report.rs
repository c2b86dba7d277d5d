//! The campaign report: what was run on which suite with which options (`identity`,
//! `ResultOptions`, `ShardSet`), mergeable per-category statistics (the optimality figures in
//! `optimality_stats.rs`), counterexamples, and how long each run took (`RunInfo`). Merging is
//! `merge.rs`; the human table `summary.rs`.
//!
//! Every statistic is a count, an integer sum (costs in millionths), a maximum, a minimum or a
//! fixed-bin histogram, and findings are kept by a total order: merging shard reports is exact,
//! and gives the same report whatever the order or grouping of the merge. Merged counts
//! saturate instead of overflowing (a crafted report cannot make a merge panic), and a report
//! read from JSON is checked for consistency before it is used.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::campaign::identity::SuiteIdentity;
use crate::campaign::names::{Failed, FindingKind, Outcome, Property, Relation};
pub use crate::campaign::optimality_stats::{OptimalityStats, RATIO_BINS};
use crate::campaign::shard::{Shard, ShardBy};
use crate::suite::RunMode;

/// Pass/fail counter of one check.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PassFail {
    /// Times it held.
    pub pass: u64,
    /// Times it failed.
    pub fail: u64,
}

impl PassFail {
    /// Counts one evaluation.
    pub fn record(&mut self, ok: bool) {
        if ok { self.pass += 1 } else { self.fail += 1 }
    }
    pub(crate) fn merge(&mut self, o: &PassFail) {
        self.pass = self.pass.saturating_add(o.pass);
        self.fail = self.fail.saturating_add(o.fail);
    }
}

/// Outcome counts (golden/README.md "Outcome statistics").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Outcomes {
    /// NavFn returned a path.
    pub found: u64,
    /// Start and goal are the same cell.
    pub start_is_goal: u64,
    /// Start not reached and not 4-connected to the goal (truly unreachable).
    pub unreachable: u64,
    /// Start connected but not reached: the propagation cycle limit cut the search short.
    pub cycle_limit: u64,
    /// Start reached but `calcPath` failed (iterations exhausted, oscillation exit, …).
    pub path_failed: u64,
}

impl Outcomes {
    /// Counts one case.
    pub fn record(&mut self, o: Outcome) {
        match o {
            Outcome::Found => self.found += 1,
            Outcome::StartIsGoal => self.start_is_goal += 1,
            Outcome::Unreachable => self.unreachable += 1,
            Outcome::CycleLimit => self.cycle_limit += 1,
            Outcome::PathFailed => self.path_failed += 1,
        }
    }

    fn merge(&mut self, o: &Outcomes) {
        self.found = self.found.saturating_add(o.found);
        self.start_is_goal = self.start_is_goal.saturating_add(o.start_is_goal);
        self.unreachable = self.unreachable.saturating_add(o.unreachable);
        self.cycle_limit = self.cycle_limit.saturating_add(o.cycle_limit);
        self.path_failed = self.path_failed.saturating_add(o.path_failed);
    }
}

/// Everything counted for one category.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CategoryStats {
    /// Maps of the category the report read (a union over merged shards).
    pub maps: u64,
    /// Cases run.
    pub cases: u64,
    /// How the cases ended.
    pub outcomes: Outcomes,
    /// Search-trace, final-state and run-time checks: property → pass/fail.
    pub checks: BTreeMap<Property, PassFail>,
    /// Metamorphic relations → held/violated (approximate ones are findings, not failures).
    pub metamorphic: BTreeMap<Relation, PassFail>,
    /// Optimality and path shape.
    pub optimality: OptimalityStats,
    /// Differential comparison with an oracle (when one was given): equal / different cases.
    pub oracle: PassFail,
    /// Largest total occupancy of the priority buffers.
    pub max_buffer_occupancy: u64,
}

impl CategoryStats {
    /// Counts one evaluation of a property.
    pub fn check(&mut self, p: Property, ok: bool) {
        self.checks.entry(p).or_default().record(ok);
    }
    /// Counts one evaluation of a relation.
    pub fn relation(&mut self, r: Relation, ok: bool) {
        self.metamorphic.entry(r).or_default().record(ok);
    }
    /// Failed properties and exact relations (oracle disagreements not included).
    pub fn hard_failures(&self) -> u64 {
        let checks = self.checks.values().map(|p| p.fail).fold(0, u64::saturating_add);
        let exact = self.metamorphic.iter().filter(|(r, _)| r.exact()).map(|(_, p)| p.fail);
        checks.saturating_add(exact.fold(0, u64::saturating_add))
    }
    /// Adds another category's counts (`maps` too: the caller decides whether they overlap).
    pub fn merge(&mut self, o: &CategoryStats) {
        self.maps = self.maps.saturating_add(o.maps);
        self.cases = self.cases.saturating_add(o.cases);
        self.outcomes.merge(&o.outcomes);
        for (k, v) in &o.checks {
            self.checks.entry(*k).or_default().merge(v);
        }
        for (k, v) in &o.metamorphic {
            self.metamorphic.entry(*k).or_default().merge(v);
        }
        self.optimality.merge(&o.optimality);
        self.oracle.merge(&o.oracle);
        self.max_buffer_occupancy = self.max_buffer_occupancy.max(o.max_buffer_occupancy);
    }
}

/// One noteworthy case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Finding {
    /// What was found.
    pub kind: FindingKind,
    /// Category folder.
    pub category: String,
    /// Map folder.
    pub map: String,
    /// Case number in its map.
    pub case: u64,
    /// `[x0, y0, x1, y1]`.
    pub coords: [u32; 4],
    /// What was seen.
    pub detail: String,
    /// Ratio navfn/optimal for optimality findings (used to rank them).
    pub score: f64,
    /// PNG written for it, if any.
    pub picture: Option<String>,
}

impl Finding {
    /// The order findings are kept in: by kind, highest score first, then by every other
    /// field (a total order).
    pub fn rank(a: &Finding, b: &Finding) -> std::cmp::Ordering {
        a.kind
            .cmp(&b.kind)
            .then(b.score.total_cmp(&a.score))
            .then_with(|| (&a.category, &a.map, a.case).cmp(&(&b.category, &b.map, b.case)))
            .then_with(|| (a.coords, &a.detail, &a.picture).cmp(&(b.coords, &b.detail, &b.picture)))
    }
}

/// How many findings of each kind a report keeps (the worst ones by score).
pub const FINDINGS_PER_KIND: usize = 25;

/// Version of the report format; `report merge` reads only this one.
pub const REPORT_FORMAT: u32 = 2;

/// The options that change what a campaign finds: reports that differ in any of them do not
/// merge.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ResultOptions {
    /// The call sequence.
    pub mode: RunMode,
    /// Metamorphic transforms run.
    pub metamorphic: bool,
    /// Optimality analysed.
    pub optimality: bool,
    /// Optimality counterexample threshold.
    pub ratio: f64,
    /// Oracle command every case was compared with, if any.
    pub oracle: Option<String>,
}

/// The shards a report covers: `indices` of `count`, split by `by`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ShardSet {
    /// `N`.
    pub count: u32,
    /// What was split.
    pub by: ShardBy,
    /// The shard indices merged into the report, ascending.
    pub indices: Vec<u32>,
}

impl Default for ShardSet {
    fn default() -> Self {
        ShardSet::of(Shard::ALL)
    }
}

impl ShardSet {
    /// The set of one shard.
    pub fn of(s: Shard) -> ShardSet {
        ShardSet { count: s.count, by: s.by, indices: vec![s.index] }
    }

    /// How many indices of `0..count` are not in the set (indices are unique and below
    /// `count` in any report that passed [`Report::inconsistency`]).
    pub fn missing_count(&self) -> u64 {
        u64::from(self.count).saturating_sub(self.indices.len() as u64)
    }

    /// The first `limit` indices of `0..count` not in the set, ascending.
    pub fn missing(&self, limit: usize) -> Vec<u32> {
        (0..self.count).filter(|i| self.indices.binary_search(i).is_err()).take(limit).collect()
    }

    /// Whether every shard is present.
    pub fn complete(&self) -> bool {
        self.missing_count() == 0
    }
}

/// One process's run: where, how long, on how many threads. Not compared by merges.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunInfo {
    /// The shard index it ran.
    pub shard: u32,
    /// The suite path as given to it.
    pub suite_path: String,
    /// Wall time, seconds.
    pub wall_seconds: f64,
    /// Worker threads.
    pub threads: usize,
    /// Time spent in each category's cases, summed over threads, seconds.
    pub cpu_seconds: BTreeMap<String, f64>,
}

/// The JSON report.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// [`REPORT_FORMAT`].
    pub format: u32,
    /// The vouch version that produced it.
    pub vouch_version: String,
    /// The suite: fingerprint, size, every map read and its digest, the content hash.
    pub suite: SuiteIdentity,
    /// The options that change results.
    pub options: ResultOptions,
    /// The shards merged into this report.
    pub shards: ShardSet,
    /// Cases run.
    pub cases: u64,
    /// Statistics per category folder.
    pub categories: BTreeMap<String, CategoryStats>,
    /// The worst findings of each kind.
    pub findings: Vec<Finding>,
    /// Each shard run, by shard index.
    pub runs: Vec<RunInfo>,
}

/// Everything the campaign says about one case (`--cases-out`, one JSON object per line).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CaseRecord {
    /// Category folder.
    pub category: String,
    /// Map folder.
    pub map: String,
    /// Case number in its map.
    pub case: u64,
    /// `[x0, y0, x1, y1]`.
    pub coords: [u32; 4],
    /// How the case ended.
    pub outcome: Outcome,
    /// Points of NavFn's path.
    pub path_points: usize,
    /// NavFn path cost (campaign model).
    pub navfn_cost: Option<f64>,
    /// Optimal 8-connected cost.
    pub optimal_cost: Option<f64>,
    /// `navfn_cost − optimal_cost`.
    pub excess: Option<f64>,
    pub obtuse_turns: u32,
    /// Sharpest turn, degrees.
    pub max_turn_deg: f64,
    /// Points equal to the point two before.
    pub oscillations: u32,
    /// Failed properties and exact relations (empty when all hold).
    pub failed: Vec<Failed>,
}

/// A report file that cannot be read back.
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum ReportError {
    /// The file cannot be read.
    #[error("{}: cannot read: {source}", path.display())]
    #[diagnostic(code(navfn::E058))]
    Io {
        /// The file.
        path: std::path::PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// Not a campaign report (JSON error with its position).
    #[error("{}:{line}:{column}: not a campaign report: {msg}", path.display())]
    #[diagnostic(code(navfn::E040))]
    Format {
        /// The file.
        path: std::path::PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What serde_json said.
        msg: String,
    },
    /// A report whose parts contradict each other (edited or damaged).
    #[error("{}: inconsistent report: {msg}", path.display())]
    #[diagnostic(code(navfn::E056))]
    Invalid {
        /// The file.
        path: std::path::PathBuf,
        /// What contradicts what.
        msg: String,
    },
    /// A report of another format version.
    #[error("{}: report format {found}, this vouch reads format {REPORT_FORMAT} (run the campaign again)", path.display())]
    #[diagnostic(code(navfn::E041))]
    Version {
        /// The file.
        path: std::path::PathBuf,
        /// Its format number (0 when absent).
        found: u32,
    },
}

impl ReportError {
    /// Whether the file could not be read at all (rather than holding something else).
    pub fn is_io(&self) -> bool {
        matches!(self, ReportError::Io { .. })
    }
}

impl Report {
    /// Reads a report file: unreadable is [`ReportError::Io`]; bytes that are not UTF-8 are
    /// rejected as not a report, located at the first bad byte.
    pub fn read(path: &Path) -> Result<Report, ReportError> {
        let bytes = std::fs::read(path)
            .map_err(|source| ReportError::Io { path: path.to_path_buf(), source })?;
        match String::from_utf8(bytes) {
            Ok(text) => Report::from_json(path, &text),
            Err(e) => {
                let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
                let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
                let column = 1 + good.iter().rev().take_while(|&&b| b != b'\n').count();
                let msg = "not UTF-8 text".to_string();
                Err(ReportError::Format { path: path.to_path_buf(), line, column, msg })
            }
        }
    }

    /// A report from its JSON text (`path` locates errors); reports of another format version
    /// are refused before their fields are read.
    pub fn from_json(path: &Path, text: &str) -> Result<Report, ReportError> {
        let format_err = |e: serde_json::Error| ReportError::Format {
            path: path.to_path_buf(),
            line: e.line(),
            column: e.column(),
            msg: e.to_string(),
        };
        #[derive(Deserialize)]
        struct Head {
            #[serde(default)]
            format: u32,
        }
        let head: Head = serde_json::from_str(text).map_err(format_err)?;
        if head.format != REPORT_FORMAT {
            return Err(ReportError::Version { path: path.to_path_buf(), found: head.format });
        }
        let report: Report = serde_json::from_str(text).map_err(format_err)?;
        match report.inconsistency() {
            Some(msg) => Err(ReportError::Invalid { path: path.to_path_buf(), msg }),
            None => Ok(report),
        }
    }

    /// What contradicts what in the report, if anything: shard indices not ascending, repeated
    /// or not below the shard count, runs of shards the report does not hold, more maps than
    /// the suite has, a case total that is not the sum of the categories', a histogram of the
    /// wrong length, a ratio below 1, another format.
    pub fn inconsistency(&self) -> Option<String> {
        let sh = &self.shards;
        let ascending = sh.indices.windows(2).all(|w| w[0] < w[1]);
        if sh.count == 0 || sh.indices.is_empty() || !ascending {
            return Some("shard indices must be ascending, unique and at least one".into());
        }
        if sh.indices.iter().any(|&i| i >= sh.count) {
            return Some(format!("a shard index is not below the shard count {}", sh.count));
        }
        if self.runs.iter().any(|r| sh.indices.binary_search(&r.shard).is_err()) {
            return Some("a run of a shard the report does not hold".into());
        }
        if self.suite.maps.len() as u64 > self.suite.maps_total {
            return Some(format!("more maps read than the suite's {}", self.suite.maps_total));
        }
        let cases = self.categories.values().map(|c| c.cases).fold(0, u64::saturating_add);
        if cases != self.cases {
            return Some(format!("{} cases, but the categories add up to {cases}", self.cases));
        }
        let bins = RATIO_BINS.len() + 1;
        if self.categories.values().any(|c| ![0, bins].contains(&c.optimality.ratio_hist.len())) {
            return Some(format!("a ratio histogram without {bins} bins"));
        }
        let ratio_ok = self.options.ratio.is_finite() && self.options.ratio >= 1.0;
        if !ratio_ok || self.format != REPORT_FORMAT {
            return Some("the ratio must be at least 1, the format 2".into());
        }
        None
    }

    /// Whether two reports say the same about the same suite: everything but which shards
    /// ran and how long they took.
    pub fn same_results(&self, o: &Report) -> bool {
        (&self.format, &self.vouch_version, &self.suite, &self.options)
            == (&o.format, &o.vouch_version, &o.suite, &o.options)
            && (self.cases, &self.categories, &self.findings)
                == (o.cases, &o.categories, &o.findings)
    }

    /// All categories added up.
    pub fn total(&self) -> CategoryStats {
        let mut t = CategoryStats::default();
        for c in self.categories.values() {
            t.merge(c);
        }
        t
    }

    /// Number of failed hard checks (search-trace properties, exact relations, oracle).
    pub fn failures(&self) -> u64 {
        let t = self.total();
        t.hard_failures().saturating_add(t.oracle.fail)
    }

    /// Keep the [`FINDINGS_PER_KIND`] first findings of each kind in [`Finding::rank`]
    /// order. The order is total, so trimming a union of trimmed lists keeps the same findings
    /// as trimming the whole.
    pub fn trim_findings(&mut self) {
        self.findings.sort_by(Finding::rank);
        self.findings.dedup();
        let mut kept = Vec::new();
        let mut count: BTreeMap<FindingKind, usize> = BTreeMap::new();
        for f in self.findings.drain(..) {
            let n = count.entry(f.kind).or_default();
            if *n < FINDINGS_PER_KIND {
                *n += 1;
                kept.push(f);
            }
        }
        self.findings = kept;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trimming_is_independent_of_order_and_grouping() {
        let f = |kind, score: f64, case: u64, detail: &str| Finding {
            kind,
            category: "c".into(),
            map: "m".into(),
            case,
            coords: [0; 4],
            detail: detail.into(),
            score,
            picture: None,
        };
        let mut all = Vec::new();
        for i in 0..60u64 {
            // equal scores and several findings per case: only the total order decides
            all.push(f(FindingKind::Suboptimal, 1.0 + (i % 7) as f64, i % 13, "x"));
            all.push(f(FindingKind::Suboptimal, 1.0 + (i % 7) as f64, i % 13, "y"));
            all.push(f(FindingKind::RelationFailed, 1.0, i, "z"));
        }
        let trim = |v: Vec<Finding>| {
            let mut r = Report { findings: v, ..Report::default() };
            r.trim_findings();
            r.findings
        };
        let whole = trim(all.clone());
        let mut rev = all.clone();
        rev.reverse();
        assert_eq!(trim(rev), whole);
        let (a, b) = all.split_at(77);
        let mut parts = trim(b.to_vec());
        parts.extend(trim(a.to_vec()));
        assert_eq!(trim(parts), whole);
        assert_eq!(whole.len(), 2 * FINDINGS_PER_KIND);
    }

    #[test]
    fn other_formats_are_refused_with_their_number() {
        let p = Path::new("r.json");
        let e = Report::from_json(p, "{\"format\": 1}").expect_err("old");
        assert!(matches!(e, ReportError::Version { found: 1, .. }), "{e}");
        let e = Report::from_json(p, "{\n \"suite\": 3\n}").expect_err("no format");
        assert!(matches!(e, ReportError::Version { found: 0, .. }), "{e}");
        let e = Report::from_json(p, "{\"format\": 2, \"cases\": \"x\"}").expect_err("bad");
        assert!(e.to_string().starts_with("r.json:1:"), "{e}");
    }
}
