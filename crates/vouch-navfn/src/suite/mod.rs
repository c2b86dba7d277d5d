//! Running suite files: the call sequences of the golden modes (`golden/README.md`, "Modes")
//! on one reused NavFn, and the golden line format (`golden.rs`).

mod golden;

pub use golden::{RunStats, fmt_g17, push_g17, run_file, write_cell_case, write_planner_case};

use crate::core::{Algo, Cell, CoreError, NavFn, SearchObserver};
use crate::maps::{SuiteCase, SuiteFile, WorldParams};
use crate::planner::PlanError;

/// How the map bytes are turned into NavFn costs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CostInput {
    /// The bytes are NavFn costs, copied verbatim (the paper suite).
    Raw,
    /// The bytes are ROS Costmap2D values: `setCostmap(isROS=true, allow_unknown=true)`.
    Ros,
}

/// Which call sequence runs a case (golden/README.md, "Modes"), as chosen with `--mode`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SuiteMode {
    /// The paper's harness: no swap, A* only, path limit `4*nx`.
    Paper,
    /// The planner's cell-level call sequence: swapped, `atStart` Dijkstra or A*, limit `max(nx,ny)*4`.
    Navfn,
    /// World-level emulation of `NavfnPlanner::createPlan`.
    Planner,
}

/// A cell-level call sequence with its propagation: the modes a case runs in without the
/// planner layer (serialised as `paper`, `navfn-dijkstra`, `navfn-astar`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum RunMode {
    /// The paper's harness: A*, no swap, `calcPath(4*nx)`.
    #[default]
    #[serde(rename = "paper")]
    Paper,
    /// The planner's cell-level call sequence with `atStart` Dijkstra.
    #[serde(rename = "navfn-dijkstra")]
    NavfnDijkstra,
    /// The planner's cell-level call sequence with A*.
    #[serde(rename = "navfn-astar")]
    NavfnAstar,
}

impl RunMode {
    /// The cell-level sequence of `mode` with `algo` (paper mode is always A*); `None` for
    /// planner mode, which is not cell-level.
    pub fn new(mode: SuiteMode, algo: Algo) -> Option<RunMode> {
        match (mode, algo) {
            (SuiteMode::Paper, _) => Some(RunMode::Paper),
            (SuiteMode::Navfn, Algo::Dijkstra) => Some(RunMode::NavfnDijkstra),
            (SuiteMode::Navfn, Algo::Astar) => Some(RunMode::NavfnAstar),
            (SuiteMode::Planner, _) => None,
        }
    }

    /// The propagation this sequence runs.
    pub fn algo(self) -> Algo {
        match self {
            RunMode::NavfnDijkstra => Algo::Dijkstra,
            RunMode::Paper | RunMode::NavfnAstar => Algo::Astar,
        }
    }

    /// `--mode`/`--algo` arguments naming this sequence (the oracle contract's, and the CLI's).
    pub fn args(self) -> &'static [&'static str] {
        match self {
            RunMode::Paper => &["--mode", "paper"],
            RunMode::NavfnDijkstra => &["--mode", "navfn", "--algo", "dijkstra"],
            RunMode::NavfnAstar => &["--mode", "navfn", "--algo", "astar"],
        }
    }

    /// The name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            RunMode::Paper => "paper",
            RunMode::NavfnDijkstra => "navfn-dijkstra",
            RunMode::NavfnAstar => "navfn-astar",
        }
    }
}

/// Everything that selects how a suite file is run.
#[derive(Clone, Copy, Debug)]
pub struct SuiteOptions {
    /// The call sequence.
    pub mode: SuiteMode,
    /// Ignored in paper mode (always A*).
    pub algo: Algo,
    /// How map bytes become NavFn costs (cell-level modes; planner mode reads ROS values).
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
#[derive(Debug, thiserror::Error, miette::Diagnostic)]
pub enum CaseError {
    /// A case point does not truncate into the map.
    #[error("{}:{line}: case {number}: a point lies outside the {width}x{height} map", path.display())]
    #[diagnostic(code(navfn::E030))]
    OutsideMap {
        /// The test file.
        path: std::path::PathBuf,
        /// 1-based line of the case.
        line: usize,
        /// Case number.
        number: usize,
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
    },
    /// The core refused the case.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Core(#[from] CoreError),
    /// The planner refused the set-up (planner mode).
    #[error(transparent)]
    #[diagnostic(transparent)]
    Plan(#[from] PlanError),
}

/// A map as a case runner reads it.
#[derive(Clone, Copy, Debug)]
pub struct MapRef<'a> {
    /// `nx*ny` bytes, cell (x, y) at `y*nx + x`.
    pub bytes: &'a [u8],
    /// Columns.
    pub nx: usize,
    /// Rows.
    pub ny: usize,
    /// How the bytes become NavFn costs (paper mode always reads them raw).
    pub costs: CostInput,
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
    /// A runner with a 1×1 NavFn (resized by the first case).
    #[expect(clippy::expect_used, reason = "1×1 is within every size limit of `NavFn::new`")]
    pub fn new() -> Self {
        CaseRunner { nav: NavFn::new(1, 1).expect("1x1 is a valid size") }
    }

    /// The NavFn of the last case: potential, costs, path.
    pub fn nav(&self) -> &NavFn {
        &self.nav
    }
    /// The NavFn, for set-up knobs such as [`NavFn::set_pri_inc`].
    pub fn nav_mut(&mut self) -> &mut NavFn {
        &mut self.nav
    }

    /// Run one case of a suite file in a cell-level mode (planner mode goes through
    /// [`crate::planner::NavfnPlanner`]).
    pub fn run_case<O: SearchObserver>(
        &mut self,
        file: &SuiteFile,
        case: &SuiteCase,
        mode: RunMode,
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
        let map = MapRef { bytes: &file.map, nx: file.width, ny: file.height, costs };
        self.run(mode, map, from, to, obs)
    }

    /// Run a case from `from` to `to` in a cell-level mode.
    pub fn run<O: SearchObserver>(
        &mut self,
        mode: RunMode,
        map: MapRef<'_>,
        from: Cell,
        to: Cell,
        obs: &mut O,
    ) -> Result<CaseOutcome, CaseError> {
        match mode {
            RunMode::Paper => self.run_paper(map.bytes, map.nx, map.ny, from, to, obs),
            m => self.run_navfn(map, m.algo(), from, to, obs),
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
    pub fn run_navfn<O: SearchObserver>(
        &mut self,
        map: MapRef<'_>,
        algo: Algo,
        from: Cell,
        to: Cell,
        obs: &mut O,
    ) -> Result<CaseOutcome, CaseError> {
        let (nx, ny) = (map.nx, map.ny);
        let nav = self.load_map(map.bytes, nx, ny, map.costs)?;
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

#[cfg(test)]
mod tests {
    use super::{fmt_g17, push_g17};

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

    /// The integer fast path prints what the general `%.17g` path prints.
    #[allow(clippy::excessive_precision)]
    #[test]
    fn g17_fast_path_agrees() {
        for v in [
            0.0,
            -0.0,
            5.0,
            -7.0,
            188.0,
            4095.0,
            1e14,
            -123456789.0,
            999999999999999.0,
            1e15,
            0.5,
            -1.2999999999999989,
        ] {
            let mut s = String::new();
            push_g17(&mut s, v);
            assert_eq!(s, fmt_g17(v), "{v}");
        }
    }
}
