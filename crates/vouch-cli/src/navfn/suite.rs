//! `vouch navfn suite run`: the golden line format of every case, optionally with the oracle
//! contract's trace lines, and the plan checks.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use vouch_navfn::campaign::oracle::{EmitOptions, emit_path};
use vouch_navfn::campaign::trace::TraceDetail;
use vouch_navfn::checks::{PlanView, check_plan};
use vouch_navfn::core::NoObserver;
use vouch_navfn::maps::{MapError, SuiteFile, find_test_files, read_suite_file, read_world_params};
use vouch_navfn::planner::WorldParams;
use vouch_navfn::suite::{CaseRunner, CostInput, RunMode, SuiteMode, SuiteOptions, run_file};

use super::{AlgoArg, ModeArg, map_failure, parse_pair, run_mode};
use crate::contract::{CmdResult, Ctx, Exit};

/// `--costs`: how map bytes become NavFn costs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CostsArg {
    /// Map bytes are NavFn costs (the paper suite)
    Raw,
    /// Map bytes are ROS Costmap2D values (suite_ros)
    Ros,
}

/// `--trace`: how much of each priority buffer a trace line shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum DetailArg {
    /// Buffer length and FNV-1a hash per cycle
    Hash,
    /// Also the ordered cell list of every buffer
    Cells,
}

impl From<DetailArg> for TraceDetail {
    fn from(d: DetailArg) -> TraceDetail {
        match d {
            DetailArg::Hash => TraceDetail::Hash,
            DetailArg::Cells => TraceDetail::Cells,
        }
    }
}

/// Arguments of `vouch navfn suite run`.
#[derive(Args)]
#[command(
    after_help = after_help!(
        ["vouch navfn suite run examples/navfn/suite --mode navfn --algo astar --check"],
        "0 every case ran, 1 suite file rejected, 2 usage or I/O error, \
         3 a plan check failed with --check"
    )
)]
pub struct SuiteRunArgs {
    /// A test file, or a folder searched recursively (sorted) for test files
    path: PathBuf,
    /// Call sequence
    #[arg(long, value_enum, default_value = "paper")]
    mode: ModeArg,
    /// Propagation in navfn and planner modes (paper mode is always A*)
    #[arg(long, value_enum, default_value = "dijkstra")]
    algo: AlgoArg,
    /// Cost input (default: raw, except ros in planner mode)
    #[arg(long, value_enum)]
    costs: Option<CostsArg>,
    /// File name searched in folders (default test.txt; test_world.txt in planner mode)
    #[arg(long, value_name = "NAME")]
    name: Option<String>,
    /// Planner mode: world origin (default: params.txt next to each test file, else 0,0)
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true, value_name = "X,Y")]
    origin: Option<[f64; 2]>,
    /// Planner mode: cell size in metres (default: params.txt next to each test file, else 1)
    #[arg(long, value_name = "METRES")]
    res: Option<f64>,
    /// Also run the plan checks on every case; violations are listed on stderr (exit 3)
    #[arg(long)]
    check: bool,
    /// Per-cycle trace lines (CYCLE/PROPEND) before each CASE line, as the oracle contract
    /// prints them (paper and navfn modes)
    #[arg(long, value_enum)]
    trace: Option<DetailArg>,
    /// A POT line with the whole final potential (float32 bits) before each CASE line
    #[arg(long)]
    pot: bool,
    /// Test only: run with a different threshold increment priInc (default 100)
    #[arg(long, hide = true)]
    perturb_pri_inc: Option<f32>,
}

