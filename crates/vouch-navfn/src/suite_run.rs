//! Running suite files and printing the golden line format of `shared/navfn/golden/README.md`
//! (`CASE` + `PATH` lines, `WORLD` in planner mode, float bit patterns, FNV-1a-64 hashes).

use std::fmt::Write as _;

use crate::core::numeric::{path_fnv, potential_fnv};
use crate::core::{Algo, Cell, CoreError, NavFn, SearchObserver};
use crate::maps::{SuiteCase, SuiteFile};
use crate::planner::{NavfnPlanner, PlanStatus, PlannerParams, WorldParams};

/// How the map bytes are turned into NavFn costs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CostInput {
    /// The bytes are NavFn costs, copied verbatim (the paper suite).
    Raw,
    /// The bytes are ROS Costmap2D values: `setCostmap(isROS=true, allow_unknown=true)`.
    Ros,
}

/// Which call sequence runs a case (golden/README.md, "Modes").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SuiteMode {
    /// The paper's harness: no swap, A* only, path limit `4*nx`.
    Paper,
    /// The planner's cell-level call sequence: swapped, `atStart` Dijkstra or A*, limit `max(nx,ny)*4`.
    Navfn,
    /// World-level emulation of `NavfnPlanner::createPlan`.
    Planner,
}

/// Everything that selects how a suite file is run.
#[derive(Clone, Copy, Debug)]
pub struct SuiteOptions {
    pub mode: SuiteMode,
    /// Ignored in paper mode (always A*).
    pub algo: Algo,
    pub costs: CostInput,
    /// World frame for planner mode.
    pub world: WorldParams,
}

/// Result of one cell-level case (paper or navfn mode).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaseOutcome {
    /// Cell given to `setStart` (path extraction starts here).
    pub navfn_start: Cell,
    /// Cell given to `setGoal` (propagation starts here).
    pub navfn_goal: Cell,
    /// Propagation return value.
    pub prop: bool,
    /// `calcPath` return value (0 = failure).
    pub len: usize,
    /// A* only: `last_path_cost_`.
    pub last_path_cost: Option<f32>,
}

/// A case that cannot be run.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    #[error("{}:{line}: case {number}: a point lies outside the {width}x{height} map", path.display())]
    OutsideMap { path: std::path::PathBuf, line: usize, number: usize, width: usize, height: usize },
    #[error(transparent)]
    Core(#[from] CoreError),
}

/// Runs cell-level cases on one reusable NavFn (arrays kept while the map size is unchanged).
pub struct CaseRunner {
    nav: NavFn,
}

impl Default for CaseRunner {
    fn default() -> Self {
        Self::new()
    }
}

impl CaseRunner {
    pub fn new() -> Self {
        CaseRunner { nav: NavFn::new(1, 1).expect("1x1 is a valid size") }
    }

    /// The NavFn of the last case: potential, costs, path.
    pub fn nav(&self) -> &NavFn {
        &self.nav
    }
    pub fn nav_mut(&mut self) -> &mut NavFn {
        &mut self.nav
    }

    /// Run one case in `paper` or `navfn` mode (planner mode goes through [`NavfnPlanner`]).
    pub fn run_case<O: SearchObserver>(
        &mut self,
        file: &SuiteFile,
        case: &SuiteCase,
        mode: SuiteMode,
        algo: Algo,
        costs: CostInput,
        obs: &mut O,
    ) -> Result<CaseOutcome, CaseError> {
        let (from, to) =
            case.cells(file.width, file.height).ok_or_else(|| CaseError::OutsideMap {
                path: file.test_path.clone(),
                line: case.line,
                number: case.number,
                width: file.width,
                height: file.height,
            })?;
        let from = Cell::new(from[0], from[1]);
        let to = Cell::new(to[0], to[1]);
        match mode {
            SuiteMode::Paper => self.run_paper(&file.map, file.width, file.height, from, to, obs),
            _ => self.run_navfn(&file.map, file.width, file.height, costs, algo, from, to, obs),
        }
    }

    /// Sizes the reused NavFn for the map and loads its costs (shared by both call sequences).
    fn load_map(
        &mut self,
        map: &[u8],
        nx: usize,
        ny: usize,
        costs: CostInput,
    ) -> Result<&mut NavFn, CaseError> {
        let nav = &mut self.nav;
        nav.resize(nx, ny)?;
        match costs {
            CostInput::Raw => nav.set_costs_raw(map)?,
            CostInput::Ros => nav.set_costs_ros(map, true)?,
        }
        Ok(nav)
    }

    /// The paper harness: NavFn goal = `to`, NavFn start = `from` (no swap), set-up,
    /// `propNavFnAstar(max(nx*ny/20, nx+ny))`, `calcPath(4*nx)`; raw costs.
    pub fn run_paper<O: SearchObserver>(
        &mut self,
        map: &[u8],
        nx: usize,
        ny: usize,
        from: Cell,
        to: Cell,
        obs: &mut O,
    ) -> Result<CaseOutcome, CaseError> {
        let nav = self.load_map(map, nx, ny, CostInput::Raw)?;
        nav.set_goal(to)?;
        nav.set_start(from)?;
        nav.setup();
        let cycles = nav.default_cycles();
        let prop = nav.propagate_astar(cycles, obs);
        let len = nav.calc_path(4 * nx, obs);
        Ok(CaseOutcome {
            navfn_start: from,
            navfn_goal: to,
            prop,
            len,
            last_path_cost: Some(nav.last_path_cost()),
        })
    }

