//! One builder per category of the paper's suite (§4 of the paper, SEMANTICS.md §9).
//! Each builder gets its own random stream and a size, and returns a bordered map.

use crate::campaign::grid::{FREE, MAX_TRAVERSABLE, OBSTACLE, SuiteMap};
use crate::campaign::rng::SplitMix64;

/// The nine generated categories, in the paper's order (ROS maps are imported, not generated).
pub const CATEGORIES: [&str; 9] =
    ["circus", "columns", "free", "obstacle", "radial", "random", "spiral", "split", "walls"];

fn random_cost(rng: &mut SplitMix64) -> u8 {
    rng.range(u32::from(FREE), u32::from(MAX_TRAVERSABLE)) as u8
}

/// Half of the maps of a uniform-cost category get random costs (name suffix `_random`).
fn maybe_randomise_costs(mut m: SuiteMap, rng: &mut SplitMix64) -> (SuiteMap, &'static str) {
    if rng.chance(1, 2) {
        randomise_costs(&mut m, rng);
        (m, "_random")
    } else {
        (m, "")
    }
}

/// Interior cells get a random traversable cost (obstacles are kept).
fn randomise_costs(m: &mut SuiteMap, rng: &mut SplitMix64) {
    for y in 1..m.height - 1 {
        for x in 1..m.width - 1 {
            if m.is_free(x, y) {
                let c = random_cost(rng);
                m.set(x, y, c);
            }
        }
    }
}

/// Build one map of `category`. `w`, `h` include the border and are ≥ 5 (circus forces w = 5).
/// Returns the map and a short suffix describing its variant (for the folder name).
pub fn build(
    category: &str,
    rng: &mut SplitMix64,
    w: u32,
    h: u32,
) -> Option<(SuiteMap, &'static str)> {
    let m = match category {
        "circus" => circus(rng, h),
        "columns" => columns(rng, w, h),
        "free" => (SuiteMap::filled("free", "", w, h, FREE), ""),
        "obstacle" => obstacle(rng, w, h),
        "radial" => radial(rng, w, h),
        "random" => {
            let mut m = SuiteMap::filled("random", "", w, h, FREE);
            randomise_costs(&mut m, rng);
            (m, "")
        }
        "spiral" => spiral(rng, w, h),
        "split" => split(rng, w, h),
        "walls" => walls(rng, w, h),
        _ => return None,
    };
    Some(m)
}

/// Roman-circus track, 5 cells wide: a cheap top row, two long lanes separated by a central
/// wall, a cheap cell at the bottom middle. One lane is cheap-ish, the other costs 253; the
/// first lane cell under the top row costs 253 on both sides (a "gate"), as in the paper's
/// hand-made maps. This is the shape on which NavFn picks the expensive lane.
fn circus(rng: &mut SplitMix64, h: u32) -> (SuiteMap, &'static str) {
    let h = h.max(7);
    let mut m = SuiteMap::filled("circus", "", 5, h, OBSTACLE);
    for x in 1..4 {
        m.set(x, 1, FREE);
    }
    let cheap = rng.range(100, 180) as u8;
    let cheap_left = rng.chance(1, 2);
    let (cx, ex) = if cheap_left { (1, 3) } else { (3, 1) };
    for y in 2..h - 1 {
        let gate = y == 2;
        m.set(cx, y, if gate { MAX_TRAVERSABLE } else { cheap });
        m.set(ex, y, MAX_TRAVERSABLE);
    }
    m.set(2, h - 2, FREE);
    (m, if cheap_left { "L" } else { "R" })
}

/// Square columns of side `s` on a regular grid with gap `g`; half of the maps random costs.
fn columns(rng: &mut SplitMix64, w: u32, h: u32) -> (SuiteMap, &'static str) {
    let mut m = SuiteMap::filled("columns", "", w, h, FREE);
    let s = rng.range(1, 2);
    let g = rng.range(1, 3);
    let (ox, oy) = (1 + rng.range(0, g), 1 + rng.range(0, g));
    let mut y = oy;
    while y + s < h {
        let mut x = ox;
        while x + s < w {
            for dy in 0..s {
                for dx in 0..s {
                    m.set(x + dx, y + dy, OBSTACLE);
                }
            }
            x += s + g;
        }
        y += s + g;
    }
    maybe_randomise_costs(m, rng)
}

/// A ratio (10–40 %) of obstacle cells, the rest uniform random 50..253.
fn obstacle(rng: &mut SplitMix64, w: u32, h: u32) -> (SuiteMap, &'static str) {
    let mut m = SuiteMap::filled("obstacle", "", w, h, FREE);
    let pct = rng.range(10, 40);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let c = if rng.chance(pct, 100) { OBSTACLE } else { random_cost(rng) };
            m.set(x, y, c);
        }
    }
    (m, "")
}

