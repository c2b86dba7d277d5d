//! `vouch navfn suite diff --oracle CMD SUITE`: vouch and an external oracle on the same suite,
//! compared black box (CASE fields: prop, len, last_path_cost, pot_fnv, path_fnv; PATH bit
//! patterns) and white box (per-cycle threshold and buffers). Both sides go through the same
//! text format and parser, so a format slip on either side is a mismatch too.
//!
//! On the first differing case of a file, the harness asks both sides again for that file with
//! `--trace cells --pot` to name the first diverging cycle, buffer position and cell, and the
//! first differing potential cell.

use std::collections::BTreeMap;
use std::path::Path;

use rayon::prelude::*;

use crate::campaign::error::CampaignError;
use crate::campaign::names::FindingKind;
use crate::campaign::oracle::{
    CaseAnswer, EmitOptions, contract_args, emit_file, parse_answers, run_oracle,
};
use crate::campaign::report::{Finding, Report};
use crate::campaign::shard::Shard;
use crate::campaign::suite_io::walk_suite;
use crate::campaign::trace::{TraceDetail, TraceDivergence, first_divergence};
use crate::maps::{MapError, find_test_files, read_suite_file};
use crate::suite::RunMode;

/// What `suite diff` compares.
#[derive(Clone, Debug)]
pub struct DiffOptions {
    /// The oracle command (run through `sh -c`).
    pub oracle: String,
    /// The call sequence.
    pub mode: RunMode,
    /// White-box detail for every case and for the details of a mismatch (`None` = black box
    /// only, for an oracle without the trace extension).
    pub white_box: Option<TraceDetail>,
    /// Test-only perturbation of vouch's own side.
    pub perturb_pri_inc: Option<f32>,
}

/// The first differing potential cell.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PotDiff {
    /// Column.
    pub x: usize,
    /// Row.
    pub y: usize,
    /// vouch's potential.
    pub ours: f32,
    /// The oracle's potential.
    pub theirs: f32,
}

/// One differing case.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CaseMismatch {
    /// The test file.
    pub file: String,
    /// Case number.
    pub case: usize,
    /// The case's coordinates as printed.
    pub coords: String,
    /// `field: ours vs theirs` for each differing CASE field, and `PATH` when the points differ.
    pub fields: Vec<String>,
    /// The first diverging cycle of the search traces.
    pub divergence: Option<TraceDivergence>,
    /// The first differing potential cell.
    pub pot: Option<PotDiff>,
}

/// Outcome of a diff run.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct DiffReport {
    /// Test files compared.
    pub files: usize,
    /// Cases compared.
    pub cases: usize,
    /// Cases both sides answered the same.
    pub equal: usize,
    /// Cases that differ (or that the oracle did not answer).
    pub different: usize,
    /// First mismatch of each file that has one, in file order.
    pub mismatches: Vec<CaseMismatch>,
}

const COMPARED: [&str; 8] =
    ["coords", "navfn_start", "navfn_goal", "prop", "len", "last_path_cost", "pot_fnv", "path_fnv"];

fn compare(ours: &CaseAnswer, theirs: &CaseAnswer) -> (Vec<String>, Option<TraceDivergence>) {
    let mut fields = Vec::new();
    for k in COMPARED {
        let (a, b) = (ours.fields.get(k), theirs.fields.get(k));
        if a != b {
            fields.push(format!(
                "{k}: {} vs {}",
                a.map_or("-", |s| s.as_str()),
                b.map_or("-", |s| s.as_str())
            ));
        }
    }
    if ours.path != theirs.path {
        let i = ours
            .path
            .iter()
            .zip(&theirs.path)
            .position(|(a, b)| a != b)
            .unwrap_or(ours.path.len().min(theirs.path.len()));
        fields.push(format!(
            "PATH: point {i}: {} vs {}",
            ours.path.get(i).map_or("-", |s| s.as_str()),
            theirs.path.get(i).map_or("-", |s| s.as_str())
        ));
    }
    // White box only when both sides traced.
    let div = if !ours.trace.cycles.is_empty() && !theirs.trace.cycles.is_empty() {
        first_divergence(&ours.trace, &theirs.trace)
    } else {
        None
    };
    (fields, div)
}

fn pot_diff(ours: &CaseAnswer, theirs: &CaseAnswer, width: usize) -> Option<PotDiff> {
    let (a, b) = (ours.pot.as_ref()?, theirs.pot.as_ref()?);
    let i = a.iter().zip(b).position(|(p, q)| p != q)?;
    Some(PotDiff {
        x: i % width,
        y: i / width,
        ours: f32::from_bits(a[i]),
        theirs: f32::from_bits(b[i]),
    })
}

fn ours_for(
    file: &crate::maps::SuiteFile,
    opts: &DiffOptions,
    trace: Option<TraceDetail>,
    pot: bool,
) -> Result<BTreeMap<usize, CaseAnswer>, CampaignError> {
    let mut text = String::new();
    emit_file(
        file,
        &EmitOptions { mode: opts.mode, trace, pot, perturb_pri_inc: opts.perturb_pri_inc },
        &mut text,
    )?;
    parse_answers(&text).map_err(CampaignError::Own)
}

