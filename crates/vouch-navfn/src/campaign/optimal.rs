//! Optimality analysis: a cost model shared by a grid optimum and NavFn's path.
//!
//! **Cost model** (documented in docs/navfn-campaign.md):
//! * The map is the NavFn cost array (50..=253 traversable, 254 obstacle; the border is 254).
//! * A *grid path* moves between 8-connected traversable cells. A move from cell `a` to cell `b`
//!   costs `len(a,b) · (cost[a] + cost[b]) / 2`, with `len` = 1 (orthogonal) or √2 (diagonal).
//!   Diagonal moves between two obstacle corners are allowed, because NavFn's grid-following
//!   fallback may take them too; the optimum is therefore a lower bound for such paths.
//! * The **optimum** is the least grid-path cost from start to goal (Dijkstra in f64).
//! * NavFn's path (a polyline of float points) is costed in the same model: the cells its
//!   points lie in (`(round(x), round(y))`, half away from zero), in order, form an 8-connected
//!   cell path from the start cell to the goal cell, costed move by move like the optimum's.
//!   The optimum is the least such cost, so `optimum ≤ NavFn` holds by construction whenever
//!   NavFn's cells are traversable: the bound is 1, derived, not quoted. (Sampling cell costs
//!   at the points only, with Euclidean segment lengths, mixed two models and could put an
//!   any-angle path 20 % *below* the optimum, which no metric bound explains.)

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::campaign::grid::OBSTACLE;

const SQRT2: f64 = std::f64::consts::SQRT_2;

/// Result of the grid optimum: cost and the cell sequence (start first), or `None` if the goal
/// is not 8-connected to the start.
#[derive(Clone, Debug)]
pub struct Optimum {
    pub cost: f64,
    pub cells: Vec<(u32, u32)>,
}

