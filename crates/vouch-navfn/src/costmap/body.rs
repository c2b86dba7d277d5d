//! The robot's body along a plan against the static map's lethal cells.
//!
//! A plan is a sequence of poses `(x, y, yaw)`. Between two poses the robot translates with the
//! first pose's heading (nav2 orients each pose toward the next one), and at each pose it turns
//! in place from its heading to the next one. The body is the disc of `robot_radius`, or the
//! `footprint` polygon (as given, without nav2's padding, which is a margin, not the robot).
//! A lethal cell is the closed square of a static-layer cell of value 254.
//!
//! What is exact and what is sampled: translations are exact — the swept region of a disc is a
//! capsule, that of a polygon the union of the polygon at both ends and of the parallelogram
//! each edge sweeps, and its distance to every cell square is computed in closed form (segment
//! to segment distances, intersection and containment tests, in `f64`). Turns in place are
//! exact for the disc (a turn sweeps nothing new) and sampled for a polygon: the polygon is
//! checked at headings at most [`TURN_STEP`] apart along the shorter turn. Cells farther than
//! the body's circumscribed radius plus `window` from the path are not examined, so a minimum
//! clearance at or above `window` is reported as "at least `window`".

use serde::Serialize;

use crate::maps::WorldParams;

/// Largest heading step when a polygon's turn in place is sampled (radians, 1°).
pub const TURN_STEP: f64 = std::f64::consts::PI / 180.0;

/// The shape checked.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Body {
    /// A disc of this radius (metres).
    Disc(f64),
    /// A polygon in the robot frame (metres), at least three vertices.
    Polygon(Vec<[f64; 2]>),
}

impl Body {
    /// Largest distance from the robot origin to the body.
    pub fn circumscribed(&self) -> f64 {
        match self {
            Body::Disc(r) => *r,
            Body::Polygon(p) => p.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max),
        }
    }
}

/// Where the body comes closest to a lethal cell.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Clearance {
    /// Distance from the body to the nearest lethal cell (metres; 0 when they touch or
    /// overlap).
    pub clearance: f64,
    /// Index of the pose the motion starts from (the segment to the next pose, or the turn at
    /// the last pose when it is the last index).
    pub pose: usize,
    /// The lethal cell (column, row; row 0 = bottom).
    pub cell: [usize; 2],
    /// The cell's centre in metres.
    pub cell_xy: [f64; 2],
}

/// The body check of one plan.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct BodyReport {
    /// Motions (segments and turns) checked.
    pub motions: usize,
    /// The smallest clearance found, if a lethal cell lies within the window.
    pub min: Option<Clearance>,
    /// The window beyond the circumscribed radius that was searched (metres).
    pub window: f64,
    /// Segments whose swept body touches a lethal cell: the first contact of each.
    pub violations: Vec<Clearance>,
}

impl BodyReport {
    /// No contact.
    pub fn is_ok(&self) -> bool {
        self.violations.is_empty()
    }
}

/// The static map the body is checked against.
pub struct BodyCheck<'m> {
    /// Static layer values, row-major, row 0 = bottom.
    pub costs: &'m [u8],
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// World frame of the map.
    pub world: WorldParams,
    /// The body.
    pub body: Body,
    /// How far beyond the body cells are examined (metres).
    pub window: f64,
}