/// Runs `vouch navfn suite run`.
pub fn run(a: SuiteRunArgs, ctx: &mut Ctx) -> CmdResult {
    if a.trace.is_some() || a.pot || a.perturb_pri_inc.is_some() {
        return run_traced(&a, ctx);
    }
    let mode = SuiteMode::from(a.mode);
    let costs = match a.costs.unwrap_or(if mode == SuiteMode::Planner {
        CostsArg::Ros
    } else {
        CostsArg::Raw
    }) {
        CostsArg::Raw => CostInput::Raw,
        CostsArg::Ros => CostInput::Ros,
    };
    let name = a.name.clone().unwrap_or_else(|| {
        if mode == SuiteMode::Planner { "test_world.txt" } else { "test.txt" }.to_string()
    });
    let files = find_test_files(&a.path, &name).map_err(map_failure)?;
    if files.is_empty() {
        return Err(map_failure(MapError::file(
            &a.path,
            format!("no `{name}` below this folder (--name NAME searches for another file name)"),
        )));
    }
    let (mut cases, mut found, mut violations) = (0usize, 0usize, 0usize);
    // A file that cannot be used is an error (printed, the run goes on with the next file);
    // the first one decides the exit code: 2 if it could not be read, else 1.
    let mut failed: Option<Exit> = None;
    let mut text = String::new();
    for f in &files {
        let loaded = read_suite_file(f).and_then(|file| Ok((world_for(&a, f)?, file)));
        let (world, file) = match loaded {
            Ok(wf) => wf,
            Err(e) => {
                file_error(ctx, &e);
                failed.get_or_insert(if e.is_io() { Exit::Usage } else { Exit::Rejected });
                continue;
            }
        };
        let opts = SuiteOptions { mode, algo: a.algo.into(), costs, world };
        text.clear();
        writeln!(ctx.out, "MAP {}", f.display())?;
        match run_file(&file, &opts, &mut text) {
            Ok(s) => {
                cases += s.cases;
                found += s.found;
            }
            Err(e) => {
                file_error(ctx, &e);
                failed.get_or_insert(Exit::Rejected);
            }
        }
        ctx.out.write_all(text.as_bytes())?;
        if let (true, Some(run_mode)) = (a.check, RunMode::new(mode, a.algo.into())) {
            violations += check_file(ctx, &file, run_mode, costs);
        }
    }
    ctx.note(format_args!("{cases} cases in {} files, {found} with a path", files.len()));
    if a.check {
        ctx.note(format_args!("plan checks: {violations} violations"));
    }
    if let Some(exit) = failed {
        return Ok(exit);
    }
    if cases == 0 {
        // Every file read, none holds a case: nothing ran, so nothing passed.
        return Err(map_failure(MapError::file(
            &a.path,
            "the suite holds no case: nothing to run",
        )));
    }
    Ok(if violations > 0 { Exit::Findings } else { Exit::Ok })
}

/// One test file's error: an error (coded, located), though the run goes on.
fn file_error(ctx: &Ctx, e: &dyn miette::Diagnostic) {
    crate::diagnostics::print(ctx.format, e, crate::contract::Severity::Error);
}

/// The oracle contract's side of vouch (`--trace`, `--pot`): cell-level modes only.
fn run_traced(a: &SuiteRunArgs, ctx: &mut Ctx) -> CmdResult {
    let opts = EmitOptions {
        mode: run_mode(a.mode, a.algo)?,
        trace: a.trace.map(Into::into),
        pot: a.pot,
        perturb_pri_inc: a.perturb_pri_inc,
    };
    let out = &mut ctx.out;
    let n = emit_path(&a.path, &opts, |text| out.write_all(text.as_bytes()))?;
    // An oracle is asked one test file at a time and answers one without a case with nothing;
    // a folder without a case is a mistake.
    if n == 0 && a.path.is_dir() {
        return Err(map_failure(MapError::file(
            &a.path,
            "the suite holds no case: nothing to run",
        )));
    }
    ctx.note(format_args!("{n} cases"));
    Ok(Exit::Ok)
}

/// The world frame of a planner-mode test file: `params.txt` beside it, then the overrides.
fn world_for(
    a: &SuiteRunArgs,
    test_file: &Path,
) -> Result<WorldParams, vouch_navfn::maps::MapError> {
    let params = test_file.with_file_name("params.txt");
    let mut w = if params.is_file() { read_world_params(&params)? } else { WorldParams::default() };
    if let Some(o) = a.origin {
        w.origin = o;
    }
    if let Some(r) = a.res {
        w.resolution = r;
    }
    Ok(w)
}

/// Plan checks on every case of `file`; violations on stderr. Returns their number.
fn check_file(ctx: &Ctx, file: &SuiteFile, mode: RunMode, costs: CostInput) -> usize {
    let mut runner = CaseRunner::new();
    let mut n = 0;
    for case in &file.cases {
        if runner.run_case(file, case, mode, costs, &mut NoObserver).is_ok() {
            let r = check_plan(&PlanView::of(runner.nav()));
            for v in &r.violations {
                ctx.note(format_args!(
                    "violation: {} case {}: {v}",
                    file.test_path.display(),
                    case.number
                ));
            }
            n += r.count();
        }
    }
    n
}
