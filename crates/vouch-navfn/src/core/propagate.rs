//! Set-up and potential propagation (`setupNavFn`, `updateCell`, `updateCellAstar`,
//! `propNavFnDijkstra`, `propNavFnAstar`), SEMANTICS.md §4.

use super::numeric::astar_heuristic;
use super::observer::{CycleView, PropagationEnd, PropagationEndView, SearchObserver};
use super::{NavFn, COST_OBS, CUR_T_INIT, POT_HIGH, PRIORITY_BUF_SIZE};

/// `INVSQRT2` of navfn.cpp: a double literal, not exactly 1/√2 (hence not `FRAC_1_SQRT_2`).
#[allow(clippy::approx_constant)]
const INVSQRT2: f64 = 0.707106781;

/// `f32(INVSQRT2 · f64(f32(cost)))` for every cost byte: the neighbour thresholds
/// `le, re, ue, de` of `updateCell`, computed once instead of per update (same roundings).
static EDGE: [f32; 256] = {
    let mut t = [0.0f32; 256];
    let mut c = 0;
    while c < 256 {
        t[c] = (INVSQRT2 * (c as f32) as f64) as f32;
        c += 1;
    }
    t
};

/// The push macros of navfn.cpp (`push_cur/next/over`): append iff not pending, cost < 254
/// and the buffer has room; a push into a full buffer is silently dropped, as upstream. The
/// caller guarantees `n` is inside the array (upstream tests `0 ≤ n < ns` here; only the
/// goal's neighbours at set-up can fall outside, and set-up tests that itself).
#[inline(always)]
fn push_inner(buf: &mut Vec<i32>, pending: &mut [bool], cost: &[u8], n: usize) {
    if !pending[n] && cost[n] < COST_OBS && buf.len() < PRIORITY_BUF_SIZE {
        buf.push(n as i32);
        pending[n] = true;
    }
}

impl NavFn {
    /// `setupNavFn(keepit=true)`: reset potentials and gradients, force the border ring to 254,
    /// empty the buffers, put the goal at potential 0 and queue its four neighbours.
    pub fn setup(&mut self) {
        self.pot.fill(POT_HIGH);
        // gradients: only the cells the last path extraction cached are non-zero
        for &n in &self.grad_touched {
            self.gx[n as usize] = 0.0;
            self.gy[n as usize] = 0.0;
        }
        self.grad_touched.clear();
        let (nx, ny) = (self.nx, self.ny);
        self.cost[..nx].fill(COST_OBS);
        self.cost[(ny - 1) * nx..].fill(COST_OBS);
        for row in 0..ny {
            self.cost[row * nx] = COST_OBS;
            self.cost[row * nx + nx - 1] = COST_OBS;
        }
        self.cur_t = CUR_T_INIT;
        // `pending` is true exactly for the cells still in a buffer (the loop clears the
        // current buffer's flags before processing it), so clearing those suffices
        for b in [&self.cur, &self.next, &self.over] {
            for &n in b.iter() {
                self.pending[n as usize] = false;
            }
        }
        debug_assert!(self.pending.iter().all(|&p| !p));
        self.cur.clear();
        self.next.clear();
        self.over.clear();
        self.last_path_cost = POT_HIGH;
        let k = self.goal_index() as i64;
        self.pot[k as usize] = 0.0;
        let nx = nx as i64;
        for n in [k + 1, k - 1, k - nx, k + nx] {
            // the goal may sit on the border, so its neighbours need the range test
            if n >= 0 && (n as usize) < self.ns {
                push_inner(&mut self.cur, &mut self.pending, &self.cost, n as usize);
            }
        }
    }

