//! Run-time checks of every plan: the properties the JLAMP paper states in Dafny
//! (`ValidPath`, `PositionSafe`, `Progress`, `FinitePotentialPath`) plus the end points,
//! evaluated on the actual arrays of one plan. Cost: one pass over the potential array
//! (O(nx·ny), comparable to the set-up NavFn does anyway) and O(1) per path point.
//!
//! Deviation from the paper, on purpose: its `Progress` exempts every cell in the goal's row
//! *and* column (`i ≠ goal.row ∧ j ≠ goal.col`), which reads as a slip for "cell ≠ goal";
//! we check the stronger property (only the goal cell is exempt).

mod report;

pub use report::{CheckReport, Violation};

use crate::core::{COST_OBS, Cell, NavFn, POT_HIGH};

/// A cell NavFn reached has a potential below `POT_HIGH`; a NaN counts as not reached.
pub(crate) fn reached(potential: f32) -> bool {
    potential < POT_HIGH
}

/// Everything a plan check looks at.
#[derive(Clone, Copy, Debug)]
pub struct PlanView<'a> {
    pub nx: usize,
    pub ny: usize,
    /// NavFn costs as NavFn used them (after set-up: border ring = 254).
    pub costs: &'a [u8],
    pub potential: &'a [f32],
    /// The path, NavFn start to NavFn goal.
    pub path: &'a [[f32; 2]],
    /// NavFn start (first point of the path).
    pub start: Cell,
    /// NavFn goal (last point; potential 0, exempt from the potential properties).
    pub goal: Cell,
}

impl<'a> PlanView<'a> {
    /// View of the last plan of `nav` (its returned path, possibly empty).
    pub fn of(nav: &'a NavFn) -> Self {
        PlanView {
            nx: nav.nx(),
            ny: nav.ny(),
            costs: nav.costs(),
            potential: nav.potential(),
            path: nav.path(),
            start: nav.start(),
            goal: nav.goal(),
        }
    }
}

/// All checks: potential properties, then the path properties.
pub fn check_plan(v: &PlanView) -> CheckReport {
    let mut r = check_potential(v);
    check_path_into(v, &mut r);
    r
}

/// `PositionSafe` (finite potential ⇒ open cell) and `Progress` (every finite non-goal cell
/// has a 4-neighbour with strictly lower potential).
pub fn check_potential(v: &PlanView) -> CheckReport {
    let mut r = CheckReport::default();
    let (nx, ny) = (v.nx, v.ny);
    if v.potential.len() != nx * ny || v.costs.len() != nx * ny {
        r.push(Violation::SizeMismatch {
            potential: v.potential.len(),
            costs: v.costs.len(),
            cells: nx * ny,
        });
        return r;
    }
    let goal = v.goal.y * nx + v.goal.x;
    for (i, &p) in v.potential.iter().enumerate() {
        if !reached(p) || i == goal {
            continue;
        }
        let (x, y) = (i % nx, i / nx);
        if v.costs[i] >= COST_OBS {
            r.push(Violation::PotentialOnObstacle { cell: Cell::new(x, y) });
        }
        let lower = |j: usize| v.potential[j] < p;
        let progress = (x > 0 && lower(i - 1))
            || (x + 1 < nx && lower(i + 1))
            || (y > 0 && lower(i - nx))
            || (y + 1 < ny && lower(i + nx));
        if !progress {
            r.push(Violation::NoProgress { cell: Cell::new(x, y) });
        }
    }
    r
}

/// Path checks only (`ValidPath`, `FinitePotentialPath`, first/last point).
pub fn check_path(v: &PlanView) -> CheckReport {
    let mut r = CheckReport::default();
    check_path_into(v, &mut r);
    r
}

fn check_path_into(v: &PlanView, r: &mut CheckReport) {
    let Some(first) = v.path.first() else { return };
    let last = v.path[v.path.len() - 1];
    if *first != [v.start.x as f32, v.start.y as f32] {
        r.push(Violation::WrongFirstPoint { point: *first, start: v.start });
    }
    if last != [v.goal.x as f32, v.goal.y as f32] {
        r.push(Violation::WrongLastPoint { point: last, goal: v.goal });
    }
    for (index, &point) in v.path.iter().enumerate() {
        let mut open = false;
        let mut finite = false;
        for (cx, cy) in belonging_cells(point, v.nx, v.ny) {
            let i = cy * v.nx + cx;
            open |= v.costs.get(i).is_some_and(|&c| c < COST_OBS);
            finite |= v.potential.get(i).is_some_and(|&p| p < POT_HIGH);
        }
        if !open {
            r.push(Violation::PoseInObstacle { index, point });
        }
        if !finite {
            r.push(Violation::PoseOnUnreachedCell { index, point });
        }
    }
}

/// The cells a point belongs to in the paper's sense (`BelongsToCell`: |p − cell| ≤ 0.5 on
/// both axes): one cell, or two/four when a coordinate sits exactly on a half.
fn belonging_cells(p: [f32; 2], nx: usize, ny: usize) -> impl Iterator<Item = (usize, usize)> {
    let axis = |c: f32, n: usize| -> [Option<usize>; 2] {
        let c = c as f64;
        let lo = (c - 0.5).ceil();
        let hi = (c + 0.5).floor();
        let ok = |v: f64| if v >= 0.0 && v < n as f64 { Some(v as usize) } else { None };
        [ok(lo), if hi != lo { ok(hi) } else { None }]
    };
    let xs = axis(p[0], nx);
    let ys = axis(p[1], ny);
    xs.into_iter().flatten().flat_map(move |x| ys.into_iter().flatten().map(move |y| (x, y)))
}