/// Diff one test file.
pub fn diff_file(
    test_txt: &Path,
    opts: &DiffOptions,
) -> Result<(usize, usize, Option<CaseMismatch>), CampaignError> {
    let file = read_suite_file(test_txt)?;
    let ours = ours_for(&file, opts, opts.white_box, false)?;
    let theirs =
        run_oracle(&opts.oracle, &contract_args(opts.mode, opts.white_box, false), test_txt)?;
    let mut equal = 0;
    let mut first: Option<usize> = None;
    let empty = CaseAnswer::default();
    for case in &file.cases {
        let a = ours.get(&case.number).unwrap_or(&empty);
        let b = theirs.get(&case.number).unwrap_or(&empty);
        let (fields, div) = compare(a, b);
        if fields.is_empty() && div.is_none() && !b.fields.is_empty() {
            equal += 1;
        } else if first.is_none() {
            first = Some(case.number);
        }
    }
    let different = file.cases.len() - equal;
    let Some(k) = first else { return Ok((equal, different, None)) };

    // Deep re-run of this file for the details of its first mismatch: the cell-level trace and
    // the potentials when the oracle offers the white box, else its answers again.
    let deep = opts.white_box.is_some();
    let trace = deep.then_some(TraceDetail::Cells);
    let ours = ours_for(&file, opts, trace, deep)?;
    let theirs = run_oracle(&opts.oracle, &contract_args(opts.mode, trace, deep), test_txt)?;
    let a = ours.get(&k).cloned().unwrap_or_default();
    let b = theirs.get(&k).cloned().unwrap_or_default();
    let (mut fields, divergence) = compare(&a, &b);
    if b.fields.is_empty() {
        fields.push("the oracle printed no CASE line for this case".into());
    }
    let mismatch = CaseMismatch {
        file: test_txt.display().to_string(),
        case: k,
        coords: a.fields.get("coords").cloned().unwrap_or_default(),
        fields,
        divergence,
        pot: pot_diff(&a, &b, file.width),
    };
    Ok((equal, different, Some(mismatch)))
}

/// Diff every test file below `suite` (files in parallel; each oracle call is one process).
pub fn diff_suite(suite: &Path, opts: &DiffOptions) -> Result<DiffReport, CampaignError> {
    let files = find_test_files(suite, "test.txt")?;
    if files.is_empty() {
        return Err(MapError::file(suite, "no test.txt found below this folder").into());
    }
    let results: Vec<(usize, usize, Option<CaseMismatch>)> =
        files.par_iter().map(|f| diff_file(f, opts)).collect::<Result<_, _>>()?;
    let mut r = DiffReport { files: files.len(), ..DiffReport::default() };
    for (eq, diff, m) in results {
        r.cases += eq + diff;
        r.equal += eq;
        r.different += diff;
        r.mismatches.extend(m);
    }
    // Nothing compared is not agreement.
    if r.cases == 0 {
        return Err(MapError::file(suite, "the suite holds no case: nothing to compare").into());
    }
    Ok(r)
}

/// Diffs every test file below `suite` whose home is `shard` (one oracle process per file, so
/// a file is compared by its home shard in both splits), adds the counts and the first
/// mismatch of each file to `report` (as `oracle_mismatch` findings), and records the oracle
/// among the report's options.
pub fn add_oracle(
    report: &mut Report,
    suite: &Path,
    oracle: &str,
    mode: RunMode,
    shard: Shard,
) -> Result<(), CampaignError> {
    let dopts = DiffOptions {
        oracle: oracle.into(),
        mode,
        white_box: Some(TraceDetail::Hash),
        perturb_pri_inc: None,
    };
    for entry in walk_suite(suite)? {
        let e = entry?;
        if Shard::home(&e.key, shard.count) != shard.index {
            continue;
        }
        let (eq, diff, m) = diff_file(&e.test_txt, &dopts)?;
        let st = report.categories.entry(e.category.clone()).or_default();
        st.oracle.pass += eq as u64;
        st.oracle.fail += diff as u64;
        if let Some(m) = m {
            let divergence = m
                .divergence
                .map(|d| format!("; cycle {}: {}", d.cycle, d.detail))
                .unwrap_or_default();
            report.findings.push(Finding {
                kind: FindingKind::OracleMismatch,
                category: e.category,
                map: e.name,
                case: m.case as u64,
                coords: [0; 4],
                detail: format!("{}{divergence}", m.fields.join("; ")),
                score: 1.0,
                picture: None,
            });
        }
    }
    report.options.oracle = Some(oracle.to_string());
    report.trim_findings();
    Ok(())
}

/// Human text of a diff report: totals and the first mismatch in detail.
pub fn describe(r: &DiffReport) -> String {
    let mut s = format!(
        "{} files, {} cases: {} equal, {} different\n",
        r.files, r.cases, r.equal, r.different
    );
    if let Some(m) = r.mismatches.first() {
        s.push_str(&format!("first diverging case: {} case {} ({})\n", m.file, m.case, m.coords));
        for f in &m.fields {
            s.push_str(&format!("  {f}\n"));
        }
        match &m.divergence {
            Some(d) => {
                s.push_str(&format!(
                    "  first diverging cycle: {} ({}: {})",
                    d.cycle, d.what, d.detail
                ));
                if let Some(p) = d.position {
                    s.push_str(&format!(
                        "; position {p}: vouch cell {:?}, oracle cell {:?}",
                        d.ours, d.theirs
                    ));
                }
                s.push('\n');
            }
            None => s.push_str("  search traces agree (the difference arises after propagation)\n"),
        }
        if let Some(p) = &m.pot {
            s.push_str(&format!(
                "  first differing potential: cell ({}, {}): vouch {} vs oracle {}\n",
                p.x, p.y, p.ours, p.theirs
            ));
        }
        if r.mismatches.len() > 1 {
            s.push_str(&format!("  ({} more files with mismatches)\n", r.mismatches.len() - 1));
        }
    }
    s
}
