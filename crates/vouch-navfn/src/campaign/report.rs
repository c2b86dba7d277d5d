//! The campaign report: mergeable per-category statistics, counterexamples, JSON, shards and
//! `report merge` (the human summary table is `summary.rs`).
//!
//! Every statistic is a count, a sum, a maximum or a fixed-bin histogram, so that the report
//! of N shards merged equals (up to float summation order) the report of one unsharded run.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::campaign::names::{Failed, FindingKind, Outcome, Property, Relation};
use crate::suite::RunMode;

/// `--shard I/N`: this process handles the cases whose global index `g` (file order over the
/// sorted suite tree, then case order) satisfies `g % N == I`. Round-robin keeps shards
/// balanced even though maps differ in size, and needs no coordination between machines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// `I`, from 0.
    pub index: u32,
    /// `N`.
    pub count: u32,
}

impl Shard {
    /// The whole suite (shard 0 of 1).
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parse `I/N` with `0 <= I < N`.
    pub fn parse(s: &str) -> Result<Shard, String> {
        let (i, n) =
            s.split_once('/').ok_or_else(|| format!("shard `{s}`: expected I/N, e.g. 0/4"))?;
        let index: u32 = i.trim().parse().map_err(|_| format!("shard `{s}`: bad index `{i}`"))?;
        let count: u32 = n.trim().parse().map_err(|_| format!("shard `{s}`: bad count `{n}`"))?;
        if count == 0 || index >= count {
            return Err(format!("shard `{s}`: need 0 <= I < N"));
        }
        Ok(Shard { index, count })
    }

    /// Whether this shard runs the case of global index `global_case`.
    pub fn owns(self, global_case: u64) -> bool {
        global_case % u64::from(self.count) == u64::from(self.index)
    }
}

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
        if ok {
            self.pass += 1
        } else {
            self.fail += 1
        }
    }
    fn merge(&mut self, o: &PassFail) {
        self.pass += o.pass;
        self.fail += o.fail;
    }
}

/// Histogram bins of the optimality ratio `navfn_cost / optimal_cost`.
pub const RATIO_BINS: [f64; 9] = [0.95, 1.0, 1.01, 1.05, 1.0825, 1.10, 1.25, 1.5, 2.0];

/// Optimality statistics over cases where NavFn found a path and start ≠ goal.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct OptimalityStats {
    /// Paths compared with the optimum.
    pub compared: u64,
    /// Sum of NavFn path costs (campaign model).
    pub navfn_cost_sum: f64,
    /// Sum of the optimal costs.
    pub optimal_cost_sum: f64,
    /// Largest `navfn − optimal` and the smallest (negative: any-angle path beat the grid).
    pub excess_max: f64,
    /// Smallest `navfn − optimal`.
    pub excess_min: f64,
    /// Largest `navfn / optimal`.
    pub ratio_max: f64,
    /// Counts of ratios below each of [`RATIO_BINS`], plus one more for "≥ last".
    pub ratio_hist: Vec<u64>,
    /// Paths with at least one turn sharper than 90° (oscillating paths excluded, as in the paper).
    pub obtuse_paths: u64,
    /// Paths in which NavFn's oscillation test fired (recorded points, found or not).
    pub oscillating_paths: u64,
    /// Found paths that are counterexamples to optimality (ratio above the threshold).
    pub suboptimal_paths: u64,
}

impl OptimalityStats {
    /// Counts one compared path.
    pub fn record(&mut self, navfn: f64, optimal: f64) {
        if self.ratio_hist.is_empty() {
            self.ratio_hist = vec![0; RATIO_BINS.len() + 1];
            self.excess_min = f64::INFINITY;
        }
        self.compared += 1;
        self.navfn_cost_sum += navfn;
        self.optimal_cost_sum += optimal;
        let excess = navfn - optimal;
        self.excess_max = self.excess_max.max(excess);
        self.excess_min = self.excess_min.min(excess);
        let ratio = if optimal > 0.0 { navfn / optimal } else { 1.0 };
        self.ratio_max = self.ratio_max.max(ratio);
        let bin = RATIO_BINS.iter().position(|&b| ratio < b).unwrap_or(RATIO_BINS.len());
        self.ratio_hist[bin] += 1;
    }

