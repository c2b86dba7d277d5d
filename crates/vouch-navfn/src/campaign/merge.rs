//! `report merge`: join shard reports into one — strictly. Reports merge only when they come
//! from the same vouch, the same options and the same suite (fingerprint, size, and the same
//! digest wherever two shards read the same map); a shard never appears twice; an incomplete
//! set (a shard index missing, a map of the suite not read by any shard, fewer cases run than
//! the maps hold) is refused unless the caller allows a partial merge. Maps are counted as the
//! union of the maps the shards read. The result does not depend on the order or grouping of
//! the inputs: every field is a union, an exact sum or a total-order selection.

use std::collections::{BTreeMap, BTreeSet};

use crate::campaign::report::{CategoryStats, Report, ShardSet};

/// Why reports do not merge.
#[derive(Debug, PartialEq, Eq, thiserror::Error, miette::Diagnostic)]
pub enum MergeError {
    /// Nothing to merge.
    #[error("no reports to merge")]
    #[diagnostic(code(navfn::E042))]
    Empty,
    /// Reports of different vouch versions.
    #[error("reports of different vouch versions: {0} and {1}")]
    #[diagnostic(code(navfn::E043))]
    Version(String, String),
    /// Reports run with different options.
    #[error("reports run with different options: {0} and {1}")]
    #[diagnostic(
        code(navfn::E044),
        help(
            "every shard must run with the same --mode/--algo, --ratio, --no-metamorphic, --no-optimality and --oracle"
        )
    )]
    Options(String, String),
    /// Reports of different suites.
    #[error("reports of different suites: {0} and {1}")]
    #[diagnostic(code(navfn::E045))]
    Suite(String, String),
    /// Two shards read different contents for the same map.
    #[error("map `{key}` differs between the shards: {a} and {b}")]
    #[diagnostic(code(navfn::E046))]
    MapContent {
        /// The map's key.
        key: String,
        /// One digest (with its category and case count).
        a: String,
        /// The other.
        b: String,
    },
    /// Shards of different splits (mixed N or mixed --shard-by).
    #[error("shards of different splits: {0} and {1}")]
    #[diagnostic(code(navfn::E047), help("merge the shards of one `--shard I/N --shard-by …` run"))]
    Split(String, String),
    /// A shard given twice (directly or inside merged reports).
    #[error("shard {index}/{count} appears twice")]
    #[diagnostic(code(navfn::E048))]
    Duplicate {
        /// `I`.
        index: u32,
        /// `N`.
        count: u32,
    },
    /// A report whose parts contradict each other.
    #[error("inconsistent report of shard(s) {shards}: {msg}")]
    #[diagnostic(code(navfn::E057))]
    Invalid {
        /// Its shard indices.
        shards: String,
        /// What contradicts what.
        msg: String,
    },
    /// The reports do not cover the suite.
    #[error("incomplete: {0}")]
    #[diagnostic(
        code(navfn::E049),
        help("give every shard's report, or --allow-partial to merge what there is")
    )]
    Incomplete(String),
}

/// Whether an incomplete set of shards may be merged.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Completeness {
    /// Refuse unless every shard, map and case is present.
    #[default]
    Required,
    /// Merge what there is (`--allow-partial`).
    AllowPartial,
}

impl Report {
    /// Join reports of shards of one campaign (see the module documentation).
    pub fn merge(reports: &[Report], completeness: Completeness) -> Result<Report, MergeError> {
        let first = reports.first().ok_or(MergeError::Empty)?;
        for r in reports {
            if let Some(msg) = r.inconsistency() {
                return Err(MergeError::Invalid { shards: format!("{:?}", r.shards.indices), msg });
            }
            compatible(first, r)?;
        }
        let mut out = Report {
            format: first.format,
            vouch_version: first.vouch_version.clone(),
            options: first.options.clone(),
            shards: ShardSet { indices: Vec::new(), ..first.shards.clone() },
            ..Report::default()
        };
        out.suite.basis = first.suite.basis;
        out.suite.fingerprint = first.suite.fingerprint.clone();
        out.suite.maps_total = first.suite.maps_total;
        let mut seen = BTreeSet::new();
        for r in reports {
            for &i in &r.shards.indices {
                if !seen.insert(i) {
                    return Err(MergeError::Duplicate { index: i, count: r.shards.count });
                }
            }
            union_maps(&mut out, r)?;
            out.cases = out.cases.saturating_add(r.cases);
            for (k, v) in &r.categories {
                out.categories.entry(k.clone()).or_default().merge(v);
            }
            out.findings.extend(r.findings.iter().cloned());
            out.runs.extend(r.runs.iter().cloned());
        }
        out.shards.indices = seen.into_iter().collect();
        out.runs.sort_by_key(|run| run.shard);
        count_maps(&mut out.categories, &out.suite.maps);
        out.trim_findings();
        out.suite.seal();
        if completeness == Completeness::Required
            && let Some(gap) = incompleteness(&out)
        {
            return Err(MergeError::Incomplete(gap));
        }
        Ok(out)
    }
}

