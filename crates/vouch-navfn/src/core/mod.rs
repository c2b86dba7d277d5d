//! The NavFn numeric core: potential propagation (Dijkstra with the `atStart` stop, and A*)
//! and path extraction, bit-exact with nav2's `navfn.cpp` (see `shared/navfn/SEMANTICS.md`).
//!
//! Memory layout: one flat array per quantity (`cost` bytes, `pot` floats, the gradient
//! pairs in `grad` (x and y side by side: path extraction reads them together; in column
//! bands, `grad.rs`), `blocked` flags as bytes: upstream's `pending` merged with the obstacle
//! test of its push) and three priority buffers of fixed capacity. The three arrays the propagation sweeps live
//! on huge pages when they are large (`cells.rs`). Nothing is allocated during a plan; a
//! [`NavFn`] keeps its arrays between plans of the same map size.
//!
//! Float discipline: every operation is written in the exact order and width of
//! SEMANTICS.md §4–6; `f64` appears only where the C++ evaluates in double. No `mul_add`.

// `a = a + b` is kept where SEMANTICS.md writes `a = a ⊕ b`, to read side by side with it.
#![allow(clippy::assign_op_pattern)]

mod cells;
mod costs;
mod grad;
pub mod numeric;
pub mod observer;
mod path;
mod propagate;

use cells::CellArray;
use grad::GradCache;
use propagate::PriorityBuf;

pub use costs::{
    COST_NEUTRAL, COST_OBS, COST_OBS_ROS, COST_UNKNOWN_ROS, FREE_SPACE_ROS, ROS_COST_TABLE,
    ros_to_navfn_cost,
};
pub use observer::{
    CycleView, NoObserver, PathStartView, PropagationEnd, PropagationEndView, SearchObserver,
};

/// Potential of unreached cells (exactly representable in float32, bits `0x501502f9`).
pub const POT_HIGH: f32 = 1.0e10;
/// Capacity of each of the three priority buffers.
pub const PRIORITY_BUF_SIZE: usize = 10_000;
/// Threshold increment `priInc` (2·COST_NEUTRAL).
pub const PRI_INC: f32 = 100.0;
/// Initial threshold `curT`.
pub const CUR_T_INIT: f32 = 254.0;

/// Which propagation NavFn runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Algo {
    /// `calcNavFnDijkstra` (with `atStart` chosen by the caller).
    Dijkstra,
    /// `calcNavFnAstar` / `propNavFnAstar`.
    Astar,
}

/// A grid cell, `x` = column, `y` = row.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
pub struct Cell {
    pub x: usize,
    pub y: usize,
}

impl Cell {
    pub fn new(x: usize, y: usize) -> Self {
        Cell { x, y }
    }
}

/// Errors of the core API (all caused by caller input, never by the search itself).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error, miette::Diagnostic)]
pub enum CoreError {
    /// The map size cannot hold NavFn's arrays.
    #[error("map size {nx}x{ny} is not usable: NavFn needs at least 1x1 cells and fewer than 2^31")]
    #[diagnostic(code(navfn::E001))]
    BadSize {
        /// Columns.
        nx: usize,
        /// Rows.
        ny: usize,
    },
    /// A start or goal cell outside the map.
    #[error("{what} cell ({x}, {y}) lies outside the {nx}x{ny} map")]
    #[diagnostic(code(navfn::E002))]
    CellOutside {
        /// Which end (`NavFn start` or `NavFn goal`).
        what: &'static str,
        /// Column of the cell.
        x: usize,
        /// Row of the cell.
        y: usize,
        /// Columns of the map.
        nx: usize,
        /// Rows of the map.
        ny: usize,
    },
    /// A cost array of the wrong length.
    #[error("cost array has {got} bytes, the {nx}x{ny} map needs {want}")]
    #[diagnostic(code(navfn::E003))]
    CostLength {
        /// Bytes given.
        got: usize,
        /// Bytes needed.
        want: usize,
        /// Columns.
        nx: usize,
        /// Rows.
        ny: usize,
    },
}

