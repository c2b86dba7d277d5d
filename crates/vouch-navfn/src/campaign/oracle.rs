//! The oracle contract (docs/navfn-campaign.md, "Oracle contract"): how `suite diff` runs an
//! external NavFn and reads its answer, and vouch's own side of the contract (`suite run --trace`).
//!
//! Invocation, once per `test.txt`: `sh -c '<ORACLE> "$@"' oracle ARGS… TEST_TXT` with ARGS
//! `--mode paper` | `--mode navfn --algo dijkstra|astar`, optionally `--trace hash|cells` and `--pot`.
//! Output on stdout: the golden `CASE`/`PATH` lines of every case, plus, when asked, `CYCLE`,
//! `PROPEND` (with `--trace`) and `POT` (with `--pot`) lines of the same case number (`trace.rs`).
//! Any other line is ignored, so an oracle may log freely; exit status 0.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

use crate::campaign::error::{CampaignError, OracleError};
use crate::campaign::trace::{self, Trace, TraceDetail, TraceRecorder};
use crate::maps::{SuiteFile, find_test_files, read_suite_file};
use crate::suite::{CaseError, CaseRunner, CostInput, RunMode, write_cell_case};

/// What one side said about one case.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CaseAnswer {
    /// `key=value` fields of the CASE line (plus `coords` = the four case numbers as printed).
    pub fields: BTreeMap<String, String>,
    /// PATH tokens `xbits:ybits`.
    pub path: Vec<String>,
    /// CYCLE/PROPEND lines.
    pub trace: Trace,
    /// POT line (float32 bits).
    pub pot: Option<Vec<u32>>,
}

/// Parse an oracle's stdout. Unknown lines are ignored; malformed known lines are errors with
/// their 1-based line number.
pub fn parse_answers(text: &str) -> Result<BTreeMap<usize, CaseAnswer>, String> {
    let mut out: BTreeMap<usize, CaseAnswer> = BTreeMap::new();
    let mut last_case: Option<usize> = None;
    for (i, line) in text.lines().enumerate() {
        let toks: Vec<&str> = line.split_whitespace().collect();
        let Some((&head, rest)) = toks.split_first() else { continue };
        let at = |e: String| format!("line {}: {e}", i + 1);
        match head {
            "CASE" => {
                let k: usize = rest
                    .first()
                    .and_then(|s| s.parse().ok())
                    .ok_or_else(|| at("CASE without a case number".into()))?;
                let a = out.entry(k).or_default();
                let coords: Vec<&str> =
                    rest.iter().skip(1).take_while(|t| !t.contains('=')).copied().collect();
                a.fields.insert("coords".into(), coords.join(" "));
                for t in rest.iter().filter(|t| t.contains('=')) {
                    if let Some((key, v)) = t.split_once('=') {
                        a.fields.insert(key.into(), v.into());
                    }
                }
                last_case = Some(k);
            }
            "PATH" => {
                let k = last_case.ok_or_else(|| at("PATH before any CASE".into()))?;
                out.entry(k).or_default().path = rest.iter().map(|s| s.to_string()).collect();
            }
            "CYCLE" => {
                let (k, c) = trace::parse_cycle(rest).map_err(at)?;
                out.entry(k).or_default().trace.cycles.push(c);
            }
            "PROPEND" => {
                let (k, e) = trace::parse_propend(rest).map_err(at)?;
                out.entry(k).or_default().trace.end = Some(e);
            }
            "POT" => {
                let (k, p) = trace::parse_pot(rest).map_err(at)?;
                out.entry(k).or_default().pot = Some(p);
            }
            _ => {}
        }
    }
    Ok(out)
}

/// Options of vouch's own side of the contract.
#[derive(Clone, Copy, Debug)]
pub struct EmitOptions {
    /// The call sequence.
    pub mode: RunMode,
    /// Per-cycle trace lines, and how detailed.
    pub trace: Option<TraceDetail>,
    /// A `POT` line per case.
    pub pot: bool,
    /// Test-only perturbation: a different threshold increment `priInc` (hidden CLI flag).
    pub perturb_pri_inc: Option<f32>,
}