/// Cost growing linearly with the Euclidean distance from a random centre, 254 beyond a radius.
fn radial(rng: &mut SplitMix64, w: u32, h: u32) -> (SuiteMap, &'static str) {
    let mut m = SuiteMap::filled("radial", "", w, h, FREE);
    let cx = rng.range(1, w - 2) as f64;
    let cy = rng.range(1, h - 2) as f64;
    let diag = f64::from(w * w + h * h).sqrt();
    // Radius between a third of the diagonal and the whole diagonal (then no 254 ring).
    let r = diag * f64::from(rng.range(33, 100)) / 100.0;
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let d = ((x as f64 - cx).powi(2) + (y as f64 - cy).powi(2)).sqrt();
            let c = if d > r {
                OBSTACLE
            } else {
                (f64::from(FREE) + f64::from(MAX_TRAVERSABLE - FREE) * d / r).round() as u8
            };
            m.set(x, y, c);
        }
    }
    (m, "")
}

/// A clockwise spiral corridor of width 1 carved into a solid interior by a turtle that goes
/// straight while the cell two ahead is still solid, and turns right otherwise.
fn spiral(rng: &mut SplitMix64, w: u32, h: u32) -> (SuiteMap, &'static str) {
    let mut m = SuiteMap::filled("spiral", "", w, h, OBSTACLE);
    let dirs: [(i64, i64); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)]; // E, S, W, N = clockwise
    let (mut x, mut y, mut d) = (1i64, 1i64, 0usize);
    let inside = |x: i64, y: i64| x >= 1 && y >= 1 && x <= w as i64 - 2 && y <= h as i64 - 2;
    m.set(1, 1, FREE);
    let mut turns_without_move = 0;
    while turns_without_move < 2 {
        let (dx, dy) = dirs[d];
        let (nx, ny) = (x + dx, y + dy);
        let (fx, fy) = (x + 2 * dx, y + 2 * dy);
        let next_ok = inside(nx, ny) && !m.is_free(nx as u32, ny as u32);
        let far_solid = !inside(fx, fy) || !m.is_free(fx as u32, fy as u32);
        // Also refuse to touch a carved cell sideways (keeps the walls one cell thick).
        let (sx, sy) = (nx - dy, ny + dx);
        let (tx, ty) = (nx + dy, ny - dx);
        let side_ok =
            |a: i64, b: i64| !inside(a, b) || !m.is_free(a as u32, b as u32) || (a == x && b == y);
        if next_ok && far_solid && side_ok(sx, sy) && side_ok(tx, ty) {
            x = nx;
            y = ny;
            m.set(x as u32, y as u32, FREE);
            turns_without_move = 0;
        } else {
            d = (d + 1) % 4;
            turns_without_move += 1;
        }
    }
    maybe_randomise_costs(m, rng)
}

/// Full-length vertical and/or horizontal walls splitting the map into regions, random costs.
fn split(rng: &mut SplitMix64, w: u32, h: u32) -> (SuiteMap, &'static str) {
    let mut m = SuiteMap::filled("split", "", w, h, FREE);
    randomise_costs(&mut m, rng);
    let vertical = rng.range(0, 2);
    let horizontal = if vertical == 0 { rng.range(1, 2) } else { rng.range(0, 2) };
    for _ in 0..vertical {
        let x = rng.range(2, w.saturating_sub(3).max(2));
        for y in 1..h - 1 {
            m.set(x, y, OBSTACLE);
        }
    }
    for _ in 0..horizontal {
        let y = rng.range(2, h.saturating_sub(3).max(2));
        for x in 1..w - 1 {
            m.set(x, y, OBSTACLE);
        }
    }
    (m, "")
}

/// Random straight walls of width 1, not necessarily border to border; half with random costs.
fn walls(rng: &mut SplitMix64, w: u32, h: u32) -> (SuiteMap, &'static str) {
    let mut m = SuiteMap::filled("walls", "", w, h, FREE);
    let random = rng.chance(1, 2);
    if random {
        randomise_costs(&mut m, rng);
    }
    let count = rng.range(1, 1 + (w + h) / 6);
    for _ in 0..count {
        if rng.chance(1, 2) {
            let y = rng.range(1, h - 2);
            let a = rng.range(1, w - 2);
            let b = rng.range(1, w - 2);
            for x in a.min(b)..=a.max(b) {
                m.set(x, y, OBSTACLE);
            }
        } else {
            let x = rng.range(1, w - 2);
            let a = rng.range(1, h - 2);
            let b = rng.range(1, h - 2);
            for y in a.min(b)..=a.max(b) {
                m.set(x, y, OBSTACLE);
            }
        }
    }
    (m, if random { "_random" } else { "" })
}
