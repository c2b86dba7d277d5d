//! What the planner accepts: a usable world frame and parameters (checked once, in
//! [`NavfnPlanner::new`]), and the stricter end-point checks of
//! [`NavfnPlanner::plan_checked`] (on the map, not in an obstacle).

use std::fmt;

use super::{NavfnPlanner, PlannerPlan};
use crate::core::{COST_OBS, Cell, CoreError};
use crate::maps::WorldParams;

/// Largest number of points the goal tolerance search may visit: `(2·tol/res + 1)²`. The search
/// visits every point of its grid, so a tolerance far above the map makes a plan never finish.
pub const MAX_TOLERANCE_POINTS: f64 = 1e8;

/// Which end of a plan an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum End {
    /// The robot start.
    Start,
    /// The robot goal.
    Goal,
}

impl fmt::Display for End {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            End::Start => "start",
            End::Goal => "goal",
        })
    }
}

/// A planner set-up or a plan request that is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error, miette::Diagnostic)]
pub enum PlanError {
    /// The map size or cost array does not fit NavFn.
    #[error(transparent)]
    #[diagnostic(transparent)]
    Core(#[from] CoreError),
    /// The world frame has a non-finite origin or a resolution that is not a positive number.
    #[error("world frame origin ({}, {}) resolution {resolution} is not usable: origin must be finite, resolution > 0", origin[0], origin[1])]
    #[diagnostic(code(navfn::E020))]
    BadWorld {
        /// Origin of cell (0, 0), metres.
        origin: [f64; 2],
        /// Cell size, metres.
        resolution: f64,
    },
    /// The tolerance is negative, not finite, or too large for the resolution.
    #[error(
        "tolerance {tolerance} is negative or too large for resolution {resolution} (the search would visit more than {MAX_TOLERANCE_POINTS:e} points)"
    )]
    #[diagnostic(code(navfn::E021))]
    BadTolerance {
        /// Goal tolerance, metres.
        tolerance: f64,
        /// Cell size, metres.
        resolution: f64,
    },
    /// The path iteration limit `max(nx, ny) · factor` overflows.
    #[error("max_cycles_factor {factor} is too large for a {nx}x{ny} map")]
    #[diagnostic(code(navfn::E022))]
    BadCyclesFactor {
        /// The factor.
        factor: usize,
        /// Columns.
        nx: usize,
        /// Rows.
        ny: usize,
    },
    /// An end given as a cell is not a cell of the map.
    #[error("{end} cell ({}, {}) is not a cell of the {width}x{height} map", cell[0], cell[1])]
    #[diagnostic(code(navfn::E023))]
    NotACell {
        /// Which end.
        end: End,
        /// Column and row as given.
        cell: [f64; 2],
        /// Columns.
        width: usize,
        /// Rows.
        height: usize,
    },
    /// An end lies outside the map.
    #[error("{end} ({}, {}) lies outside the map (x from {:.4} to {:.4}, y from {:.4} to {:.4})", point[0], point[1], bounds[0], bounds[1], bounds[2], bounds[3])]
    #[diagnostic(code(navfn::E024))]
    OutsideMap {
        /// Which end.
        end: End,
        /// The point, metres.
        point: [f64; 2],
        /// `[x_min, x_max, y_min, y_max]` of the map, metres.
        bounds: [f64; 4],
    },
    /// The planner ran and found no path.
    #[error("no plan: {}", status.name())]
    #[diagnostic(code(navfn::E026))]
    NoPlan {
        /// The planner's status.
        status: super::PlanStatus,
    },
    /// An end lies in a lethal cell.
    #[error("{end} ({}, {}) lies in an obstacle (cell {}, {})", point[0], point[1], cell.x, cell.y)]
    #[diagnostic(code(navfn::E025))]
    InObstacle {
        /// Which end.
        end: End,
        /// The point, metres.
        point: [f64; 2],
        /// Its cell.
        cell: Cell,
    },
}

/// The checks of [`NavfnPlanner::new`].
pub(super) fn check_setup(
    cost_len: usize,
    nx: usize,
    ny: usize,
    world: WorldParams,
    params: super::PlannerParams,
) -> Result<(), PlanError> {
    let want = nx.checked_mul(ny).ok_or(CoreError::BadSize { nx, ny })?;
    if cost_len != want {
        return Err(CoreError::CostLength { got: cost_len, want, nx, ny }.into());
    }
    let res = world.resolution;
    if !(world.origin.iter().all(|o| o.is_finite()) && res.is_finite() && res > 0.0) {
        return Err(PlanError::BadWorld { origin: world.origin, resolution: res });
    }
    let tol = params.tolerance;
    let side = 2.0 * tol / res + 1.0;
    if !(tol.is_finite() && tol >= 0.0 && side * side <= MAX_TOLERANCE_POINTS) {
        return Err(PlanError::BadTolerance { tolerance: tol, resolution: res });
    }
    if nx.max(ny).checked_mul(params.max_cycles_factor).is_none() {
        return Err(PlanError::BadCyclesFactor { factor: params.max_cycles_factor, nx, ny });
    }
    Ok(())
}

impl NavfnPlanner<'_> {
    /// The world point of a cell given as (column, row) numbers: it must be a whole cell of
    /// the map (row 0 = bottom). The point is the cell's corner, as nav2's `mapToWorld` of
    /// NavFn cells.
    pub fn cell_point(&self, end: End, cell: [f64; 2]) -> Result<[f64; 2], PlanError> {
        let ok = |v: f64, n: usize| v.fract() == 0.0 && v >= 0.0 && v < n as f64;
        if !ok(cell[0], self.nx) || !ok(cell[1], self.ny) {
            return Err(PlanError::NotACell { end, cell, width: self.nx, height: self.ny });
        }
        let w = self.world;
        Ok([w.origin[0] + cell[0] * w.resolution, w.origin[1] + cell[1] * w.resolution])
    }

    /// Checks that `point` lies on the map (Costmap2D's rule) and not in a lethal cell.
    pub fn check_end(&self, end: End, point: [f64; 2]) -> Result<Cell, PlanError> {
        let w = self.world;
        let Some(c) = w.costmap_world_to_map(point, self.nx, self.ny) else {
            let bounds = [
                w.origin[0],
                w.origin[0] + self.nx as f64 * w.resolution,
                w.origin[1],
                w.origin[1] + self.ny as f64 * w.resolution,
            ];
            return Err(PlanError::OutsideMap { end, point, bounds });
        };
        if self.costmap[c.y * self.nx + c.x] == COST_OBS {
            return Err(PlanError::InObstacle { end, point, cell: c });
        }
        Ok(c)
    }

    /// `createPlan` for a user request: both ends must lie on the map and outside obstacles
    /// (nav2 would clear an occupied robot cell, and plan next to an occupied goal with a
    /// tolerance; a user asking for such a plan has most likely given a wrong point).
    pub fn plan_checked(
        &mut self,
        start: [f64; 2],
        goal: [f64; 2],
    ) -> Result<PlannerPlan, PlanError> {
        self.check_end(End::Start, start)?;
        self.check_end(End::Goal, goal)?;
        Ok(self.create_plan(start, goal))
    }
}
