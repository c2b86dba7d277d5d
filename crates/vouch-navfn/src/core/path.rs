//! Path extraction (`calcPath`, `gradCell`), SEMANTICS.md §5–6.
//!
//! The descent works on local slices (no per-read dispatch through the struct), reads the
//! 3×3 block around the current cell once for both the "any neighbour unreached" test and
//! grid following, and takes the recorded point's column and row by a multiplication
//! ([`WidthDiv`]) instead of two divisions.

use super::numeric::{WidthDiv, c_float_to_int, hypotf, round_half_away};
use super::observer::{PathStartView, SearchObserver};
use super::{COST_NEUTRAL, COST_OBS, NavFn, POT_HIGH};

/// Potential of cell `i`, unreached outside the array (the C++ reads past the border ring
/// there, undefined behaviour; only start cells on the border get there). A negative index
/// converts to one past any array, so one comparison covers both ends.
#[inline(always)]
fn pot_at(pot: &[f32], i: i64) -> f32 {
    pot.get(i as usize).copied().unwrap_or(POT_HIGH)
}

/// `gradCell(n)`: normalised gradient of the potential at `n`, cached in `grad` at `slot`.
#[inline(always)]
fn grad_cell(
    pot: &[f32],
    grad: &mut [[f32; 2]],
    touched: &mut Vec<u32>,
    nx: i64,
    n: i64,
    slot: usize,
) {
    let ns = pot.len() as i64;
    let Some(&[gx_cached, gy_cached]) = grad.get(slot) else { return };
    if gx_cached + gy_cached > 0.0 {
        return; // cached
    }
    if n < nx || n > ns - nx {
        return;
    }
    let c = pot[n as usize];
    let (pl, pr, pu, pd) =
        (pot_at(pot, n - 1), pot_at(pot, n + 1), pot_at(pot, n - nx), pot_at(pot, n + nx));
    let mut gxv = 0.0f32;
    let mut gyv = 0.0f32;
    let obs = COST_OBS as f32;
    if c >= POT_HIGH {
        if pl < POT_HIGH {
            gxv = -obs;
        } else if pr < POT_HIGH {
            gxv = obs;
        }
        if pu < POT_HIGH {
            gyv = -obs;
        } else if pd < POT_HIGH {
            gyv = obs;
        }
    } else {
        if pl < POT_HIGH {
            gxv = gxv + (pl - c);
        }
        if pr < POT_HIGH {
            gxv = gxv + (c - pr);
        }
        if pu < POT_HIGH {
            gyv = gyv + (pu - c);
        }
        if pd < POT_HIGH {
            gyv = gyv + (c - pd);
        }
    }
    let norm = hypotf(gxv, gyv);
    if norm > 0.0 {
        let inv = (1.0 / norm as f64) as f32;
        if let Some(g) = grad.get_mut(slot) {
            *g = [inv * gxv, inv * gyv];
            touched.push(slot as u32);
        }
    }
}

impl NavFn {
    /// `calcPath(n)`: descend from NavFn start to NavFn goal for at most `n` iterations.
    /// Returns the number of points (0 = failure); the points are in [`NavFn::path`].
    pub fn calc_path<O: SearchObserver>(&mut self, n: usize, obs: &mut O) -> usize {
        obs.on_path_start(&PathStartView {
            start_cell: self.start_index(),
            goal_cell: self.goal_index(),
            max_iterations: n,
            potential: &self.pot,
        });
        self.path.clear();
        self.path_len = 0;
        let len = self.descend(n, obs);
        self.path_len = len;
        len
    }

    fn descend<O: SearchObserver>(&mut self, n: usize, obs: &mut O) -> usize {
        let nx = self.nx as i64;
        let nxf = self.nx as f32;
        let width = WidthDiv::new(self.nx);
        let goal = [self.goal.x as f32, self.goal.y as f32];
        let mut stc = self.start_index() as i64;
        let NavFn { pot, grad, path, .. } = self;
        let pot: &[f32] = pot;
        let (layout, grad, touched) = grad.parts();
        let ns = pot.len() as i64;
        let (mut dx, mut dy) = (0.0f32, 0.0f32);
        for iteration in 0..n {
            // success is tested on the rounded position
            let near = stc + round_half_away(dx) + (nxf * round_half_away(dy) as f32) as i64;
            if pot_at(pot, near.clamp(0, ns - 1)) < COST_NEUTRAL as f32 {
                path.push(goal);
                return path.len();
            }
            if stc < nx || stc > ns - nx {
                return 0;
            }
            // the point is recorded before moving
            let (col, row) = width.col_row(stc as usize);
            let point = [col as f32 + dx, row as f32 + dy];
            let osc = path.len() >= 2 && path[path.len() - 2] == point;
            path.push(point);
            if osc {
                obs.on_path_oscillation(iteration, point);
            }
            let block = block_around(pot, stc, nx);
            // potentials are never NaN: "any ≥ 1e10" is "the largest ≥ 1e10"
            if osc || block.iter().fold(0.0f32, |a, &b| a.max(b)) >= POT_HIGH {
                stc = lowest_neighbour(&block, stc, nx);
                (dx, dy) = (0.0, 0.0);
                if pot_at(pot, stc) >= POT_HIGH {
                    return 0;
                }
            } else {
                // all nine cells are finite, hence inside the array and off the border ring
                // (only the goal can be finite there, and then its two ring neighbours in
                // the block are not): the 2×2 block is cells (col..col+1, row..row+1)
                let slots = layout.block(stc as usize, col as usize, row as usize);
                let [s00, s01, s10, s11] = slots;
                grad_cell(pot, grad, touched, nx, stc, s00);
                grad_cell(pot, grad, touched, nx, stc + 1, s01);
                grad_cell(pot, grad, touched, nx, stc + nx, s10);
                grad_cell(pot, grad, touched, nx, stc + nx + 1, s11);
                match gradient_step(grad, slots, stc, nx, dx, dy) {
                    Some(next) => (stc, dx, dy) = next,
                    None => return 0,
                }
            }
        }
        0
    }
}