/// A NavFn instance: the arrays of `navfn.cpp` for one map size, reused between plans.
pub struct NavFn {
    pub(crate) nx: usize,
    pub(crate) ny: usize,
    pub(crate) ns: usize,
    pub(crate) cost: CellArray<u8>,
    pub(crate) pot: CellArray<f32>,
    /// Cached normalised gradient `(gx, gy)` of each cell (`gradx`/`grady` upstream), with
    /// the cells to clear at the next set-up.
    pub(crate) grad: GradCache,
    /// 1 while a cell may not be queued: it is queued already (`pending` upstream) or it is an
    /// obstacle (cost ≥ 254, the other half of upstream's push test). Set up from the costs
    /// by `setup`; bytes so that they can be mapped.
    pub(crate) blocked: CellArray<u8>,
    pub(crate) cur: PriorityBuf,
    pub(crate) next: PriorityBuf,
    pub(crate) over: PriorityBuf,
    pub(crate) cur_t: f32,
    pub(crate) start: Cell,
    pub(crate) goal: Cell,
    /// Points recorded by the last `calc_path`, also on failure (the C++ buffer).
    pub(crate) path: Vec<[f32; 2]>,
    /// Return value of the last `calc_path` (0 = failure).
    pub(crate) path_len: usize,
    pub(crate) last_path_cost: f32,
    /// Threshold increment `priInc` (a NavFn member upstream; only perturbation tests change it).
    pub(crate) pri_inc: f32,
    /// Large arrays on transparent huge pages ([`NavFn::set_huge_pages`]).
    pub(crate) huge_pages: bool,
}

impl NavFn {
    /// Arrays for an `nx`×`ny` map (`setNavArr`). Costs start at COST_NEUTRAL.
    pub fn new(nx: usize, ny: usize) -> Result<Self, CoreError> {
        let ns = checked_size(nx, ny)?;
        Ok(NavFn {
            nx,
            ny,
            ns,
            cost: CellArray::filled(ns, COST_NEUTRAL, false),
            pot: CellArray::filled(ns, POT_HIGH, false),
            grad: GradCache::new(nx, ny),
            blocked: CellArray::zeroed(ns, false),
            cur: PriorityBuf::new(),
            next: PriorityBuf::new(),
            over: PriorityBuf::new(),
            cur_t: CUR_T_INIT,
            start: Cell::new(0, 0),
            goal: Cell::new(0, 0),
            path: Vec::new(),
            path_len: 0,
            last_path_cost: POT_HIGH,
            pri_inc: PRI_INC,
            huge_pages: false,
        })
    }

    /// Put the potential, cost and blocked arrays of 2 MiB and more on transparent huge pages
    /// (Linux `madvise`; elsewhere, or where the kernel declines, ordinary pages). Fewer page
    /// walks when a large map is planned on again and again in one process; the first touch of
    /// each huge page costs kernel time, so a process that plans once gains nothing (the
    /// figures are in docs/navfn-core.md). Takes effect now: the arrays are allocated afresh
    /// (costs back to COST_NEUTRAL), as by a change of size.
    pub fn set_huge_pages(&mut self, on: bool) {
        if on != self.huge_pages {
            self.huge_pages = on;
            self.allocate();
        }
    }

    /// Whether large arrays are on huge pages.
    pub fn huge_pages(&self) -> bool {
        self.huge_pages
    }

    /// Make the arrays fit an `nx`×`ny` map; keeps the allocation when the size is unchanged.
    /// Every later `setup` re-initialises what a plan reads, so reuse cannot leak state
    /// between plans (the costs are the caller's to set).
    pub fn resize(&mut self, nx: usize, ny: usize) -> Result<(), CoreError> {
        if nx == self.nx && ny == self.ny {
            return Ok(());
        }
        let ns = checked_size(nx, ny)?;
        self.nx = nx;
        self.ny = ny;
        self.ns = ns;
        self.allocate();
        Ok(())
    }

