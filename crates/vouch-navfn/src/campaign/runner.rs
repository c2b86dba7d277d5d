//! `vouch navfn campaign`: every case of a suite (or of one shard of it) through NavFn with the
//! checks of `evaluate`, in parallel (rayon), into a mergeable [`Report`].
//!
//! The suite is **streamed**: the tree is walked one folder at a time, the maps this shard reads
//! are loaded a small batch at a time, their units run in waves of a few per thread, and every
//! wave's per-case records go to the [`CaseSink`] in suite order before the next wave starts.
//! A map is dropped as soon as its cases are done. Memory is therefore the batch and the wave
//! (a constant) plus the report, whose only part that grows is the digest of each map read —
//! a shard's share. Progress goes to a [`Progress`]; the library draws nothing.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;

use crate::campaign::error::CampaignError;
pub use crate::campaign::evaluate::{CampaignOptions, PreparedMap, prepare, to_pairs};
use crate::campaign::evaluate::{UnitResult, run_unit};
use crate::campaign::identity::{IdentityBasis, ListingFingerprint, MapDigest, read_manifest};
use crate::campaign::merge::count_maps;
use crate::campaign::report::{
    CaseRecord, REPORT_FORMAT, Report, ResultOptions, RunInfo, ShardSet,
};
use crate::campaign::shard::{Shard, ShardBy};
use crate::campaign::suite_io::{SuiteEntry, no_test_files, read_entry_with_digest, walk_suite};
use crate::maps::MapError;

/// Receives progress from the worker threads.
pub trait Progress: Sync {
    /// `cases` more cases were found to run (maps are discovered as the suite streams by).
    fn found(&self, _cases: u64) {}
    /// `cases` more cases are done.
    fn advance(&self, _cases: u64) {}
}

/// No progress reporting.
impl Progress for () {}

/// Receives one record per case run, in suite order (map walk order, then case order).
pub trait CaseSink {
    /// One more record.
    fn accept(&mut self, record: CaseRecord) -> Result<(), CampaignError>;
}

/// Keeps the records in memory.
impl CaseSink for Vec<CaseRecord> {
    fn accept(&mut self, record: CaseRecord) -> Result<(), CampaignError> {
        self.push(record);
        Ok(())
    }
}

/// The version written into reports.
pub const VOUCH_VERSION: &str = env!("CARGO_PKG_VERSION");

/// One map of the current batch, read.
struct Loaded {
    key: String,
    digest: MapDigest,
    /// Cases of it this shard runs.
    owned: u64,
    /// The prepared map, when this shard runs some of its cases.
    map: Option<PreparedMap>,
    /// Whether the report lists it (this shard runs some of its cases, or is its home).
    listed: bool,
}

fn load(entry: &SuiteEntry, home: u32, opts: &CampaignOptions) -> Result<Loaded, CampaignError> {
    let (map, sha256) = read_entry_with_digest(entry)?;
    let cases = map.cases.len() as u64;
    let owned = (0..cases).filter(|&k| opts.shard.owns_case(home, k)).count() as u64;
    let digest = MapDigest { category: map.category.clone(), cases, sha256 };
    let prepared = (owned > 0).then(|| PreparedMap {
        key: entry.key.clone(),
        home,
        ..prepare(map, opts.metamorphic)
    });
    let listed = owned > 0 || home == opts.shard.index;
    Ok(Loaded { key: entry.key.clone(), digest, owned, map: prepared, listed })
}

/// The report being built, and where the records go.
struct Builder<'a, 's> {
    opts: &'a CampaignOptions,
    progress: &'a dyn Progress,
    sink: Option<&'s mut dyn CaseSink>,
    report: Report,
    cpu: BTreeMap<String, f64>,
    /// Units run in parallel before their records are written.
    wave: usize,
}

impl Builder<'_, '_> {
    /// Load a batch of maps, run their units wave by wave, write the records.
    fn batch(&mut self, entries: &[(SuiteEntry, u32)]) -> Result<(), CampaignError> {
        let opts = self.opts;
        let loaded: Vec<Loaded> =
            entries.par_iter().map(|(e, home)| load(e, *home, opts)).collect::<Result<_, _>>()?;
        for l in &loaded {
            if l.listed {
                self.report.categories.entry(l.digest.category.clone()).or_default();
                self.report.suite.maps.insert(l.key.clone(), l.digest.clone());
            }
            self.progress.found(l.owned);
        }
        let step = opts.unit_cases.max(1);
        let units: Vec<(&PreparedMap, std::ops::Range<usize>)> = loaded
            .iter()
            .filter_map(|l| l.map.as_ref())
            .flat_map(|pm| {
                let n = pm.map.cases.len();
                (0..n).step_by(step).map(move |s| (pm, s..(s + step).min(n)))
            })
            .collect();
        let (per_case, progress) = (self.sink.is_some(), self.progress);
        for wave in units.chunks(self.wave) {
            let results: Vec<UnitResult> = wave
                .par_iter()
                .map(|(pm, range)| {
                    let r = run_unit(pm, range.clone(), opts, per_case)?;
                    progress.advance(r.stats.cases);
                    Ok(r)
                })
                .collect::<Result<_, CampaignError>>()?;
            for r in results {
                self.add(r)?;
            }
            self.report.trim_findings();
        }
        Ok(())
    }