    /// The planner's cell-level call sequence: NavFn start = `to`, NavFn goal = `from`
    /// (swapped), `calcNavFnDijkstra(atStart=true)` or `calcNavFnAstar`, `calcPath(max(nx,ny)*4)`.
    #[allow(clippy::too_many_arguments)]
    pub fn run_navfn<O: SearchObserver>(
        &mut self,
        map: &[u8],
        nx: usize,
        ny: usize,
        costs: CostInput,
        algo: Algo,
        from: Cell,
        to: Cell,
        obs: &mut O,
    ) -> Result<CaseOutcome, CaseError> {
        let nav = self.load_map(map, nx, ny, costs)?;
        nav.set_start(to)?;
        nav.set_goal(from)?;
        let (prop, last_path_cost) = match algo {
            Algo::Dijkstra => (nav.calc_dijkstra(true, obs), None),
            Algo::Astar => {
                let p = nav.calc_astar(obs);
                (p, Some(nav.last_path_cost()))
            }
        };
        let len = nav.calc_path(nx.max(ny) * 4, obs);
        Ok(CaseOutcome { navfn_start: to, navfn_goal: from, prop, len, last_path_cost })
    }
}

/// C's `printf("%.17g", v)` (used for the case coordinates of the CASE line).
pub fn fmt_g17(v: f64) -> String {
    if v == 0.0 {
        return if v.is_sign_negative() { "-0".into() } else { "0".into() };
    }
    if !v.is_finite() {
        return if v.is_nan() {
            "nan".into()
        } else if v > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    // the exponent after rounding to 17 significant digits decides between the two styles
    let sci = format!("{:.16e}", v);
    let (mant, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if (-4..17).contains(&exp) {
        let decimals = (16 - exp) as usize;
        strip_zeros(format!("{:.*}", decimals, v))
    } else {
        let m = strip_zeros(mant.to_string());
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{m}e{sign}{:02}", exp.abs())
    }
}

fn strip_zeros(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn write_path_line(out: &mut String, tag: &str, path: &[[f32; 2]]) {
    out.push_str(tag);
    for p in path {
        let _ = write!(out, " {:08x}:{:08x}", p[0].to_bits(), p[1].to_bits());
    }
    out.push('\n');
}

/// Append the CASE and PATH lines of one cell-level case.
pub fn write_cell_case(out: &mut String, case: &SuiteCase, o: &CaseOutcome, nav: &NavFn) {
    let [x0, y0, x1, y1] = case.coords.map(fmt_g17);
    let lpc = match o.last_path_cost {
        Some(c) => format!("{:08x}", c.to_bits()),
        None => "na".to_string(),
    };
    let _ = writeln!(
        out,
        "CASE {} {x0} {y0} {x1} {y1} navfn_start={},{} navfn_goal={},{} prop={} len={} last_path_cost={lpc} pot_fnv={:016x} path_fnv={:016x}",
        case.number,
        o.navfn_start.x,
        o.navfn_start.y,
        o.navfn_goal.x,
        o.navfn_goal.y,
        o.prop as u8,
        o.len,
        potential_fnv(nav.potential()),
        path_fnv(nav.path()),
    );
    write_path_line(out, "PATH", nav.path());
}

/// Counters of one run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunStats {
    pub cases: usize,
    /// Cases with a non-empty path.
    pub found: usize,
}

/// Run every case of `file` and append the golden-format lines to `out`.
pub fn run_file(
    file: &SuiteFile,
    opts: &SuiteOptions,
    out: &mut String,
) -> Result<RunStats, CaseError> {
    let mut stats = RunStats::default();
    match opts.mode {
        SuiteMode::Planner => {
            let mut planner = NavfnPlanner::new(
                file.map.clone(),
                file.width,
                file.height,
                opts.world,
                PlannerParams { use_astar: opts.algo == Algo::Astar, ..PlannerParams::default() },
            )?;
            for case in &file.cases {
                let [x0, y0, x1, y1] = case.coords;
                let plan = planner.create_plan([x0, y0], [x1, y1]);
                stats.cases += 1;
                stats.found += (plan.status == PlanStatus::Ok) as usize;
                crate::planner::write_planner_case(out, case, &plan, planner.nav());
            }
        }
        mode => {
            let mut runner = CaseRunner::new();
            let algo = if mode == SuiteMode::Paper { Algo::Astar } else { opts.algo };
            let mut obs = crate::core::NoObserver;
            for case in &file.cases {
                let o = runner.run_case(file, case, mode, algo, opts.costs, &mut obs)?;
                stats.cases += 1;
                stats.found += (o.len > 0) as usize;
                write_cell_case(out, case, &o, runner.nav());
            }
        }
    }
    Ok(stats)
}

#[cfg(test)]
mod tests {
    use super::fmt_g17;

    // the literals are written with all 17 digits on purpose: they are what printf prints
    #[allow(clippy::excessive_precision)]
    #[test]
    fn g17_matches_printf() {
        assert_eq!(fmt_g17(188.0), "188");
        assert_eq!(fmt_g17(-1.2999999999999989), "-1.2999999999999989");
        assert_eq!(fmt_g17(5.2000000000000011), "5.2000000000000011");
        assert_eq!(fmt_g17(-7.0), "-7");
        assert_eq!(fmt_g17(0.05), "0.050000000000000003");
        assert_eq!(fmt_g17(1e20), "1e+20");
        assert_eq!(fmt_g17(1.5e-7), "1.4999999999999999e-07");
    }
}
