//! Path extraction (`calcPath`, `gradCell`), SEMANTICS.md §5–6.

use super::numeric::{c_float_to_int, hypotf, round_half_away};
use super::observer::{PathStartView, SearchObserver};
use super::{COST_NEUTRAL, COST_OBS, NavFn, POT_HIGH};

impl NavFn {
    /// Potential read that tolerates the out-of-array reads the C++ can make on the border
    /// ring (index −1 or `ns`): an outside cell reads as unreached. This only matters for
    /// start cells on the border, which the C++ handles with undefined behaviour.
    #[inline(always)]
    fn pot_at(&self, i: i64) -> f32 {
        if i < 0 || i as usize >= self.ns { POT_HIGH } else { self.pot[i as usize] }
    }

    /// `gradCell(n)`: normalised gradient of the potential at `n`, cached in `gx/gy`.
    fn grad_cell(&mut self, n: i64) {
        let (nx, ns) = (self.nx as i64, self.ns as i64);
        if n < 0 || n >= ns {
            return;
        }
        let nu = n as usize;
        let [gx_cached, gy_cached] = self.grad[nu];
        if gx_cached + gy_cached > 0.0 {
            return; // cached
        }
        if n < nx || n > ns - nx {
            return;
        }
        let c = self.pot[nu];
        let mut gxv = 0.0f32;
        let mut gyv = 0.0f32;
        let (pl, pr, pu, pd) =
            (self.pot_at(n - 1), self.pot_at(n + 1), self.pot_at(n - nx), self.pot_at(n + nx));
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
            self.grad_touched.push(n as u32);
            self.grad[nu] = [inv * gxv, inv * gyv];
        }
    }

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
        let ns = self.ns as i64;
        let nxf = self.nx as f32;
        let mut stc = self.start_index() as i64;
        let mut dx = 0.0f32;
        let mut dy = 0.0f32;
        for iteration in 0..n {
            // success is tested on the rounded position
            let near = stc + round_half_away(dx) + (nxf * round_half_away(dy) as f32) as i64;
            let near = near.clamp(0, ns - 1);
            if self.pot[near as usize] < COST_NEUTRAL as f32 {
                self.path.push([self.goal.x as f32, self.goal.y as f32]);
                return self.path.len();
            }
            if stc < nx || stc > ns - nx {
                return 0;
            }
            // the point is recorded before moving
            self.path.push([(stc % nx) as f32 + dx, (stc / nx) as f32 + dy]);
            let np = self.path.len();
            let osc = np > 2 && self.path[np - 1] == self.path[np - 3];
            if osc {
                obs.on_path_oscillation(iteration, self.path[np - 1]);
            }
            let north = stc + nx;
            let south = stc - nx;
            let p = |i: i64| self.pot_at(i);
            let unreached_near = if south >= 1 && north + 1 < ns {
                // common case: the 3x3 block is inside the array; read its three rows directly
                let s0 = (south - 1) as usize;
                let (n0, m0) = ((north - 1) as usize, (stc - 1) as usize);
                // the same nine tests as below (potentials are never NaN, so "any ≥ 1e10" is
                // "the largest ≥ 1e10"), without a branch per cell
                let row_max = |i: usize| {
                    let r = &self.pot[i..i + 3];
                    r[0].max(r[1]).max(r[2])
                };
                row_max(s0).max(row_max(m0)).max(row_max(n0)) >= POT_HIGH
            } else {
                p(stc) >= POT_HIGH
                    || p(stc + 1) >= POT_HIGH
                    || p(stc - 1) >= POT_HIGH
                    || p(north) >= POT_HIGH
                    || p(north + 1) >= POT_HIGH
                    || p(north - 1) >= POT_HIGH
                    || p(south) >= POT_HIGH
                    || p(south + 1) >= POT_HIGH
                    || p(south - 1) >= POT_HIGH
            };
            if unreached_near || osc {
                // grid following: lowest of the eight neighbours, compared against the
                // potential truncated to int (INT_MIN for an unreached cell, x86-64)
                let mut minc = stc;
                let mut minp = c_float_to_int(p(stc));
                for s in
                    [south - 1, south, south + 1, stc - 1, stc + 1, north - 1, north, north + 1]
                {
                    let ps = p(s);
                    if ps < minp as f32 {
                        minp = c_float_to_int(ps);
                        minc = s;
                    }
                }
                stc = minc;
                dx = 0.0;
                dy = 0.0;
                if self.pot_at(stc) >= POT_HIGH {
                    return 0;
                }
            } else {
                // all nine cells are finite, hence inside the array
                self.grad_cell(stc);
                self.grad_cell(stc + 1);
                self.grad_cell(north);
                self.grad_cell(north + 1);
                let (s0, s1, n0, n1) =
                    (stc as usize, stc as usize + 1, north as usize, north as usize + 1);
                let dxd = dx as f64;
                let dyd = dy as f64;
                // first product in double, second a float product widened (as in C++)
                let x1 =
                    ((1.0 - dxd) * self.grad[s0][0] as f64 + (dx * self.grad[s1][0]) as f64) as f32;
                let x2 =
                    ((1.0 - dxd) * self.grad[n0][0] as f64 + (dx * self.grad[n1][0]) as f64) as f32;
                let x = ((1.0 - dyd) * x1 as f64 + (dy * x2) as f64) as f32;
                let y1 =
                    ((1.0 - dxd) * self.grad[s0][1] as f64 + (dx * self.grad[s1][1]) as f64) as f32;
                let y2 =
                    ((1.0 - dxd) * self.grad[n0][1] as f64 + (dx * self.grad[n1][1]) as f64) as f32;
                let y = ((1.0 - dyd) * y1 as f64 + (dy * y2) as f64) as f32;
                if x == 0.0 && y == 0.0 {
                    return 0;
                }
                let ss = 0.5f32 / hypotf(x, y);
                dx = dx + x * ss;
                dy = dy + y * ss;
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
            }
        }
        0
    }
}