    /// `updateCell` (ASTAR = false) and `updateCellAstar` (ASTAR = true) for a queued cell.
    /// Queued cells have cost < 254, hence are never on the border ring, so the four
    /// neighbour indices are in range.
    #[inline(always)]
    fn update_cell<const ASTAR: bool>(&mut self, n: usize) {
        let nx = self.nx;
        let ns = self.pot.len();
        // Never true for a queued cell; stating it lets the compiler drop the bounds checks
        // of the neighbour reads below (a measurable share of the update).
        if n <= nx || n + nx >= ns || self.cost.len() != ns || self.pending.len() != ns {
            return;
        }
        let l = self.pot[n - 1];
        let r = self.pot[n + 1];
        let u = self.pot[n - nx];
        let d = self.pot[n + nx];
        let tc = if l < r { l } else { r };
        let mut ta = if u < d { u } else { d };
        let c = self.cost[n];
        if c >= COST_OBS {
            return;
        }
        let hf = c as f32;
        let mut dc = tc - ta;
        if dc < 0.0 {
            dc = -dc;
            ta = tc;
        }
        let mut pot = if dc >= hf {
            ta + hf
        } else {
            // float division, then the quadratic in double with double literals, in the
            // C++ evaluation order ((-a*q)*q + b*q) + c; one rounding to float at the end.
            let q = (dc / hf) as f64;
            let v = ((-0.2301 * q) * q + 0.5307 * q) + 0.7040;
            ta + hf * (v as f32)
        };
        if pot < self.pot[n] {
            let le = EDGE[self.cost[n - 1] as usize];
            let re = EDGE[self.cost[n + 1] as usize];
            let ue = EDGE[self.cost[n - nx] as usize];
            let de = EDGE[self.cost[n + nx] as usize];
            self.pot[n] = pot;
            if ASTAR {
                // 32-bit division like the C++ `int` arithmetic (and much cheaper than 64-bit)
                let (n32, nx32) = (n as u32, nx as u32);
                let x = (n32 % nx32) as i64;
                let y = (n32 / nx32) as i64;
                let h = astar_heuristic(x - self.start.x as i64, y - self.start.y as i64);
                pot = pot + h;
            }
            let buf = if pot < self.cur_t { &mut self.next } else { &mut self.over };
            let (pending, cost) = (&mut self.pending, &self.cost);
            if l > pot + le {
                push_inner(buf, pending, cost, n - 1);
            }
            if r > pot + re {
                push_inner(buf, pending, cost, n + 1);
            }
            if u > pot + ue {
                push_inner(buf, pending, cost, n - nx);
            }
            if d > pot + de {
                push_inner(buf, pending, cost, n + nx);
            }
        }
    }

    /// The shared main loop. `stop_at_start` is `atStart` for Dijkstra and always true for A*.
    /// Returns the loop index at exit and why it exited.
    fn propagate<const ASTAR: bool, O: SearchObserver>(
        &mut self,
        cycles: usize,
        stop_at_start: bool,
        obs: &mut O,
    ) -> (usize, PropagationEnd) {
        let start_cell = self.start_index();
        let mut cycle = 0;
        let mut end = PropagationEnd::CycleLimit;
        while cycle < cycles {
            obs.on_cycle(&CycleView {
                cycle,
                threshold: self.cur_t,
                current: &self.cur,
                next: &self.next,
                overflow: &self.over,
                potential: &self.pot,
            });
            // (the upstream cancel hook every 5,000 cycles has no numeric effect)
            if self.cur.is_empty() && self.next.is_empty() {
                end = PropagationEnd::QueuesEmpty;
                break;
            }
            // Taking the buffer out lets the updates push into `next`/`over` while we walk
            // it; it is a pointer move, not an allocation.
            let cur = std::mem::take(&mut self.cur);
            for &c in &cur {
                self.pending[c as usize] = false;
            }
            for &c in &cur {
                self.update_cell::<ASTAR>(c as usize);
            }
            self.cur = cur;
            // next becomes current; the old current storage becomes the empty next
            std::mem::swap(&mut self.cur, &mut self.next);
            self.next.clear();
            if self.cur.is_empty() {
                self.cur_t = self.cur_t + self.pri_inc;
                std::mem::swap(&mut self.cur, &mut self.over);
                self.over.clear();
            }
            if stop_at_start && self.pot[start_cell] < POT_HIGH {
                end = PropagationEnd::StartReached;
                break;
            }
            cycle += 1;
        }
        obs.on_propagation_end(&PropagationEndView {
            cycles: cycle,
            end,
            threshold: self.cur_t,
            current: &self.cur,
            next: &self.next,
            overflow: &self.over,
            potential: &self.pot,
        });
        (cycle, end)
    }

    /// `propNavFnDijkstra(cycles, atStart)`; call [`NavFn::setup`] first.
    /// Returns true iff the loop ended before `cycles` iterations.
    pub fn propagate_dijkstra<O: SearchObserver>(
        &mut self,
        cycles: usize,
        at_start: bool,
        obs: &mut O,
    ) -> bool {
        let (cycle, _) = self.propagate::<false, O>(cycles, at_start, obs);
        cycle < cycles
    }

    /// `propNavFnAstar(cycles)`; call [`NavFn::setup`] first. Stores `last_path_cost` and
    /// returns true iff the start cell's potential is finite.
    pub fn propagate_astar<O: SearchObserver>(&mut self, cycles: usize, obs: &mut O) -> bool {
        let dx = self.goal.x as i64 - self.start.x as i64;
        let dy = self.goal.y as i64 - self.start.y as i64;
        self.cur_t = astar_heuristic(dx, dy) + self.cur_t;
        self.propagate::<true, O>(cycles, true, obs);
        self.last_path_cost = self.pot[self.start_index()];
        self.last_path_cost < POT_HIGH
    }
}
