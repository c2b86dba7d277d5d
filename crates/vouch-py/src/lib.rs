//! The Python module `vouch` (PyO3, built by maturin): nav2 maps read as map_server reads
//! them, vouch's bit-exact NavFn planner with nav2's parameters, the run-time plan checks,
//! nav2's costmap inflation and the robot body check (`costmap.rs`), `check-bag` on rosbag2
//! recordings, suite runs in the golden line format and campaign shards. Arrays go in and out as numpy arrays (row 0 = the map's bottom row, as in ROS).
//! Bad input raises `ValueError` with the library's located message; unreadable files raise
//! `OSError`.

// The library never prints, exits or panics on its own: callers get data and typed errors.
// Tests (`cfg(test)`) may unwrap; an exception in library code is an `#[expect(..., reason)]`
// in place.
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::print_stdout,
        clippy::print_stderr,
        clippy::exit,
        clippy::dbg_macro,
        clippy::todo,
        clippy::unimplemented
    )
)]

mod costmap;

use std::path::PathBuf;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyReadonlyArray2};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use vouch_navfn::bagcheck::{BagCheckOptions, ReplayMode, check_bag_file};
use vouch_navfn::campaign::runner::{CampaignOptions, run_campaign};
use vouch_navfn::campaign::shard::{Shard, ShardBy};
use vouch_navfn::checks::{PlanView, check_plan};
use vouch_navfn::core::{Algo, Cell};
use vouch_navfn::maps::{MapError, WorldParams, load_ros_map, read_suite_file};
use vouch_navfn::planner::{End, NavfnPlanner, PlannerParams, Pose};
use vouch_navfn::suite::run_file;
use vouch_navfn::suite::{CostInput, RunMode, SuiteMode, SuiteOptions};

fn map_error(e: MapError) -> PyErr {
    if e.is_io() { PyOSError::new_err(e.to_string()) } else { PyValueError::new_err(e.located()) }
}

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A 2-D numpy array of `rows`×`cols` from row-major values.
fn grid<'py, T: numpy::Element>(
    py: Python<'py>,
    rows: usize,
    cols: usize,
    values: Vec<T>,
) -> PyResult<Bound<'py, numpy::PyArray2<T>>> {
    Ok(Array2::from_shape_vec((rows, cols), values).map_err(value_error)?.into_pyarray(py))
}

/// Reads a map as map_server does (a YAML naming a PGM/PNG, or an image) and returns a dict:
/// `costmap` (uint8, nav2's static layer), `occupancy` (int8), `resolution`, `origin`
/// (x, y, yaw), `negate`, `occupied_thresh`, `free_thresh`, `mode`, `image`.
#[pyfunction]
fn load_map<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let map = load_ros_map(&path, true).map_err(map_error)?;
    let d = PyDict::new(py);
    let (h, w) = (map.height, map.width);
    d.set_item("costmap", grid(py, h, w, map.costmap)?)?;
    d.set_item("occupancy", grid(py, h, w, map.occupancy)?)?;
    let m = &map.meta;
    d.set_item("resolution", m.resolution)?;
    d.set_item("origin", (m.origin[0], m.origin[1], m.origin[2]))?;
    d.set_item("negate", m.negate)?;
    d.set_item("occupied_thresh", m.occupied_thresh)?;
    d.set_item("free_thresh", m.free_thresh)?;
    d.set_item("mode", format!("{:?}", m.mode).to_lowercase())?;
    d.set_item("image", m.image.display().to_string())?;
    Ok(d)
}

/// Plans like nav2's NavfnPlanner on a costmap (uint8 array, Costmap2D values, shape
/// (height, width)) from `start` to `goal` (metres, or cells with `cells=True`). Returns a dict:
/// `status`, `poses` (n×7: x y z qx qy qz qw), `navfn_path` (m×2, cell units, NavFn order),
/// `potential` (float32, height×width), `navfn_costs`, `navfn_start`, `navfn_goal`,
/// `tolerance_used`, `best_goal`, `violations` (the plan checks; empty when they hold).
#[pyfunction]
#[pyo3(signature = (costmap, start, goal, *, resolution=1.0, origin=(0.0, 0.0), tolerance=0.5,
    use_astar=false, allow_unknown=true, max_cycles_factor=4, use_final_approach_orientation=false,
    start_yaw=0.0, goal_yaw=0.0, cells=false))]