/// `category → maps` from the union of the map digests (the stats' own `maps` are per shard).
pub fn count_maps(
    categories: &mut BTreeMap<String, CategoryStats>,
    maps: &BTreeMap<String, crate::campaign::identity::MapDigest>,
) {
    for c in categories.values_mut() {
        c.maps = 0;
    }
    for d in maps.values() {
        categories.entry(d.category.clone()).or_default().maps += 1;
    }
}

fn compatible(a: &Report, b: &Report) -> Result<(), MergeError> {
    if a.vouch_version != b.vouch_version {
        return Err(MergeError::Version(a.vouch_version.clone(), b.vouch_version.clone()));
    }
    if a.options != b.options {
        let show = |r: &Report| {
            let o = &r.options;
            format!(
                "(mode {}, metamorphic {}, optimality {}, ratio {}, oracle {})",
                o.mode.name(),
                o.metamorphic,
                o.optimality,
                o.ratio,
                o.oracle.as_deref().unwrap_or("none")
            )
        };
        return Err(MergeError::Options(show(a), show(b)));
    }
    let (sa, sb) = (&a.suite, &b.suite);
    if (sa.basis, &sa.fingerprint, sa.maps_total) != (sb.basis, &sb.fingerprint, sb.maps_total) {
        let show = |s: &crate::campaign::identity::SuiteIdentity| {
            format!("{} maps, {:?} fingerprint {}", s.maps_total, s.basis, short(&s.fingerprint))
        };
        return Err(MergeError::Suite(show(sa), show(sb)));
    }
    if (a.shards.count, a.shards.by) != (b.shards.count, b.shards.by) {
        let show = |s: &ShardSet| format!("N = {} split by {}", s.count, s.by.name());
        return Err(MergeError::Split(show(&a.shards), show(&b.shards)));
    }
    Ok(())
}

fn short(h: &str) -> &str {
    h.get(..12).unwrap_or(h)
}

fn union_maps(out: &mut Report, r: &Report) -> Result<(), MergeError> {
    for (key, d) in &r.suite.maps {
        match out.suite.maps.get(key) {
            None => {
                out.suite.maps.insert(key.clone(), d.clone());
            }
            Some(seen) if seen == d => {}
            Some(seen) => {
                let show = |d: &crate::campaign::identity::MapDigest| {
                    format!("{} ({}, {} cases)", short(&d.sha256), d.category, d.cases)
                };
                return Err(MergeError::MapContent { key: key.clone(), a: show(seen), b: show(d) });
            }
        }
    }
    Ok(())
}

/// What is missing from a merged report, if anything.
fn incompleteness(r: &Report) -> Option<String> {
    let mut gaps = Vec::new();
    let missing = r.shards.missing_count();
    if missing > 0 {
        let first = r.shards.missing(8);
        let mut list: Vec<String> =
            first.iter().map(|i| format!("{i}/{}", r.shards.count)).collect();
        if missing > first.len() as u64 {
            list.push(format!("and {} more", missing - first.len() as u64));
        }
        gaps.push(format!("shard(s) {} missing", list.join(", ")));
    }
    let maps = r.suite.maps.len() as u64;
    if maps != r.suite.maps_total {
        gaps.push(format!("{maps} of the suite's {} maps read", r.suite.maps_total));
    }
    let expected = r.suite.cases();
    if missing == 0 && maps == r.suite.maps_total && r.cases != expected {
        gaps.push(format!("{} cases run, the suite's maps hold {expected}", r.cases));
    }
    (!gaps.is_empty()).then(|| gaps.join("; "))
}