    /// Fresh arrays for the current size. Fresh zeroed allocations rather than a fill: pages
    /// of the gradient array that a plan never touches then take no memory (most of them on
    /// large maps).
    fn allocate(&mut self) {
        let (ns, huge) = (self.ns, self.huge_pages);
        self.pot = CellArray::filled(ns, POT_HIGH, huge);
        self.grad = GradCache::new(self.nx, self.ny);
        self.cost = CellArray::filled(ns, COST_NEUTRAL, huge);
        self.blocked = CellArray::zeroed(ns, huge);
        self.cur.clear();
        self.next.clear();
        self.over.clear();
        self.path.clear();
        self.path_len = 0;
    }

    pub fn nx(&self) -> usize {
        self.nx
    }
    pub fn ny(&self) -> usize {
        self.ny
    }
    /// NavFn start: where path extraction begins (the robot *goal* when driven by the planner).
    pub fn start(&self) -> Cell {
        self.start
    }
    /// NavFn goal: where propagation begins (potential 0).
    pub fn goal(&self) -> Cell {
        self.goal
    }

    /// `setCostmap(cmap, isROS=false)` without the PGM frame: the bytes are NavFn costs,
    /// copied verbatim (the paper harness and the suite's `navfn` mode).
    pub fn set_costs_raw(&mut self, costs: &[u8]) -> Result<(), CoreError> {
        self.check_len(costs.len())?;
        self.cost.copy_from_slice(costs);
        Ok(())
    }

    /// `setCostmap(cmap, isROS=true, allow_unknown)`: ROS Costmap2D values → NavFn costs.
    pub fn set_costs_ros(&mut self, ros: &[u8], allow_unknown: bool) -> Result<(), CoreError> {
        self.check_len(ros.len())?;
        for (c, &v) in self.cost.iter_mut().zip(ros) {
            *c = ros_to_navfn_cost(v, allow_unknown);
        }
        Ok(())
    }

    /// Overwrites the NavFn cost of one cell (after the conversion of the whole map).
    pub fn set_cost(&mut self, c: Cell, cost: u8) -> Result<(), CoreError> {
        self.check_cell("cost", c)?;
        self.cost[c.y * self.nx + c.x] = cost;
        Ok(())
    }

    fn check_len(&self, got: usize) -> Result<(), CoreError> {
        if got != self.ns {
            return Err(CoreError::CostLength { got, want: self.ns, nx: self.nx, ny: self.ny });
        }
        Ok(())
    }

    fn check_cell(&self, what: &'static str, c: Cell) -> Result<(), CoreError> {
        if c.x >= self.nx || c.y >= self.ny {
            return Err(CoreError::CellOutside { what, x: c.x, y: c.y, nx: self.nx, ny: self.ny });
        }
        Ok(())
    }

    /// `setStart`: the cell path extraction descends from.
    pub fn set_start(&mut self, c: Cell) -> Result<(), CoreError> {
        self.check_cell("NavFn start", c)?;
        self.start = c;
        Ok(())
    }

    /// `setGoal`: the cell propagation starts from.
    pub fn set_goal(&mut self, c: Cell) -> Result<(), CoreError> {
        self.check_cell("NavFn goal", c)?;
        self.goal = c;
        Ok(())
    }