#[derive(PartialEq)]
struct Entry {
    cost: f64,
    cell: usize,
}
impl Eq for Entry {}
impl Ord for Entry {
    fn cmp(&self, o: &Self) -> Ordering {
        // Min-heap on cost; ties by cell index for determinism.
        o.cost.total_cmp(&self.cost).then_with(|| o.cell.cmp(&self.cell))
    }
}
impl PartialOrd for Entry {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// 8-connected Dijkstra from `source` under the campaign cost model. Stops early once `target`
/// is settled (if given). Returns the distance and predecessor arrays (`INFINITY`/`usize::MAX`
/// for cells not reached). Obstacle sources reach nothing.
pub fn dijkstra(
    costs: &[u8],
    w: usize,
    h: usize,
    source: usize,
    target: Option<usize>,
) -> (Vec<f64>, Vec<usize>) {
    let n = w * h;
    let mut dist = vec![f64::INFINITY; n];
    let mut prev = vec![usize::MAX; n];
    if source >= n || costs.len() != n || costs[source] >= OBSTACLE {
        return (dist, prev);
    }
    let mut heap = BinaryHeap::new();
    dist[source] = 0.0;
    heap.push(Entry { cost: 0.0, cell: source });
    while let Some(Entry { cost, cell }) = heap.pop() {
        if cost > dist[cell] {
            continue;
        }
        if Some(cell) == target {
            break;
        }
        let (x, y) = ((cell % w) as i64, (cell / w) as i64);
        for dy in -1i64..=1 {
            for dx in -1i64..=1 {
                if dx == 0 && dy == 0 {
                    continue;
                }
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let nb = ny as usize * w + nx as usize;
                if costs[nb] >= OBSTACLE {
                    continue;
                }
                let len = if dx != 0 && dy != 0 { SQRT2 } else { 1.0 };
                let c = cost + len * (f64::from(costs[cell]) + f64::from(costs[nb])) / 2.0;
                if c < dist[nb] {
                    dist[nb] = c;
                    prev[nb] = cell;
                    heap.push(Entry { cost: c, cell: nb });
                }
            }
        }
    }
    (dist, prev)
}

/// Least grid-path cost and cells from `start` to `goal` (start first), or `None` if the goal
/// is not 8-connected to the start or either end is an obstacle or outside the map.
/// `start == goal` gives cost 0 with a one-cell path.
pub fn grid_optimum(
    costs: &[u8],
    w: u32,
    h: u32,
    start: (u32, u32),
    goal: (u32, u32),
) -> Option<Optimum> {
    let (wu, hu) = (w as usize, h as usize);
    if start.0 >= w || start.1 >= h || goal.0 >= w || goal.1 >= h {
        return None;
    }
    let s = start.1 as usize * wu + start.0 as usize;
    let g = goal.1 as usize * wu + goal.0 as usize;
    let (dist, prev) = dijkstra(costs, wu, hu, s, Some(g));
    if costs.get(g).is_none_or(|&c| c >= OBSTACLE) || !dist[g].is_finite() {
        return None;
    }
    let mut cells = vec![(goal.0, goal.1)];
    let mut c = g;
    while c != s {
        c = prev[c];
        cells.push(((c % wu) as u32, (c / wu) as u32));
    }
    cells.reverse();
    Some(Optimum { cost: dist[g], cells })
}

/// The cell a float point lies in (nearest cell centre, half away from zero), clamped to the
/// map (a point outside it, which NavFn never records, counts as the nearest border cell).
fn point_cell(w: u32, h: u32, p: (f32, f32)) -> (i64, i64) {
    let x = (p.0.round() as i64).clamp(0, i64::from(w) - 1);
    let y = (p.1.round() as i64).clamp(0, i64::from(h) - 1);
    (x, y)
}

/// NavFn's path read as the 8-connected cell path it visits: the cells of its points in order,
/// repeats dropped; two consecutive cells that are not neighbours (NavFn's half-cell steps
/// never do this, the bridge is for completeness) are joined by diagonal then straight steps.
pub fn path_cells(w: u32, h: u32, path: &[(f32, f32)]) -> Vec<(i64, i64)> {
    let mut cells: Vec<(i64, i64)> = Vec::with_capacity(path.len());
    for &p in path {
        let c = point_cell(w, h, p);
        while let Some(&last) = cells.last() {
            if last == c {
                break;
            }
            let step = ((c.0 - last.0).signum(), (c.1 - last.1).signum());
            cells.push((last.0 + step.0, last.1 + step.1));
        }
        if cells.is_empty() {
            cells.push(c);
        }
    }
    cells
}

/// Cost of NavFn's path in the optimum's own model: its cell path ([`path_cells`]) costed move
/// by move as the grid optimum costs a move, `len · (cost[a] + cost[b]) / 2`, summed from the
/// start in f64. Both sides of the comparison are then costs of 8-connected cell paths between
/// the same two cells under one metric, and the optimum is the least of them: `optimum ≤ cost`
/// for every path whose cells are traversable (ValidPath), so a ratio above 1 is a real detour
/// and none can fall below 1 (`tests/campaign_suite.rs` checks it on the paper's suite).
pub fn path_cost(costs: &[u8], w: u32, h: u32, path: &[(f32, f32)]) -> f64 {
    let cells = path_cells(w, h, path);
    let cost_of = |c: (i64, i64)| f64::from(costs[c.1 as usize * w as usize + c.0 as usize]);
    let mut total = 0.0;
    for pair in cells.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let len = if a.0 != b.0 && a.1 != b.1 { SQRT2 } else { 1.0 };
        total += len * (cost_of(a) + cost_of(b)) / 2.0;
    }
    total
}

/// Shape statistics of one path.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Shape {
    /// Turns sharper than 90° (consecutive non-zero segments with negative dot product).
    pub obtuse_turns: u32,
    /// The sharpest turn, degrees (0 = straight on, 180 = reversal).
    pub max_turn_deg: f64,
    /// Points equal (exact float equality of both coordinates) to the point two before —
    /// NavFn's own oscillation criterion.
    pub oscillations: u32,
}

