//! The logic behind the campaign's CLI subcommands (`suite gen`, `suite diff`, `campaign`,
//! `report merge`, `suite run --trace`); the CLI only parses arguments and maps errors to
//! exit codes. Each function returns the text for stdout.

use std::path::{Path, PathBuf};

use crate::campaign::diff::{describe, diff_file, DiffOptions};
use crate::campaign::gen::{generate, sample_cases, GenError, GenOptions};
use crate::campaign::oracle::{emit_file, EmitOptions};
use crate::campaign::pictures::counterexample_png;
use crate::campaign::report::{summary_table, Finding, Report};
use crate::campaign::rng::SplitMix64;
use crate::campaign::ros_import::import_ros_map;
use crate::campaign::runner::{
    find_map, picture_path, run_campaign, CampaignError, CampaignOptions,
};
use crate::campaign::suite_io::{write_suite, SuiteIoError};
use crate::campaign::trace::TraceDetail;
use crate::maps::{find_test_files, read_suite_file, MapError};

/// Errors of the campaign commands, with the exit code they map to.
#[derive(Debug, thiserror::Error)]
pub enum CmdError {
    /// Bad input data (exit 1).
    #[error("{0}")]
    Input(String),
    /// Usage or I/O problem (exit 2).
    #[error("{0}")]
    Usage(String),
}

impl CmdError {
    pub fn exit_code(&self) -> u8 {
        match self {
            CmdError::Input(_) => 1,
            CmdError::Usage(_) => 2,
        }
    }
}

impl From<GenError> for CmdError {
    fn from(e: GenError) -> Self {
        CmdError::Usage(e.to_string())
    }
}
impl From<SuiteIoError> for CmdError {
    fn from(e: SuiteIoError) -> Self {
        match e {
            SuiteIoError::Io { .. } => CmdError::Usage(e.to_string()),
            SuiteIoError::Map(m) => m.into(),
            _ => CmdError::Input(e.to_string()),
        }
    }
}
impl From<MapError> for CmdError {
    fn from(e: MapError) -> Self {
        match e {
            MapError::Io { .. } => CmdError::Usage(e.to_string()),
            _ => CmdError::Input(e.to_string()),
        }
    }
}
impl From<CampaignError> for CmdError {
    fn from(e: CampaignError) -> Self {
        match e {
            CampaignError::Suite(s) => s.into(),
            CampaignError::Case { .. } => CmdError::Input(e.to_string()),
        }
    }
}

/// `suite gen`: generate (and import ROS maps), write the suite, describe it.
pub fn suite_gen(
    opts: &GenOptions,
    out: &Path,
    ros_maps: &[PathBuf],
    ros_cases: usize,
) -> Result<String, CmdError> {
    let mut maps = generate(opts)?;
    for (i, yaml) in ros_maps.iter().enumerate() {
        let name = yaml
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| format!("ros{i}"));
        let mut m = import_ros_map(yaml, &name, None)?;
        let mut rng = SplitMix64::derive(opts.seed, "ROS", i as u64);
        m.cases = sample_cases(&m, &mut rng, ros_cases);
        maps.push(m);
    }
    write_suite(out, &maps)?;
    let cases: usize = maps.iter().map(|m| m.cases.len()).sum();
    Ok(format!(
        "wrote {} maps, {cases} cases to {} (seed {})\n",
        maps.len(),
        out.display(),
        opts.seed
    ))
}