    fn merge(&mut self, o: &OptimalityStats) {
        if o.compared > 0 {
            if self.ratio_hist.is_empty() {
                self.ratio_hist = vec![0; RATIO_BINS.len() + 1];
                self.excess_min = f64::INFINITY;
            }
            for (a, b) in self.ratio_hist.iter_mut().zip(&o.ratio_hist) {
                *a += b;
            }
            self.excess_max = self.excess_max.max(o.excess_max);
            self.excess_min = self.excess_min.min(o.excess_min);
            self.ratio_max = self.ratio_max.max(o.ratio_max);
        }
        self.compared += o.compared;
        self.navfn_cost_sum += o.navfn_cost_sum;
        self.optimal_cost_sum += o.optimal_cost_sum;
        self.obtuse_paths += o.obtuse_paths;
        self.oscillating_paths += o.oscillating_paths;
        self.suboptimal_paths += o.suboptimal_paths;
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
        self.found += o.found;
        self.start_is_goal += o.start_is_goal;
        self.unreachable += o.unreachable;
        self.cycle_limit += o.cycle_limit;
        self.path_failed += o.path_failed;
    }
}

/// Everything counted for one category.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CategoryStats {
    /// Maps of the category (in this shard).
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
    /// CPU time spent in this category's cases, summed over threads (seconds).
    pub cpu_seconds: f64,
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
        let checks: u64 = self.checks.values().map(|p| p.fail).sum();
        let exact: u64 =
            self.metamorphic.iter().filter(|(r, _)| r.exact()).map(|(_, p)| p.fail).sum();
        checks + exact
    }
    /// Adds another category's counts.
    pub fn merge(&mut self, o: &CategoryStats) {
        self.maps += o.maps;
        self.cases += o.cases;
        self.outcomes.merge(&o.outcomes);
        for (k, v) in &o.checks {
            self.checks.entry(*k).or_default().merge(v);
        }
        for (k, v) in &o.metamorphic {
            self.metamorphic.entry(*k).or_default().merge(v);
        }
        self.optimality.merge(&o.optimality);
        self.oracle.merge(&o.oracle);
        self.cpu_seconds += o.cpu_seconds;
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

/// How many findings of each kind a report keeps (the worst ones by score).
pub const FINDINGS_PER_KIND: usize = 25;

/// The JSON report.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Report {
    /// The suite folder.
    pub suite: String,
    /// The call sequence.
    pub mode: RunMode,
    /// Shards merged into this report (one entry per shard run).
    pub shards: Vec<Shard>,
    pub cases: u64,
    /// Wall time of each shard run, seconds.
    pub wall_seconds: Vec<f64>,
    /// Worker threads of each shard run.
    pub threads: Vec<usize>,
    /// Statistics per category folder.
    pub categories: BTreeMap<String, CategoryStats>,
    /// The worst findings of each kind.
    pub findings: Vec<Finding>,
    /// One record per case when asked for (`campaign --cases-out`); written as JSON lines, not
    /// part of the JSON report (and not merged).
    #[serde(skip)]
    pub per_case: Vec<CaseRecord>,
}

/// Everything the campaign says about one case (`--cases-out`, one JSON object per line).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CaseRecord {
    /// Global index (suite file order, then case order): the key shards split on.
    pub global: u64,
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
    /// Reports that cannot be merged.
    #[error("{0}")]
    #[diagnostic(code(navfn::E041))]
    Merge(String),
}