impl BodyCheck<'_> {
    /// Check the plan `poses` (x, y, yaw).
    pub fn check(&self, poses: &[[f64; 3]]) -> BodyReport {
        let mut report = BodyReport { window: self.window, ..BodyReport::default() };
        for (i, p) in poses.iter().enumerate() {
            let next = poses.get(i + 1).copied().unwrap_or(*p);
            let shapes = self.motion_shapes(*p, next);
            report.motions += 1;
            let reach = self.body.circumscribed() + self.window;
            let lo = [p[0].min(next[0]) - reach, p[1].min(next[1]) - reach];
            let hi = [p[0].max(next[0]) + reach, p[1].max(next[1]) + reach];
            let Some(best) = self.nearest(&shapes, lo, hi, i) else { continue };
            if best.clearance <= 0.0 {
                report.violations.push(best);
            }
            if report.min.is_none_or(|m| best.clearance < m.clearance) {
                report.min = Some(best);
            }
        }
        report
    }

    /// The primitives swept from pose `a` to pose `b`: capsules (a segment and a radius) or
    /// polygons (radius 0).
    fn motion_shapes(&self, a: [f64; 3], b: [f64; 3]) -> Vec<Shape> {
        match &self.body {
            Body::Disc(r) => vec![Shape::Capsule([a[0], a[1]], [b[0], b[1]], *r)],
            Body::Polygon(pts) => {
                let at = |x: f64, y: f64, yaw: f64| -> Vec<[f64; 2]> {
                    let (s, c) = yaw.sin_cos();
                    pts.iter().map(|p| [x + p[0] * c - p[1] * s, y + p[0] * s + p[1] * c]).collect()
                };
                let start = at(a[0], a[1], a[2]);
                let end = at(b[0], b[1], a[2]);
                let mut shapes = vec![Shape::Polygon(start.clone()), Shape::Polygon(end.clone())];
                for k in 0..start.len() {
                    let k1 = (k + 1) % start.len();
                    shapes.push(Shape::Polygon(vec![start[k], start[k1], end[k1], end[k]]));
                }
                // the turn at `b` from a's heading to b's, sampled
                let turn = wrap(b[2] - a[2]);
                let steps = (turn.abs() / TURN_STEP).ceil() as usize;
                for s in 1..=steps {
                    let yaw = a[2] + turn * s as f64 / steps as f64;
                    shapes.push(Shape::Polygon(at(b[0], b[1], yaw)));
                }
                shapes
            }
        }
    }

    fn nearest(
        &self,
        shapes: &[Shape],
        lo: [f64; 2],
        hi: [f64; 2],
        pose: usize,
    ) -> Option<Clearance> {
        let w = &self.world;
        let res = w.resolution;
        let to_cell =
            |v: f64, o: f64, n: usize| ((v - o) / res).floor().clamp(0.0, n as f64 - 1.0) as usize;
        let (c0, c1) =
            (to_cell(lo[0], w.origin[0], self.width), to_cell(hi[0], w.origin[0], self.width));
        let (r0, r1) =
            (to_cell(lo[1], w.origin[1], self.height), to_cell(hi[1], w.origin[1], self.height));
        let mut best: Option<Clearance> = None;
        for row in r0..=r1 {
            for col in c0..=c1 {
                if self.costs.get(row * self.width + col) != Some(&254) {
                    continue;
                }
                let x0 = w.origin[0] + col as f64 * res;
                let y0 = w.origin[1] + row as f64 * res;
                let square = [[x0, y0], [x0 + res, y0], [x0 + res, y0 + res], [x0, y0 + res]];
                let d = shapes.iter().map(|s| s.distance_to(&square)).fold(f64::INFINITY, f64::min);
                if d > self.window {
                    continue;
                }
                if best.is_none_or(|b| d < b.clearance) {
                    best = Some(Clearance {
                        clearance: d,
                        pose,
                        cell: [col, row],
                        cell_xy: [x0 + res / 2.0, y0 + res / 2.0],
                    });
                }
            }
        }
        best
    }
}

/// An angle in (−π, π].
fn wrap(a: f64) -> f64 {
    let t = a.rem_euclid(std::f64::consts::TAU);
    if t > std::f64::consts::PI { t - std::f64::consts::TAU } else { t }
}

enum Shape {
    Capsule([f64; 2], [f64; 2], f64),
    Polygon(Vec<[f64; 2]>),
}

impl Shape {
    /// Distance to a (convex, counter-clockwise) cell square; 0 when they meet.
    fn distance_to(&self, square: &[[f64; 2]; 4]) -> f64 {
        match self {
            Shape::Capsule(a, b, r) => (segment_polygon_distance(*a, *b, square) - r).max(0.0),
            Shape::Polygon(p) => polygon_distance(p, square),
        }
    }
}

fn edges(p: &[[f64; 2]]) -> impl Iterator<Item = ([f64; 2], [f64; 2])> + '_ {
    (0..p.len()).map(move |i| (p[i], p[(i + 1) % p.len()]))
}

/// Distance from segment `a`–`b` to a convex polygon (0 if it meets or enters it).
fn segment_polygon_distance(a: [f64; 2], b: [f64; 2], poly: &[[f64; 2]]) -> f64 {
    if contains(poly, a) {
        return 0.0;
    }
    edges(poly).map(|(p, q)| segment_distance(a, b, p, q)).fold(f64::INFINITY, f64::min)
}

/// Distance between two simple polygons: 0 if an edge of one crosses an edge of the other or
/// one holds a vertex of the other, else the smallest edge-to-edge distance.
fn polygon_distance(p: &[[f64; 2]], q: &[[f64; 2]]) -> f64 {
    if contains(p, q[0]) || contains(q, p[0]) {
        return 0.0;
    }
    let mut d = f64::INFINITY;
    for (a, b) in edges(p) {
        for (c, e) in edges(q) {
            d = d.min(segment_distance(a, b, c, e));
        }
    }
    d
}