    fn add(&mut self, r: UnitResult) -> Result<(), CampaignError> {
        self.report.cases += r.stats.cases;
        self.report.categories.entry(r.category.clone()).or_default().merge(&r.stats);
        self.report.findings.extend(r.findings);
        *self.cpu.entry(r.category).or_default() += r.seconds;
        if let Some(sink) = self.sink.as_deref_mut() {
            for rec in r.records {
                sink.accept(rec)?;
            }
        }
        Ok(())
    }
}

/// Run the campaign on the suite at `dir` (a folder, or one test file); per-case records go to
/// `sink` when one is given.
pub fn run_campaign(
    dir: &Path,
    opts: &CampaignOptions,
    progress: &dyn Progress,
    sink: Option<&mut dyn CaseSink>,
) -> Result<Report, CampaignError> {
    let began = Instant::now();
    let manifest = read_manifest(dir)?;
    let threads = rayon::current_num_threads();
    let report = Report {
        format: REPORT_FORMAT,
        vouch_version: VOUCH_VERSION.to_string(),
        options: ResultOptions {
            mode: opts.mode,
            metamorphic: opts.metamorphic,
            optimality: opts.optimality,
            ratio: opts.suboptimal_ratio,
            oracle: None,
        },
        shards: ShardSet::of(opts.shard),
        ..Report::default()
    };
    let mut b =
        Builder { opts, progress, sink, report, cpu: BTreeMap::new(), wave: 4 * threads.max(1) };
    let batch_maps = 4 * threads.max(2);
    let mut listing = ListingFingerprint::default();
    let mut pending = Vec::with_capacity(batch_maps);
    for entry in walk_suite(dir)? {
        let entry = entry?;
        listing.add(&entry.key, entry.test_size);
        let home = Shard::home(&entry.key, opts.shard.count);
        if opts.shard.reads(home) {
            pending.push((entry, home));
        }
        if pending.len() >= batch_maps {
            b.batch(&pending)?;
            pending.clear();
        }
    }
    // A share of a generated suite may hold no map at all (more shards than maps); it still
    // reports, so that the merge sees every shard.
    if listing.maps() == 0 && manifest.is_none() {
        return Err(no_test_files(dir).into());
    }
    b.batch(&pending)?;
    let mut report = b.report;
    // The whole suite without a case would pass vacuously (one shard of it may hold none).
    if report.cases == 0 && opts.shard.count == 1 {
        return Err(MapError::file(dir, "the suite holds no case: nothing to check").into());
    }
    let suite = &mut report.suite;
    match manifest {
        Some((fingerprint, maps_total)) => {
            check_share(dir, listing.maps(), maps_total, opts.shard)?;
            (suite.basis, suite.fingerprint, suite.maps_total) =
                (IdentityBasis::Manifest, fingerprint, maps_total);
        }
        None => {
            suite.maps_total = listing.maps();
            (suite.basis, suite.fingerprint) = (IdentityBasis::Listing, listing.finish());
        }
    }
    suite.seal();
    count_maps(&mut report.categories, &report.suite.maps);
    report.trim_findings();
    report.runs.push(RunInfo {
        shard: opts.shard.index,
        suite_path: dir.display().to_string(),
        wall_seconds: began.elapsed().as_secs_f64(),
        threads,
        cpu_seconds: b.cpu,
    });
    Ok(report)
}

/// A folder with a manifest may hold one share of a generated suite (`suite gen --shard`):
/// never more maps than the manifest counts, and a share is run split by map.
fn check_share(dir: &Path, listed: u64, total: u64, shard: Shard) -> Result<(), CampaignError> {
    let msg = if listed > total {
        format!("holds {listed} maps, more than the {total} its suite manifest counts")
    } else if listed < total && shard.by == ShardBy::Case {
        format!(
            "holds {listed} of the suite's {total} maps (a share of a generated suite): \
             run it with --shard-by map and the share's --shard I/N"
        )
    } else {
        return Ok(());
    };
    Err(CampaignError::Share { dir: dir.to_path_buf(), msg })
}
