//! `vouch navfn …` subcommands (owned by the navfn family; navfn-core wrote `plan`,
//! `suite run` and `bench`, navfn-campaign adds its own variants next to them).
//!
//! Exit codes: 0 success, 1 input rejected (bad map, bad point, no path), 2 usage/IO error,
//! 3 plan-check violations with `--checked`.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Args, Subcommand, ValueEnum};
use vouch_navfn::checks::{check_plan, PlanView};
use vouch_navfn::core::{Algo, NoObserver, COST_OBS};
use vouch_navfn::maps::{
    find_test_files, load_ros_map, read_suite_file, read_world_params, SuiteFile,
};
use vouch_navfn::picture::{save_png, PictureInput};
use vouch_navfn::planner::{NavfnPlanner, PlanStatus, PlannerParams, WorldParams};
use vouch_navfn::suite_run::{run_file, CaseRunner, CostInput, SuiteMode, SuiteOptions};

#[path = "navfn_campaign.rs"]
mod campaign_cmd;

#[derive(Subcommand)]
pub enum NavfnCmd {
    /// Plan one path on a ROS map (YAML+PGM/PNG, or an image) like nav2's NavfnPlanner, checked
    Plan(PlanArgs),
    /// The paper's test suite (test.txt + map.bin)
    #[command(subcommand)]
    Suite(SuiteCmd),
    /// Time the paper suite (µs per path) and the nav2 400×400 default pair (ms per plan)
    Bench(BenchArgs),
    /// Verification campaign: properties, optimality, metamorphic relations, oracle diff, report
    Campaign(campaign_cmd::CampaignArgs),
    /// Campaign reports
    #[command(subcommand)]
    Report(campaign_cmd::ReportCmd),
}

#[derive(Subcommand)]
pub enum SuiteCmd {
    /// Run every case of a test file (or of every test file below a folder, sorted) and print
    /// the golden line format (CASE / PATH [/ WORLD]) on stdout
    Run(SuiteRunArgs),
    /// Generate a suite (nine categories of the paper), deterministic for a seed
    Gen(campaign_cmd::SuiteGenArgs),
    /// Run vouch and an external oracle on a suite and compare (black box and per-cycle trace)
    Diff(campaign_cmd::SuiteDiffArgs),
}

pub fn run(cmd: NavfnCmd, _ctx: &mut crate::contract::Ctx) -> crate::contract::CmdResult {
    crate::legacy(run_legacy(cmd))
}

fn run_legacy(cmd: NavfnCmd) -> ExitCode {
    match cmd {
        NavfnCmd::Plan(a) => plan(a),
        NavfnCmd::Suite(SuiteCmd::Run(a)) => suite_run(a),
        NavfnCmd::Bench(a) => bench(a),
        NavfnCmd::Suite(SuiteCmd::Gen(a)) => campaign_cmd::suite_gen(a),
        NavfnCmd::Suite(SuiteCmd::Diff(a)) => campaign_cmd::suite_diff(a),
        NavfnCmd::Campaign(a) => campaign_cmd::campaign(a),
        NavfnCmd::Report(c) => campaign_cmd::report(c),
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AlgoArg {
    Dijkstra,
    Astar,
}

impl From<AlgoArg> for Algo {
    fn from(a: AlgoArg) -> Algo {
        match a {
            AlgoArg::Dijkstra => Algo::Dijkstra,
            AlgoArg::Astar => Algo::Astar,
        }
    }
}

fn fail(code: u8, msg: impl std::fmt::Display) -> ExitCode {
    eprintln!("error: {msg}");
    ExitCode::from(code)
}

// ------------------------------------------------------------------------------------------
// vouch navfn plan

#[derive(Args)]
pub struct PlanArgs {
    /// Map: map_server YAML (naming a PGM/PNG), or a PGM/PNG image (resolution 1, origin 0)
    map: PathBuf,
    /// Robot start X,Y (metres in the map frame; cell column,row with --cells)
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true)]
    start: [f64; 2],
    /// Robot goal X,Y
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true)]
    goal: [f64; 2],
    /// Start and goal are cell indices (column,row; row 0 = bottom of the image)
    #[arg(long)]
    cells: bool,
    #[arg(long, value_enum, default_value = "dijkstra")]
    algo: AlgoArg,
    /// Goal tolerance in metres (nav2 default 0.5)
    #[arg(long, default_value_t = 0.5)]
    tolerance: f64,
    /// Treat unknown cells as obstacles (nav2 allow_unknown=false)
    #[arg(long)]
    no_unknown: bool,
    /// Print the result as JSON
    #[arg(long)]
    json: bool,
    /// Write a picture: map, potential heat map, path
    #[arg(long)]
    png: Option<PathBuf>,
    /// A plan-check violation is an error (exit 3) instead of a warning
    #[arg(long)]
    checked: bool,
}

