//! Violations found by the run-time checks.

use std::fmt;

use crate::core::Cell;

/// One violated property of one plan.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Violation {
    /// `ValidPath`: no open cell (cost < 254) within ±0.5 of the point.
    PoseInObstacle { index: usize, point: [f32; 2] },
    /// `FinitePotentialPath`: no cell with finite potential within ±0.5 of the point.
    PoseOnUnreachedCell { index: usize, point: [f32; 2] },
    /// `PositionSafe`: a non-goal cell with finite potential is an obstacle.
    PotentialOnObstacle { cell: Cell },
    /// `Progress`: a finite non-goal cell has no 4-neighbour with lower potential.
    NoProgress { cell: Cell },
    /// The path does not start at the NavFn start cell.
    WrongFirstPoint { point: [f32; 2], start: Cell },
    /// The path does not end at the NavFn goal cell.
    WrongLastPoint { point: [f32; 2], goal: Cell },
    /// The arrays do not match the map size.
    SizeMismatch { potential: usize, costs: usize, cells: usize },
}

impl fmt::Display for Violation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Violation::PoseInObstacle { index, point } => {
                write!(
                    f,
                    "path point {index} ({}, {}) lies in an obstacle (ValidPath)",
                    point[0], point[1]
                )
            }
            Violation::PoseOnUnreachedCell { index, point } => write!(
                f,
                "path point {index} ({}, {}) lies on a cell without finite potential (FinitePotentialPath)",
                point[0], point[1]
            ),
            Violation::PotentialOnObstacle { cell } => {
                write!(
                    f,
                    "obstacle cell ({}, {}) has a finite potential (PositionSafe)",
                    cell.x, cell.y
                )
            }
            Violation::NoProgress { cell } => write!(
                f,
                "cell ({}, {}) has a finite potential but no neighbour with a lower one (Progress)",
                cell.x, cell.y
            ),
            Violation::WrongFirstPoint { point, start } => write!(
                f,
                "path starts at ({}, {}), not at the start cell ({}, {})",
                point[0], point[1], start.x, start.y
            ),
            Violation::WrongLastPoint { point, goal } => write!(
                f,
                "path ends at ({}, {}), not at the goal cell ({}, {})",
                point[0], point[1], goal.x, goal.y
            ),
            Violation::SizeMismatch { potential, costs, cells } => write!(
                f,
                "array sizes do not match the map: potential {potential}, costs {costs}, cells {cells}"
            ),
        }
    }
}

/// Violations of one plan. At most [`CheckReport::LIMIT`] are kept; the rest are counted.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct CheckReport {
    pub violations: Vec<Violation>,
    /// Violations found beyond the limit (not stored).
    pub truncated: usize,
}

impl CheckReport {
    /// Keep the report small on a badly corrupted potential array.
    pub const LIMIT: usize = 100;

    pub fn is_ok(&self) -> bool {
        self.violations.is_empty()
    }

    /// Total number of violations found.
    pub fn count(&self) -> usize {
        self.violations.len() + self.truncated
    }

    pub(crate) fn push(&mut self, v: Violation) {
        if self.violations.len() < Self::LIMIT {
            self.violations.push(v);
        } else {
            self.truncated += 1;
        }
    }
}