#[allow(clippy::too_many_arguments)] // Python keyword arguments
fn plan<'py>(
    py: Python<'py>,
    costmap: PyReadonlyArray2<'py, u8>,
    start: (f64, f64),
    goal: (f64, f64),
    resolution: f64,
    origin: (f64, f64),
    tolerance: f64,
    use_astar: bool,
    allow_unknown: bool,
    max_cycles_factor: usize,
    use_final_approach_orientation: bool,
    start_yaw: f64,
    goal_yaw: f64,
    cells: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let view = costmap.as_array();
    let (h, w) = view.dim();
    let costs: Vec<u8> = view.iter().copied().collect();
    let world = WorldParams { origin: [origin.0, origin.1], resolution };
    let params = PlannerParams {
        tolerance,
        use_astar,
        allow_unknown,
        max_cycles_factor,
        use_final_approach_orientation,
    };
    let mut planner = NavfnPlanner::new(&costs, w, h, world, params).map_err(value_error)?;
    let (s, g) = if cells {
        let s = planner.cell_point(End::Start, [start.0, start.1]).map_err(value_error)?;
        (s, planner.cell_point(End::Goal, [goal.0, goal.1]).map_err(value_error)?)
    } else {
        ([start.0, start.1], [goal.0, goal.1])
    };
    let out = planner.create_plan_poses(
        &Pose::from_xy_yaw(s[0], s[1], start_yaw),
        &Pose::from_xy_yaw(g[0], g[1], goal_yaw),
    );
    let nav = planner.nav();
    let ran = out.plan.navfn_goal.is_some();
    let d = PyDict::new(py);
    d.set_item("status", out.plan.status.name())?;
    let poses: Vec<f64> =
        out.poses.iter().flat_map(|p| p.position.into_iter().chain(p.orientation)).collect();
    d.set_item("poses", grid(py, out.poses.len(), 7, poses)?)?;
    let found = out.plan.status == vouch_navfn::planner::PlanStatus::Ok;
    let path: Vec<[f32; 2]> = if found { nav.path().to_vec() } else { Vec::new() };
    d.set_item("navfn_path", grid(py, path.len(), 2, path.concat())?)?;
    if ran {
        d.set_item("potential", grid(py, h, w, nav.potential().to_vec())?)?;
        d.set_item("navfn_costs", grid(py, h, w, nav.costs().to_vec())?)?;
        let report = check_plan(&PlanView::of(nav));
        let v: Vec<String> = report.violations.iter().map(|v| v.to_string()).collect();
        d.set_item("violations", v)?;
    } else {
        d.set_item("potential", py.None())?;
        d.set_item("navfn_costs", py.None())?;
        d.set_item("violations", Vec::<String>::new())?;
    }
    let cell = |c: Option<Cell>| c.map(|c| (c.x, c.y));
    d.set_item("navfn_start", cell(out.plan.navfn_start))?;
    d.set_item("navfn_goal", cell(out.plan.navfn_goal))?;
    d.set_item("tolerance_used", out.plan.tol_used)?;
    d.set_item("best_goal", out.plan.best.map(|b| (b[0], b[1])))?;
    Ok(d)
}

/// The run-time checks of one NavFn plan (ValidPath, FinitePotentialPath, PositionSafe,
/// Progress, end points) on its arrays: NavFn costs (uint8) and potential (float32), both
/// height×width, the path (m×2, NavFn order), NavFn start and goal cells. Returns the
/// violations as strings (empty when every property holds).
#[pyfunction]
fn check(
    navfn_costs: PyReadonlyArray2<'_, u8>,
    potential: PyReadonlyArray2<'_, f32>,
    path: PyReadonlyArray2<'_, f32>,
    navfn_start: (usize, usize),
    navfn_goal: (usize, usize),
) -> PyResult<Vec<String>> {
    let costs = navfn_costs.as_array();
    let (ny, nx) = costs.dim();
    if potential.as_array().dim() != (ny, nx) {
        return Err(value_error("potential and costs must have the same shape"));
    }
    if path.as_array().dim().1 != 2 && path.as_array().dim().0 > 0 {
        return Err(value_error("the path must be an n×2 array"));
    }
    let costs: Vec<u8> = costs.iter().copied().collect();
    let pot: Vec<f32> = potential.as_array().iter().copied().collect();
    let pts: Vec<[f32; 2]> = path.as_array().rows().into_iter().map(|r| [r[0], r[1]]).collect();
    let view = PlanView {
        nx,
        ny,
        costs: &costs,
        potential: &pot,
        path: &pts,
        start: Cell::new(navfn_start.0, navfn_start.1),
        goal: Cell::new(navfn_goal.0, navfn_goal.1),
    };
    Ok(check_plan(&view).violations.iter().map(|v| v.to_string()).collect())
}

fn json<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value).map_err(value_error)?;
    py.import("json")?.call_method1("loads", (text,))
}