/// Run every case of `file` and append the contract's lines (`suite run --trace`).
pub fn emit_file(
    file: &SuiteFile,
    opts: &EmitOptions,
    out: &mut String,
) -> Result<usize, CaseError> {
    let mut runner = CaseRunner::new();
    if let Some(p) = opts.perturb_pri_inc {
        runner.nav_mut().set_pri_inc(p);
    }
    let mode = opts.mode;
    let mut found = 0;
    for case in &file.cases {
        let o = match opts.trace {
            Some(d) => {
                let mut rec = TraceRecorder::new(d);
                let o = runner.run_case(file, case, mode, CostInput::Raw, &mut rec)?;
                trace::write_trace(out, case.number, &rec.trace);
                o
            }
            None => {
                runner.run_case(file, case, mode, CostInput::Raw, &mut crate::core::NoObserver)?
            }
        };
        if opts.pot {
            trace::write_pot(out, case.number, runner.nav().potential());
        }
        write_cell_case(out, case, &o, runner.nav());
        found += usize::from(o.len > 0);
    }
    Ok(found)
}

/// Every case of every test file below `path` (a test file or a folder), in the contract's
/// format, handed to `sink` one file at a time. Returns the number of cases.
pub fn emit_path<E: From<CampaignError>>(
    path: &Path,
    opts: &EmitOptions,
    mut sink: impl FnMut(&str) -> Result<(), E>,
) -> Result<usize, E> {
    let files = find_test_files(path, "test.txt").map_err(CampaignError::from)?;
    let mut cases = 0;
    let mut text = String::new();
    for f in files {
        let file = read_suite_file(&f).map_err(CampaignError::from)?;
        text.clear();
        emit_file(&file, opts, &mut text)
            .map_err(|source| CampaignError::Case { map: f.display().to_string(), source })?;
        cases += file.cases.len();
        sink(&text)?;
    }
    Ok(cases)
}

/// Contract arguments for a run.
pub fn contract_args(mode: RunMode, trace: Option<TraceDetail>, pot: bool) -> Vec<String> {
    let mut a: Vec<String> = mode.args().iter().map(|s| s.to_string()).collect();
    if let Some(d) = trace {
        a.push("--trace".into());
        a.push(if d == TraceDetail::Cells { "cells" } else { "hash" }.into());
    }
    if pot {
        a.push("--pot".into());
    }
    a
}

/// Run the oracle command on one test file and parse its answers.
pub fn run_oracle(
    cmd: &str,
    args: &[String],
    test_txt: &Path,
) -> Result<BTreeMap<usize, CaseAnswer>, OracleError> {
    let file = test_txt.display().to_string();
    let output = Command::new("sh")
        .arg("-c")
        .arg(format!("{cmd} \"$@\""))
        .arg("oracle")
        .args(args)
        .arg(test_txt)
        .output()
        .map_err(|source| OracleError::Spawn { cmd: cmd.into(), source })?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let stderr: String = stderr.lines().take(5).collect::<Vec<_>>().join(" | ");
        // A black-box oracle (the basic contract only) may refuse the trace extension.
        let hint = args.iter().any(|a| a == "--trace" || a == "--pot").then(|| {
            "an oracle without the trace extension (--trace, --pot) is compared black box only: \
             `vouch navfn suite diff --white-box none`"
                .to_string()
        });
        return Err(OracleError::Failed {
            cmd: cmd.into(),
            file,
            status: output.status.to_string(),
            stderr,
            hint,
        });
    }
    let text = String::from_utf8_lossy(&output.stdout);
    parse_answers(&text).map_err(|msg| OracleError::Output { cmd: cmd.into(), file, msg })
}