/// `campaign`: run, optionally diff against an oracle, write report and pictures.
pub fn campaign(
    suite: &Path,
    opts: &CampaignOptions,
    oracle: Option<&str>,
    report_path: Option<&Path>,
    pictures: Option<&Path>,
    cases_out: Option<&Path>,
) -> Result<(String, Report), CmdError> {
    let mut opts = opts.clone();
    opts.per_case |= cases_out.is_some();
    let opts = &opts;
    let (mut report, maps) = run_campaign(suite, opts)?;
    if let Some(p) = cases_out {
        write_case_lines(p, &report)?;
    }
    if let Some(cmd) = oracle {
        let files = find_test_files(suite, "test.txt")?;
        let dopts = DiffOptions {
            oracle: cmd.into(),
            mode: opts.mode,
            white_box: Some(TraceDetail::Hash),
            perturb_pri_inc: None,
        };
        for (i, f) in files.iter().enumerate() {
            // Oracle comparison is sharded by file (one oracle process per file).
            if !opts.shard.owns(i as u64) {
                continue;
            }
            let (eq, diff, m) = diff_file(f, &dopts).map_err(|e| CmdError::Usage(e.to_string()))?;
            let category = f
                .parent()
                .and_then(Path::parent)
                .and_then(Path::file_name)
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
            let st = report.categories.entry(category.clone()).or_default();
            st.oracle.pass += eq as u64;
            st.oracle.fail += diff as u64;
            if let Some(m) = m {
                report.findings.push(Finding {
                    kind: "oracle_mismatch".into(),
                    category,
                    map: f
                        .parent()
                        .and_then(Path::file_name)
                        .map(|s| s.to_string_lossy().into_owned())
                        .unwrap_or_default(),
                    case: m.case as u64,
                    coords: [0; 4],
                    detail: format!(
                        "{}{}",
                        m.fields.join("; "),
                        m.divergence
                            .map(|d| format!("; cycle {}: {}", d.cycle, d.detail))
                            .unwrap_or_default()
                    ),
                    score: 1.0,
                    picture: None,
                });
            }
        }
        report.trim_findings();
    }
    if let Some(dir) = pictures {
        std::fs::create_dir_all(dir)
            .map_err(|e| CmdError::Usage(format!("{}: {e}", dir.display())))?;
        for f in report.findings.iter_mut() {
            if f.kind == "oracle_mismatch" || f.kind == "approx_relation" {
                continue;
            }
            let Some(pm) = find_map(&maps, &f.category, &f.map) else { continue };
            let p = picture_path(dir, f);
            counterexample_png(&p, pm, f.case as usize, opts.mode)
                .map_err(|e| CmdError::Usage(format!("{}: {e}", p.display())))?;
            f.picture = Some(p.display().to_string());
        }
    }
    if let Some(p) = report_path {
        write_report(p, &report)?;
    }
    let mut text = summary_table(&report);
    let worst: Vec<&Finding> =
        report.findings.iter().filter(|f| f.kind == "suboptimal").take(3).collect();
    if !worst.is_empty() {
        text.push_str("worst optimality counterexamples:\n");
        for f in worst {
            text.push_str(&format!(
                "  {}/{} case {} {:?}: {}\n",
                f.category, f.map, f.case, f.coords, f.detail
            ));
        }
    }
    Ok((text, report))
}

/// One JSON object per case and line (`--cases-out`).
pub fn write_case_lines(p: &Path, r: &Report) -> Result<(), CmdError> {
    use std::io::Write as _;
    let err = |e: std::io::Error| CmdError::Usage(format!("{}: {e}", p.display()));
    let f = std::fs::File::create(p).map_err(err)?;
    let mut w = std::io::BufWriter::new(f);
    for rec in &r.per_case {
        let line = serde_json::to_string(rec).map_err(|e| CmdError::Usage(e.to_string()))?;
        writeln!(w, "{line}").map_err(err)?;
    }
    w.flush().map_err(err)
}

pub fn write_report(p: &Path, r: &Report) -> Result<(), CmdError> {
    let json = serde_json::to_string_pretty(r).map_err(|e| CmdError::Usage(e.to_string()))?;
    std::fs::write(p, json).map_err(|e| CmdError::Usage(format!("{}: {e}", p.display())))
}

pub fn read_report(p: &Path) -> Result<Report, CmdError> {
    let text =
        std::fs::read_to_string(p).map_err(|e| CmdError::Usage(format!("{}: {e}", p.display())))?;
    serde_json::from_str(&text)
        .map_err(|e| CmdError::Input(format!("{}: not a campaign report: {e}", p.display())))
}

/// `report merge`: join shard reports, write the merged one, return its summary.
pub fn report_merge(out: &Path, inputs: &[PathBuf]) -> Result<(String, Report), CmdError> {
    let reports = inputs.iter().map(|p| read_report(p)).collect::<Result<Vec<_>, _>>()?;
    let merged = Report::merge(&reports).map_err(CmdError::Input)?;
    write_report(out, &merged)?;
    let mut text = summary_table(&merged);
    if !merged.complete() {
        text.push_str("warning: the merged shards do not cover every shard index\n");
    }
    Ok((text, merged))
}

/// `suite diff`: returns the description and whether everything agreed.
pub fn suite_diff(
    suite: &Path,
    opts: &DiffOptions,
    json: Option<&Path>,
) -> Result<(String, bool), CmdError> {
    let r = crate::campaign::diff::diff_suite(suite, opts).map_err(|e| match e {
        crate::campaign::diff::DiffError::Map(m) => CmdError::from(m),
        other => CmdError::Usage(other.to_string()),
    })?;
    if let Some(p) = json {
        let s = serde_json::to_string_pretty(&r).map_err(|e| CmdError::Usage(e.to_string()))?;
        std::fs::write(p, s).map_err(|e| CmdError::Usage(format!("{}: {e}", p.display())))?;
    }
    Ok((describe(&r), r.different == 0))
}

/// `suite run --trace/--pot`: vouch's side of the oracle contract for every test file below `path`.
pub fn suite_run_traced(
    path: &Path,
    opts: &EmitOptions,
    out: &mut dyn std::io::Write,
) -> Result<usize, CmdError> {
    let files = find_test_files(path, "test.txt")?;
    let mut cases = 0;
    for f in files {
        let file = read_suite_file(&f)?;
        let mut text = String::new();
        emit_file(&file, opts, &mut text).map_err(|e| CmdError::Input(e.to_string()))?;
        cases += file.cases.len();
        out.write_all(text.as_bytes()).map_err(|e| CmdError::Usage(e.to_string()))?;
    }
    Ok(cases)
}
