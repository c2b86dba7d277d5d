//! World ↔ map conversions of nav2 (SEMANTICS.md §8). Two different world→map rules exist:
//! Costmap2D's (truncation, used for validity) and the planner's own (rounding, used for the
//! NavFn cells). NavFn cells are corner-aligned: map→world adds no half cell.

use crate::core::Cell;

/// World frame of a costmap: origin of cell (0, 0) and cell size in metres.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct WorldParams {
    /// World position of cell (0, 0)'s corner, metres.
    pub origin: [f64; 2],
    /// Cell size, metres.
    pub resolution: f64,
}

impl Default for WorldParams {
    /// nav2_system_tests' planner tester: origin (0, 0), 1 m cells.
    fn default() -> Self {
        WorldParams { origin: [0.0, 0.0], resolution: 1.0 }
    }
}

impl WorldParams {
    /// `Costmap2D::worldToMap`: `unsigned((w − origin) / res)`, invalid below the origin or at
    /// or beyond the size.
    pub fn costmap_world_to_map(&self, p: [f64; 2], nx: usize, ny: usize) -> Option<Cell> {
        self.cell_of(p, nx, ny, f64::trunc)
    }

    /// `NavfnPlanner::worldToMap`: `int(round((w − origin) / res))` (half away from zero),
    /// invalid below the origin or when the rounded index reaches the size.
    pub fn planner_world_to_map(&self, p: [f64; 2], nx: usize, ny: usize) -> Option<Cell> {
        self.cell_of(p, nx, ny, f64::round)
    }

    /// The cell of `p` with `index` turning the scaled offset into an index.
    fn cell_of(&self, p: [f64; 2], nx: usize, ny: usize, index: fn(f64) -> f64) -> Option<Cell> {
        let axis = |w: f64, o: f64, n: usize| -> Option<usize> {
            if w < o || w.is_nan() {
                return None;
            }
            let m = index((w - o) / self.resolution);
            (m < n as f64).then_some(m as usize)
        };
        Some(Cell::new(axis(p[0], self.origin[0], nx)?, axis(p[1], self.origin[1], ny)?))
    }

    /// `NavfnPlanner::mapToWorld` of a NavFn path point: `origin + f64(p) * res`.
    pub fn navfn_to_world(&self, p: [f32; 2]) -> [f64; 2] {
        [
            self.origin[0] + p[0] as f64 * self.resolution,
            self.origin[1] + p[1] as f64 * self.resolution,
        ]
    }
}