/// Turn and oscillation statistics of a path.
pub fn path_shape(path: &[(f32, f32)]) -> Shape {
    let mut s = Shape::default();
    for i in 2..path.len() {
        if path[i] == path[i - 2] {
            s.oscillations += 1;
        }
    }
    // Drop zero-length segments so that a repeated point does not hide a turn.
    let mut pts: Vec<(f64, f64)> = Vec::with_capacity(path.len());
    for p in path {
        let q = (f64::from(p.0), f64::from(p.1));
        if pts.last() != Some(&q) {
            pts.push(q);
        }
    }
    for w in pts.windows(3) {
        let u = (w[1].0 - w[0].0, w[1].1 - w[0].1);
        let v = (w[2].0 - w[1].0, w[2].1 - w[1].1);
        let dot = u.0 * v.0 + u.1 * v.1;
        let nu = (u.0 * u.0 + u.1 * u.1).sqrt();
        let nv = (v.0 * v.0 + v.1 * v.1).sqrt();
        let cos = (dot / (nu * nv)).clamp(-1.0, 1.0);
        let deg = cos.acos().to_degrees();
        if deg > s.max_turn_deg {
            s.max_turn_deg = deg;
        }
        if dot < 0.0 {
            s.obtuse_turns += 1;
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn optimum_on_free_3x3_interior_is_octile() {
        // 5x5 map, border 254, interior 50: corner to corner of the interior = 2 diagonals.
        let mut c = vec![50u8; 25];
        for i in 0..5 {
            c[i] = 254;
            c[20 + i] = 254;
            c[i * 5] = 254;
            c[i * 5 + 4] = 254;
        }
        let o = grid_optimum(&c, 5, 5, (1, 1), (3, 3)).expect("reachable");
        assert!((o.cost - 2.0 * SQRT2 * 50.0).abs() < 1e-9);
        assert_eq!(o.cells.len(), 3);
        assert!(grid_optimum(&c, 5, 5, (1, 1), (0, 0)).is_none());
        let same = grid_optimum(&c, 5, 5, (2, 2), (2, 2)).expect("trivial");
        assert_eq!(same.cost, 0.0);
    }

    #[test]
    fn any_angle_path_is_costed_as_its_cells() {
        // 3×2 map; the straight line (0,0)→(2,1) at half-cell steps: its points round (half away
        // from zero) to the cells (0,0) (1,0) (1,1) (2,1) (2,1) — three straight moves
        let c = vec![50u8, 60, 70, 80, 90, 100];
        let p = [(0.0f32, 0.0f32), (0.5, 0.25), (1.0, 0.5), (1.5, 0.75), (2.0, 1.0)];
        assert_eq!(path_cells(3, 2, &p), vec![(0, 0), (1, 0), (1, 1), (2, 1)]);
        // (50+60)/2 + (60+90)/2 + (90+100)/2 = 55 + 75 + 95
        assert!((path_cost(&c, 3, 2, &p) - 225.0).abs() < 1e-12);
        // never below the optimum: here the optimum is (0,0)→(1,0)→(2,1) = 55 + √2·80
        let opt = grid_optimum(&c, 3, 2, (0, 0), (2, 1)).expect("reachable").cost;
        assert!(opt <= path_cost(&c, 3, 2, &p));
        // a jump of two cells is bridged diagonally then straight
        assert_eq!(path_cells(3, 2, &[(0.0, 0.0), (2.0, 1.0)]), vec![(0, 0), (1, 1), (2, 1)]);
    }

    #[test]
    fn path_cost_of_grid_path_equals_grid_cost() {
        let c = vec![50u8, 100, 150, 200];
        let p = [(0.0f32, 0.0f32), (1.0, 0.0), (1.0, 1.0)];
        // (50+100)/2 + (100+200)/2 = 75 + 150
        assert!((path_cost(&c, 2, 2, &p) - 225.0).abs() < 1e-12);
    }

    #[test]
    fn shape_counts_reversal_and_oscillation() {
        let p = [(0.0f32, 0.0f32), (1.0, 0.0), (0.0, 0.0), (0.0, 1.0)];
        let s = path_shape(&p);
        assert_eq!(s.oscillations, 1);
        assert_eq!(s.obtuse_turns, 1);
        assert!((s.max_turn_deg - 180.0).abs() < 1e-9);
        let straight = path_shape(&[(0.0, 0.0), (0.5, 0.0), (1.0, 0.0)]);
        assert_eq!(straight, Shape::default());
    }
}