impl Report {
    /// A report from its JSON text (`path` locates errors).
    pub fn from_json(path: &Path, text: &str) -> Result<Report, ReportError> {
        serde_json::from_str(text).map_err(|e| ReportError::Format {
            path: path.to_path_buf(),
            line: e.line(),
            column: e.column(),
            msg: e.to_string(),
        })
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
        t.hard_failures() + t.oracle.fail
    }

    /// Keep the [`FINDINGS_PER_KIND`] highest-scoring findings of each kind, in a stable order.
    pub fn trim_findings(&mut self) {
        self.findings.sort_by(|a, b| {
            a.kind
                .cmp(&b.kind)
                .then(b.score.total_cmp(&a.score))
                .then(a.category.cmp(&b.category))
                .then(a.map.cmp(&b.map))
                .then(a.case.cmp(&b.case))
        });
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

    /// `vouch navfn report merge`: join shard reports of the same suite and mode.
    pub fn merge(reports: &[Report]) -> Result<Report, ReportError> {
        let merge_err = |m: String| ReportError::Merge(m);
        let first = reports.first().ok_or_else(|| merge_err("no reports to merge".into()))?;
        let mut out = Report { suite: first.suite.clone(), mode: first.mode, ..Report::default() };
        for r in reports {
            if r.suite != first.suite || r.mode != first.mode {
                return Err(merge_err(format!(
                    "cannot merge a report of `{}` ({}) with one of `{}` ({})",
                    r.suite,
                    r.mode.name(),
                    first.suite,
                    first.mode.name()
                )));
            }
            for s in &r.shards {
                if out.shards.contains(s) {
                    return Err(merge_err(format!("shard {}/{} appears twice", s.index, s.count)));
                }
            }
            out.shards.extend(r.shards.iter().copied());
            out.cases += r.cases;
            out.wall_seconds.extend(r.wall_seconds.iter().copied());
            out.threads.extend(r.threads.iter().copied());
            for (k, v) in &r.categories {
                let e = out.categories.entry(k.clone()).or_default();
                // A map seen by several shards is counted once per shard; keep the largest.
                let maps = e.maps.max(v.maps);
                e.merge(v);
                e.maps = maps;
            }
            out.findings.extend(r.findings.iter().cloned());
        }
        out.shards.sort_by_key(|s| (s.count, s.index));
        out.trim_findings();
        Ok(out)
    }

    /// Whether the shards form a complete partition (every index of one count present once).
    pub fn complete(&self) -> bool {
        let Some(n) = self.shards.first().map(|s| s.count) else { return false };
        self.shards.len() == n as usize && self.shards.iter().all(|s| s.count == n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shard_parse_and_ownership_partition_cases() {
        assert!(Shard::parse("3/3").is_err());
        assert!(Shard::parse("x").is_err());
        let shards: Vec<Shard> =
            (0..4).map(|i| Shard::parse(&format!("{i}/4")).expect("valid")).collect();
        for g in 0..1000u64 {
            assert_eq!(shards.iter().filter(|s| s.owns(g)).count(), 1);
        }
    }

    #[test]
    fn merge_adds_counts_and_rejects_duplicates() {
        let mut a = Report {
            suite: "s".into(),
            mode: RunMode::Paper,
            shards: vec![Shard { index: 0, count: 2 }],
            cases: 3,
            ..Report::default()
        };
        let mut c = CategoryStats { maps: 1, cases: 3, ..Default::default() };
        c.check(Property::Progress, true);
        c.optimality.record(110.0, 100.0);
        a.categories.insert("free".into(), c);
        let mut b = a.clone();
        b.shards = vec![Shard { index: 1, count: 2 }];
        let m = Report::merge(&[a.clone(), b]).expect("merges");
        assert!(m.complete());
        assert_eq!(m.cases, 6);
        let f = &m.categories["free"];
        assert_eq!(f.checks[&Property::Progress], PassFail { pass: 2, fail: 0 });
        assert_eq!(f.optimality.compared, 2);
        assert_eq!(f.maps, 1);
        assert!(Report::merge(&[a.clone(), a]).is_err());
    }
}