fn parse_pair(s: &str) -> Result<[f64; 2], String> {
    let (a, b) = s.split_once(',').ok_or_else(|| format!("expected X,Y, found `{s}`"))?;
    let num = |t: &str| t.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    match (num(a), num(b)) {
        (Some(x), Some(y)) => Ok([x, y]),
        _ => Err(format!("expected two numbers X,Y, found `{s}`")),
    }
}

fn plan(a: PlanArgs) -> ExitCode {
    let map = match load_ros_map(&a.map, true) {
        Ok(m) => m,
        Err(e) => return fail(1, e),
    };
    let world = map.world();
    let (w, h) = (map.width, map.height);
    let to_world = |p: [f64; 2], what: &str| -> Result<[f64; 2], String> {
        if !a.cells {
            return Ok(p);
        }
        let ok = |v: f64, n: usize| v.fract() == 0.0 && v >= 0.0 && v < n as f64;
        if !ok(p[0], w) || !ok(p[1], h) {
            return Err(format!(
                "{what} cell ({}, {}) is not a cell of the {w}x{h} map",
                p[0], p[1]
            ));
        }
        Ok([world.origin[0] + p[0] * world.resolution, world.origin[1] + p[1] * world.resolution])
    };
    let (start, goal) = match (to_world(a.start, "start"), to_world(a.goal, "goal")) {
        (Ok(s), Ok(g)) => (s, g),
        (Err(e), _) | (_, Err(e)) => return fail(1, e),
    };
    for (what, p) in [("start", start), ("goal", goal)] {
        match world.costmap_world_to_map(p, w, h) {
            None => {
                return fail(
                    1,
                    format!(
                        "{what} ({}, {}) lies outside the map (x from {:.4} to {:.4}, y from {:.4} to {:.4})",
                        p[0],
                        p[1],
                        world.origin[0],
                        world.origin[0] + w as f64 * world.resolution,
                        world.origin[1],
                        world.origin[1] + h as f64 * world.resolution
                    ),
                )
            }
            Some(c) if map.costmap.get(c.y * w + c.x) == Some(&COST_OBS) => {
                return fail(1, format!("{what} ({}, {}) lies in an obstacle (cell {}, {})", p[0], p[1], c.x, c.y))
            }
            Some(_) => {}
        }
    }
    // the tolerance search scans a (2·tol/res)² grid: refuse what would not finish
    let side = 2.0 * a.tolerance / world.resolution + 1.0;
    if !(a.tolerance >= 0.0 && a.tolerance.is_finite()) || side * side > 1e8 {
        return fail(
            1,
            format!(
                "tolerance {} is negative or too large for resolution {}",
                a.tolerance, world.resolution
            ),
        );
    }
    let params = PlannerParams {
        tolerance: a.tolerance,
        use_astar: a.algo == AlgoArg::Astar,
        allow_unknown: !a.no_unknown,
        ..PlannerParams::default()
    };
    let mut planner = match NavfnPlanner::new(map.costmap.clone(), w, h, world, params) {
        Ok(p) => p,
        Err(e) => return fail(1, e),
    };
    let t0 = Instant::now();
    let result = planner.create_plan(start, goal);
    let elapsed_ms = t0.elapsed().as_secs_f64() * 1e3;
    let nav = planner.nav();
    let ran_navfn = result.navfn_goal.is_some();
    let report = if ran_navfn { check_plan(&PlanView::of(nav)) } else { Default::default() };
    if let Some(png) = &a.png {
        if ran_navfn {
            let mut pic = PictureInput::of(nav, true);
            // robot start in green, robot goal in blue (NavFn runs them swapped)
            pic.plan.start = nav.goal();
            pic.plan.goal = nav.start();
            if let Err(e) = save_png(png, &pic) {
                return fail(2, format!("{}: {e}", png.display()));
            }
        } else {
            eprintln!("warning: no picture, NavFn did not run ({})", result.status.name());
        }
    }
    // a closed pipe (`| head`) is not an error worth a panic: ignore write failures
    let mut out = std::io::stdout().lock();
    if a.json {
        let v = serde_json::json!({
            "status": result.status.name(),
            "start": start, "goal": goal,
            "algo": format!("{:?}", a.algo).to_lowercase(),
            "navfn_start": result.navfn_start, "navfn_goal": result.navfn_goal,
            "tolerance_used": result.tol_used, "best_goal": result.best,
            "navfn_points": result.navfn_len, "poses": result.world,
            "checks": report, "time_ms": elapsed_ms,
        });
        let _ = writeln!(out, "{}", serde_json::to_string_pretty(&v).unwrap_or_default());
    } else {
        let _ = writeln!(
            out,
            "status {}  poses {}  navfn points {}  tolerance used {}  checks {}  {:.3} ms",
            result.status.name(),
            result.world.len(),
            result.navfn_len,
            result.tol_used,
            if report.is_ok() {
                "ok".to_string()
            } else {
                format!("{} violations", report.count())
            },
            elapsed_ms
        );
        for p in &result.world {
            if writeln!(out, "{:.6} {:.6}", p[0], p[1]).is_err() {
                break;
            }
        }
    }
    let _ = out.flush();
    for v in &report.violations {
        eprintln!("{}: {v}", if a.checked { "error" } else { "warning" });
    }
    if !report.is_ok() && a.checked {
        return ExitCode::from(3);
    }
    if result.status != PlanStatus::Ok {
        eprintln!("no plan: {}", result.status.name());
        return ExitCode::from(1);
    }
    ExitCode::SUCCESS
}