/// The potentials of the 3×3 block around `stc`: the row below (`stc - nx`), the cell's row,
/// the row above, each west to east. Outside the array they read as unreached.
#[inline(always)]
fn block_around(pot: &[f32], stc: i64, nx: i64) -> [f32; 9] {
    let (south, north) = (stc - nx, stc + nx);
    if south >= 1 {
        let row = |centre: i64| pot.get(centre as usize - 1..centre as usize + 2);
        if let (Some(s), Some(m), Some(n)) = (row(south), row(stc), row(north)) {
            return [s[0], s[1], s[2], m[0], m[1], m[2], n[0], n[1], n[2]];
        }
    }
    let p = |i: i64| pot_at(pot, i);
    [
        p(south - 1),
        p(south),
        p(south + 1),
        p(stc - 1),
        p(stc),
        p(stc + 1),
        p(north - 1),
        p(north),
        p(north + 1),
    ]
}

/// Grid following: the lowest of the eight neighbours of `stc` (first lowest in navfn.cpp's
/// order), compared against the potential truncated to int (INT_MIN for an unreached cell,
/// x86-64); `stc` itself when none is lower.
#[inline(always)]
fn lowest_neighbour(block: &[f32; 9], stc: i64, nx: i64) -> i64 {
    let (south, north) = (stc - nx, stc + nx);
    let cells = [south - 1, south, south + 1, stc - 1, stc + 1, north - 1, north, north + 1];
    let values = [block[0], block[1], block[2], block[3], block[5], block[6], block[7], block[8]];
    let mut minc = stc;
    let mut minp = c_float_to_int(block[4]);
    for (s, ps) in cells.into_iter().zip(values) {
        if ps < minp as f32 {
            minp = c_float_to_int(ps);
            minc = s;
        }
    }
    minc
}

/// One half-cell step along the interpolated gradient from offset `(dx, dy)` in cell `stc`;
/// the new cell and offset, or `None` for a zero gradient (failure).
#[inline(always)]
fn gradient_step(
    grad: &[[f32; 2]],
    slots: [usize; 4],
    stc: i64,
    nx: i64,
    dx: f32,
    dy: f32,
) -> Option<(i64, f32, f32)> {
    let [g00, g01, g10, g11] = slots.map(|s| grad.get(s).copied().unwrap_or([0.0; 2]));
    let (dxd, dyd) = (dx as f64, dy as f64);
    // first product in double, second a float product widened (as in C++)
    let x1 = ((1.0 - dxd) * g00[0] as f64 + (dx * g01[0]) as f64) as f32;
    let x2 = ((1.0 - dxd) * g10[0] as f64 + (dx * g11[0]) as f64) as f32;
    let x = ((1.0 - dyd) * x1 as f64 + (dy * x2) as f64) as f32;
    let y1 = ((1.0 - dxd) * g00[1] as f64 + (dx * g01[1]) as f64) as f32;
    let y2 = ((1.0 - dxd) * g10[1] as f64 + (dx * g11[1]) as f64) as f32;
    let y = ((1.0 - dyd) * y1 as f64 + (dy * y2) as f64) as f32;
    if x == 0.0 && y == 0.0 {
        return None;
    }
    let ss = 0.5f32 / hypotf(x, y);
    let (mut stc, mut dx, mut dy) = (stc, dx + x * ss, dy + y * ss);
    if dx > 1.0 {
        stc += 1;
        dx = dx - 1.0;
    }
    if dx < -1.0 {
        stc -= 1;
        dx = dx + 1.0;
    }
    if dy > 1.0 {
        stc += nx;
        dy = dy - 1.0;
    }
    if dy < -1.0 {
        stc -= nx;
        dy = dy + 1.0;
    }
    Some((stc, dx, dy))
}