/// Distance between segments `a`–`b` and `c`–`d` (0 when they cross).
fn segment_distance(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> f64 {
    if segments_cross(a, b, c, d) {
        return 0.0;
    }
    distance_to_segment(a, c, d)
        .min(distance_to_segment(b, c, d))
        .min(distance_to_segment(c, a, b))
        .min(distance_to_segment(d, a, b))
}

/// Distance from `p` to the segment `a`–`b`; a point when `a = b` (a robot standing still, a
/// repeated footprint vertex).
fn distance_to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (cx, cy) = (b[0] - a[0], b[1] - a[1]);
    let len_sq = cx * cx + cy * cy;
    let t = if len_sq > 0.0 {
        (((p[0] - a[0]) * cx + (p[1] - a[1]) * cy) / len_sq).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a[0] + t * cx - p[0]).hypot(a[1] + t * cy - p[1])
}

fn cross(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
}

fn segments_cross(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (d1, d2) = (cross(c, d, a), cross(c, d, b));
    let (d3, d4) = (cross(a, b, c), cross(a, b, d));
    (d1 > 0.0) != (d2 > 0.0) && (d3 > 0.0) != (d4 > 0.0) && d1 != 0.0 && d3 != 0.0
}

/// Point in polygon (even-odd; points on the boundary count through the distance, which is 0).
fn contains(poly: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut inside = false;
    for (a, b) in edges(poly) {
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map_with(cells: &[(usize, usize)]) -> Vec<u8> {
        let mut m = vec![0u8; 20 * 20];
        for &(c, r) in cells {
            m[r * 20 + c] = 254;
        }
        m
    }

    fn check(body: Body, costs: &[u8], poses: &[[f64; 3]]) -> BodyReport {
        let world = WorldParams { origin: [0.0, 0.0], resolution: 1.0 };
        BodyCheck { costs, width: 20, height: 20, world, body, window: 5.0 }.check(poses)
    }

    #[test]
    fn disc_clearance_to_a_wall_cell() {
        // path along y = 5.5 from x = 1.5 to 8.5; lethal cell [5,7]×[7,8]: distance 1.5 to the
        // path, clearance 1.5 − 0.4 = 1.1
        let costs = map_with(&[(5, 7)]);
        let r = check(Body::Disc(0.4), &costs, &[[1.5, 5.5, 0.0], [8.5, 5.5, 0.0]]);
        assert!(r.is_ok());
        let m = r.min.unwrap();
        assert!((m.clearance - 1.1).abs() < 1e-12, "{m:?}");
        assert_eq!(m.cell, [5, 7]);
        let r = check(Body::Disc(1.6), &costs, &[[1.5, 5.5, 0.0], [8.5, 5.5, 0.0]]);
        assert_eq!(r.violations.len(), 1);
    }

    #[test]
    fn polygon_sweeps_between_poses_and_turns() {
        // a 2 m × 0.4 m bar along x; moving along x at y = 5.5 it clears the cell at row 7 by
        // 1.3 m; turned 90° at the end (x = 8.5) it reaches y ∈ [4.5, 6.5]: cell (8, 6)'s
        // square [8, 9]×[6, 7] is then touched
        let bar = Body::Polygon(vec![[1.0, 0.2], [-1.0, 0.2], [-1.0, -0.2], [1.0, -0.2]]);
        let costs = map_with(&[(5, 7), (8, 7)]);
        let straight = [[1.5, 5.5, 0.0], [8.5, 5.5, 0.0]];
        let r = check(bar.clone(), &costs, &straight);
        assert!(r.is_ok(), "{r:?}");
        assert!((r.min.unwrap().clearance - 1.3).abs() < 1e-12);
        let turning = [[1.5, 5.5, 0.0], [8.5, 5.5, std::f64::consts::FRAC_PI_2]];
        let r = check(bar, &map_with(&[(8, 6)]), &turning);
        assert!(!r.is_ok());
    }

    #[test]
    fn degenerate_shapes_and_standing_still_give_numbers() {
        let costs = map_with(&[(5, 7)]);
        let still = [[5.5, 5.5, 0.0], [5.5, 5.5, 0.0]];
        let r = check(Body::Disc(0.2), &costs, &still);
        // from (5.5, 5.5) to the square [5, 6]×[7, 8]: 1.5, less the radius
        assert!((r.min.unwrap().clearance - 1.3).abs() < 1e-12);
        let dot = Body::Polygon(vec![[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]);
        let r = check(dot, &costs, &still);
        assert!((r.min.unwrap().clearance - 1.5).abs() < 1e-12);
    }
}