// ------------------------------------------------------------------------------------------
// vouch navfn suite run

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// The paper's harness: no swap, A*, path limit 4·nx
    Paper,
    /// The planner's cell-level call sequence (swapped, atStart Dijkstra or A*)
    Navfn,
    /// World-level NavfnPlanner emulation (test_world.txt, params.txt)
    Planner,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CostsArg {
    /// Map bytes are NavFn costs (the paper suite)
    Raw,
    /// Map bytes are ROS Costmap2D values (suite_ros)
    Ros,
}

#[derive(Args)]
pub struct SuiteRunArgs {
    /// A test file, or a folder searched recursively (sorted) for test files
    path: PathBuf,
    #[arg(long, value_enum, default_value = "paper")]
    mode: ModeArg,
    /// Propagation (paper mode is always A*)
    #[arg(long, value_enum, default_value = "dijkstra")]
    algo: AlgoArg,
    /// Cost input (default: raw, except ros in planner mode)
    #[arg(long, value_enum)]
    costs: Option<CostsArg>,
    /// File name searched in folders (default test.txt; test_world.txt in planner mode)
    #[arg(long)]
    name: Option<String>,
    /// Planner mode world frame (default: params.txt next to each test file, else 0,0 / 1.0)
    #[arg(long, value_parser = parse_pair, allow_hyphen_values = true)]
    origin: Option<[f64; 2]>,
    #[arg(long)]
    res: Option<f64>,
    /// Also run the plan checks on every case; violations are reported on stderr (exit 3)
    #[arg(long)]
    check: bool,
    /// Oracle-contract output (navfn-campaign): --trace hash|cells, --pot
    #[command(flatten)]
    trace: campaign_cmd::TraceArgs,
}