    /// NavFn cost array (after `setup` the border ring holds 254).
    pub fn costs(&self) -> &[u8] {
        &self.cost
    }
    /// Potential array, row-major; unreached cells hold [`POT_HIGH`].
    pub fn potential(&self) -> &[f32] {
        &self.pot
    }
    /// Mutable potential (for tests that corrupt it on purpose).
    pub fn potential_mut(&mut self) -> &mut [f32] {
        &mut self.pot
    }
    /// The path of the last `calc_path`: its first `len` points (empty on failure).
    pub fn path(&self) -> &[[f32; 2]] {
        &self.path[..self.path_len]
    }
    /// Every point the last `calc_path` recorded, including those of a failed descent.
    pub fn path_recorded(&self) -> &[[f32; 2]] {
        &self.path
    }
    /// `last_path_cost_` (written by A* only; [`POT_HIGH`] otherwise).
    pub fn last_path_cost(&self) -> f32 {
        self.last_path_cost
    }
    /// Set the threshold increment `priInc` (default [`PRI_INC`]; kept across `setup`). Only
    /// for perturbation experiments: any other value breaks bit-exactness on purpose.
    pub fn set_pri_inc(&mut self, v: f32) {
        self.pri_inc = v;
    }
    pub fn pri_inc(&self) -> f32 {
        self.pri_inc
    }
    /// Current threshold `curT`.
    pub fn threshold(&self) -> f32 {
        self.cur_t
    }

    #[inline(always)]
    pub(crate) fn start_index(&self) -> usize {
        self.start.y * self.nx + self.start.x
    }
    #[inline(always)]
    pub(crate) fn goal_index(&self) -> usize {
        self.goal.y * self.nx + self.goal.x
    }

    /// Cycle limit of `calcNavFn*`: `max(nx*ny/20, nx+ny)`.
    pub fn default_cycles(&self) -> usize {
        (self.ns / 20).max(self.nx + self.ny)
    }

    /// `calcNavFnDijkstra(atStart)`: set-up, then Dijkstra propagation with the default cycle limit.
    /// Returns NavFn's return value (true iff the loop ended before the cycle limit).
    pub fn calc_dijkstra<O: SearchObserver>(&mut self, at_start: bool, obs: &mut O) -> bool {
        self.setup();
        let cycles = self.default_cycles();
        self.propagate_dijkstra(cycles, at_start, obs)
    }

    /// `calcNavFnAstar`: set-up, then A* propagation with the default cycle limit.
    /// Returns true iff the start cell has a finite potential.
    pub fn calc_astar<O: SearchObserver>(&mut self, obs: &mut O) -> bool {
        self.setup();
        let cycles = self.default_cycles();
        self.propagate_astar(cycles, obs)
    }
}

fn checked_size(nx: usize, ny: usize) -> Result<usize, CoreError> {
    match nx.checked_mul(ny) {
        Some(ns) if nx >= 1 && ny >= 1 && ns < i32::MAX as usize => Ok(ns),
        _ => Err(CoreError::BadSize { nx, ny }),
    }
}

#[cfg(test)]
mod tests {
    use super::{Cell, NavFn, NoObserver};

    /// Huge pages change where the arrays live, never a result: the same plan on a map of
    /// several MiB per array with and without them, switched on before and after a plan.
    #[test]
    fn huge_pages_change_no_result() {
        let (nx, ny) = (1100, 600);
        let costs: Vec<u8> = (0..nx * ny).map(|i| 50 + (i * 31 % 150) as u8).collect();
        let plan = |nav: &mut NavFn| {
            nav.set_costs_raw(&costs).expect("size");
            nav.set_goal(Cell::new(5, 5)).expect("inside");
            nav.set_start(Cell::new(900, 400)).expect("inside");
            nav.calc_astar(&mut NoObserver);
            nav.calc_path(4 * nx, &mut NoObserver);
            (nav.potential().iter().map(|p| p.to_bits()).collect::<Vec<_>>(), nav.path().to_vec())
        };
        let mut plain = NavFn::new(nx, ny).expect("size");
        let expected = plan(&mut plain);
        assert!(!expected.1.is_empty(), "a path");
        let mut huge = NavFn::new(nx, ny).expect("size");
        huge.set_huge_pages(true);
        assert!(huge.huge_pages());
        assert_eq!(plan(&mut huge), expected);
        huge.set_huge_pages(false);
        assert_eq!(plan(&mut huge), expected);
    }
}