/// Checks every plan of a rosbag2 recording (folder or .mcap/.db3 file) and returns the report
/// as a dict (`plans`, `summary`), as `vouch navfn check-bag --json` prints it.
#[pyfunction]
#[pyo3(signature = (path, *, replay="check", tolerance=0.5, use_astar=false, allow_unknown=true))]
fn check_bag<'py>(
    py: Python<'py>,
    path: PathBuf,
    replay: &str,
    tolerance: f64,
    use_astar: bool,
    allow_unknown: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let replay = match replay {
        "check" => ReplayMode::Check,
        "report" => ReplayMode::Report,
        "off" => ReplayMode::Off,
        other => {
            return Err(value_error(format!("replay must be check, report or off, not {other}")));
        }
    };
    let mut opts = BagCheckOptions { replay, ..BagCheckOptions::default() };
    opts.params = PlannerParams { tolerance, use_astar, allow_unknown, ..PlannerParams::default() };
    let report = check_bag_file(&path, &opts)
        .map_err(|e| if e.is_io() { PyOSError::new_err(e.to_string()) } else { value_error(e) })?;
    json(py, &report)
}

fn parse_algo(name: &str) -> PyResult<Algo> {
    match name {
        "dijkstra" => Ok(Algo::Dijkstra),
        "astar" => Ok(Algo::Astar),
        other => Err(value_error(format!("algo must be dijkstra or astar, not {other}"))),
    }
}

/// Runs every case of a suite test file (`test.txt` + map) and returns the golden line format
/// (MAP / CASE / PATH [/ WORLD]) that `vouch navfn suite run` prints. `mode` is paper, navfn or
/// planner (planner mode reads ROS costs and needs `origin` and `resolution`).
#[pyfunction]
#[pyo3(signature = (test_file, *, mode="navfn", algo="dijkstra", origin=(0.0, 0.0), resolution=1.0))]
fn run_suite(
    test_file: PathBuf,
    mode: &str,
    algo: &str,
    origin: (f64, f64),
    resolution: f64,
) -> PyResult<String> {
    let mode = match mode {
        "paper" => SuiteMode::Paper,
        "navfn" => SuiteMode::Navfn,
        "planner" => SuiteMode::Planner,
        other => {
            return Err(value_error(format!("mode must be paper, navfn or planner, not {other}")));
        }
    };
    let file = read_suite_file(&test_file).map_err(map_error)?;
    let opts = SuiteOptions {
        mode,
        algo: parse_algo(algo)?,
        costs: CostInput::Raw,
        world: WorldParams { origin: [origin.0, origin.1], resolution },
    };
    let mut out = String::new();
    run_file(&file, &opts, &mut out).map_err(value_error)?;
    Ok(out)
}

/// Runs shard `index` of `count` (whole maps per shard) of the verification campaign on a suite
/// folder and returns its report as a dict (merge shards with `vouch navfn report merge`).
#[pyfunction]
#[pyo3(signature = (suite_dir, *, index=0, count=1, mode="paper", algo="dijkstra",
    metamorphic=true, optimality=true))]
#[allow(clippy::too_many_arguments)] // Python keyword arguments
fn run_campaign_shard<'py>(
    py: Python<'py>,
    suite_dir: PathBuf,
    index: u32,
    count: u32,
    mode: &str,
    algo: &str,
    metamorphic: bool,
    optimality: bool,
) -> PyResult<Bound<'py, PyAny>> {
    if count == 0 || index >= count {
        return Err(value_error(format!("shard {index}/{count}: need 0 <= index < count")));
    }
    let suite_mode = match mode {
        "paper" => SuiteMode::Paper,
        "navfn" => SuiteMode::Navfn,
        other => return Err(value_error(format!("mode must be paper or navfn, not {other}"))),
    };
    let run_mode =
        RunMode::new(suite_mode, parse_algo(algo)?).ok_or_else(|| value_error("mode"))?;
    let opts = CampaignOptions {
        mode: run_mode,
        shard: Shard { index, count, by: ShardBy::default() },
        metamorphic,
        optimality,
        ..CampaignOptions::default()
    };
    let report = run_campaign(&suite_dir, &opts, &(), None)
        .map_err(|e| if e.is_io() { PyOSError::new_err(e.to_string()) } else { value_error(e) })?;
    json(py, &report)
}

/// The module (named `vouch` in Python; the Rust library is `vouch_py` so that its
/// documentation does not collide with the `vouch` binary's).
#[pymodule]
#[pyo3(name = "vouch")]
fn vouch_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(load_map, m)?)?;
    m.add_function(wrap_pyfunction!(plan, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(costmap::inflate_costmap, m)?)?;
    m.add_function(wrap_pyfunction!(costmap::check_body, m)?)?;
    m.add_function(wrap_pyfunction!(check_bag, m)?)?;
    m.add_function(wrap_pyfunction!(run_suite, m)?)?;
    m.add_function(wrap_pyfunction!(run_campaign_shard, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