fn suite_run(a: SuiteRunArgs) -> ExitCode {
    if a.trace.active() {
        // The oracle contract's output (CYCLE/PROPEND/POT + CASE/PATH), cell-level modes only.
        let navfn_mode = match a.mode {
            ModeArg::Paper => None,
            ModeArg::Navfn => Some(a.algo == AlgoArg::Astar),
            ModeArg::Planner => return fail(2, "--trace/--pot need --mode paper or navfn"),
        };
        return campaign_cmd::suite_run_traced(&a.path, navfn_mode, &a.trace);
    }
    let mode = match a.mode {
        ModeArg::Paper => SuiteMode::Paper,
        ModeArg::Navfn => SuiteMode::Navfn,
        ModeArg::Planner => SuiteMode::Planner,
    };
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
    let files = match find_test_files(&a.path, &name) {
        Ok(f) if f.is_empty() => return fail(2, format!("no `{name}` below {}", a.path.display())),
        Ok(f) => f,
        Err(e) => return fail(2, e),
    };
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let (mut cases, mut found, mut violations, mut errors) = (0usize, 0usize, 0usize, 0usize);
    let mut text = String::new();
    for f in &files {
        let loaded = read_suite_file(f)
            .map_err(|e| e.to_string())
            .and_then(|file| Ok((file, world_for(&a, f)?)));
        let (file, world) = match loaded {
            Ok(fw) => fw,
            Err(e) => {
                eprintln!("error: {e}");
                errors += 1;
                continue;
            }
        };
        let opts = SuiteOptions { mode, algo: a.algo.into(), costs, world };
        text.clear();
        let _ = writeln!(out, "MAP {}", f.display());
        match run_file(&file, &opts, &mut text) {
            Ok(s) => {
                cases += s.cases;
                found += s.found;
            }
            Err(e) => {
                eprintln!("error: {e}");
                errors += 1;
            }
        }
        if out.write_all(text.as_bytes()).is_err() {
            return ExitCode::from(2); // closed pipe
        }
        if a.check && mode != SuiteMode::Planner {
            violations += check_file(&file, mode, opts.algo, costs);
        }
    }
    let _ = out.flush();
    eprintln!("{cases} cases in {} files, {found} with a path", files.len());
    if a.check {
        eprintln!("plan checks: {violations} violations");
    }
    if errors > 0 {
        ExitCode::from(1)
    } else if violations > 0 {
        ExitCode::from(3)
    } else {
        ExitCode::SUCCESS
    }
}

fn world_for(a: &SuiteRunArgs, test_file: &Path) -> Result<WorldParams, String> {
    let mut w = WorldParams::default();
    let params = test_file.with_file_name("params.txt");
    if params.is_file() {
        w = read_world_params(&params).map_err(|e| e.to_string())?;
    }
    if let Some(o) = a.origin {
        w.origin = o;
    }
    if let Some(r) = a.res {
        if !(r > 0.0 && r.is_finite()) {
            return Err(format!("--res {r} must be a positive number"));
        }
        w.resolution = r;
    }
    Ok(w)
}

fn check_file(file: &SuiteFile, mode: SuiteMode, algo: Algo, costs: CostInput) -> usize {
    let mut runner = CaseRunner::new();
    let mut n = 0;
    for case in &file.cases {
        if runner.run_case(file, case, mode, algo, costs, &mut NoObserver).is_ok() {
            let r = check_plan(&PlanView::of(runner.nav()));
            for v in &r.violations {
                eprintln!("violation: {} case {}: {v}", file.test_path.display(), case.number);
            }
            n += r.count();
        }
    }
    n
}

// ------------------------------------------------------------------------------------------
// vouch navfn bench

#[derive(Args)]
pub struct BenchArgs {
    /// The shared navfn data folder (with suite/ and suite_ros/)
    #[arg(long, default_value = "../shared/navfn")]
    data: PathBuf,
    /// Repetitions of the whole suite (the best and the mean are reported)
    #[arg(long, default_value_t = 5)]
    repeat: usize,
    /// Repetitions of the 400×400 default pair
    #[arg(long, default_value_t = 50)]
    repeat_pair: usize,
}

fn bench(a: BenchArgs) -> ExitCode {
    match vouch_navfn::bench::run(&a.data, a.repeat, a.repeat_pair, &mut std::io::stdout()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(2, e),
    }
}
