//! Set-up and potential propagation (`setupNavFn`, `updateCell`, `updateCellAstar`,
//! `propNavFnDijkstra`, `propNavFnAstar`), SEMANTICS.md §4.

use super::numeric::astar_heuristic;
use super::observer::{CycleView, PropagationEnd, PropagationEndView, SearchObserver};
use super::{COST_OBS, CUR_T_INIT, NavFn, POT_HIGH, PRIORITY_BUF_SIZE};
use prefetch_index::prefetch_index;

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

/// One of the three priority buffers: `PRIORITY_BUF_SIZE` cells plus one slot of slack, so that
/// a push can store its cell before it is known whether the push counts (no branch per test).
pub(crate) struct PriorityBuf {
    cells: Box<[i32]>,
    len: usize,
}

impl PriorityBuf {
    pub(crate) fn new() -> Self {
        PriorityBuf { cells: vec![0; PRIORITY_BUF_SIZE + 1].into_boxed_slice(), len: 0 }
    }
    /// The queued cells, in order.
    #[inline(always)]
    pub(crate) fn as_slice(&self) -> &[i32] {
        &self.cells[..self.len]
    }
    #[inline(always)]
    pub(crate) fn clear(&mut self) {
        self.len = 0;
    }
    #[inline(always)]
    fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The push macros of navfn.cpp (`push_cur/next/over`) guarded by the update's own test:
    /// append iff `test`, the cell is not pending, its cost is < 254 and the buffer has room; a
    /// push into a full buffer is silently dropped, as upstream. Computed without branches (the
    /// tests are data-dependent and mispredict often). The caller guarantees `n` is inside the
    /// arrays (upstream tests `0 ≤ n < ns` here; only the goal's neighbours at set-up can fall
    /// outside, and set-up tests that itself).
    #[inline(always)]
    fn push_if(&mut self, test: bool, pending: &mut [u8], cost: &[u8], n: usize) {
        let ok = test & (pending[n] == 0) & (cost[n] < COST_OBS) & (self.len < PRIORITY_BUF_SIZE);
        self.cells[self.len] = n as i32;
        self.len += ok as usize;
        pending[n] |= ok as u8;
    }
}

/// `n / d` and `n % d` for the map width, by a multiplication (Lemire, Kaser, Kurz 2019:
/// `M = ⌊(2^64−1)/d⌋ + 1`, quotient = high 64 bits of `M·n`, exact for every 32-bit `n` and
/// `2 ≤ d < 2^32`); the A* update needs the cell's column and row, and a hardware division per
/// update costs more than the rest of the index arithmetic.
#[derive(Clone, Copy)]
pub(crate) struct WidthDiv {
    d: u64,
    m: u64,
}

impl WidthDiv {
    pub(crate) fn new(d: usize) -> Self {
        let d = d as u64;
        WidthDiv { d, m: if d >= 2 { u64::MAX / d + 1 } else { 0 } }
    }
    /// `(n % d, n / d)` for `n < 2^32`.
    #[inline(always)]
    pub(crate) fn col_row(self, n: usize) -> (u64, u64) {
        let n = n as u64;
        let q = if self.d >= 2 { ((self.m as u128 * n as u128) >> 64) as u64 } else { n };
        (n - q * self.d, q)
    }
}

/// The arrays one propagation cycle works on (disjoint borrows of a [`NavFn`]).
struct Grid<'a> {
    pot: &'a mut [f32],
    cost: &'a [u8],
    pending: &'a mut [u8],
    nx: usize,
}

/// How many queued cells ahead of the one being updated the loop prefetches.
const PREFETCH_AHEAD: usize = 6;

impl Grid<'_> {
    /// Asks the cache for the lines of the rows above and below cell `n` that its update
    /// reads, in the three arrays (its own row's lines were read by the neighbour update that
    /// queued it, and are mostly still cached). On a large map the queue jumps along the
    /// propagation front, so these lines are often out of the first cache levels; the update
    /// waits for them, and a prefetch a few cells ahead overlaps the waits. A hint only: it
    /// never faults and changes no value (hence no bounds: an index past the array is fine).
    #[inline(always)]
    fn prefetch(&self, n: usize) {
        for i in [n.wrapping_sub(self.nx), n.wrapping_add(self.nx)] {
            prefetch_index(&*self.pot, i);
            prefetch_index(self.cost, i);
            prefetch_index(&*self.pending, i);
        }
    }
}

/// What the A* update adds (unused by Dijkstra).
#[derive(Clone, Copy)]
struct Heuristic {
    width: WidthDiv,
    start_x: i64,
    start_y: i64,
}

/// `updateCell` (ASTAR = false) and `updateCellAstar` (ASTAR = true) for a queued cell `n`.
/// Queued cells have cost < 254, hence are never on the border ring, so the four neighbour
/// indices are in range.
#[inline(always)]
fn update_cell<const ASTAR: bool>(
    g: &mut Grid<'_>,
    n: usize,
    cur_t: f32,
    heuristic: Heuristic,
    next: &mut PriorityBuf,
    over: &mut PriorityBuf,
) {
    let nx = g.nx;
    let ns = g.pot.len();
    // Never true for a queued cell; stating it lets the compiler drop the bounds checks of
    // the neighbour reads below (a measurable share of the update).
    if n <= nx || n + nx >= ns || g.cost.len() != ns || g.pending.len() != ns {
        return;
    }
    let l = g.pot[n - 1];
    let r = g.pot[n + 1];
    let u = g.pot[n - nx];
    let d = g.pot[n + nx];
    let tc = if l < r { l } else { r };
    let mut ta = if u < d { u } else { d };
    let c = g.cost[n];
    if c >= COST_OBS {
        return;
    }
    let hf = c as f32;
    let mut dc = tc - ta;
    if dc < 0.0 {
        dc = -dc;
        ta = tc;
    }
    // float division, then the quadratic in double with double literals, in the
    // C++ evaluation order ((-a*q)*q + b*q) + c; one rounding to float at the end.
    let quadratic = || {
        let q = (dc / hf) as f64;
        let v = ((-0.2301 * q) * q + 0.5307 * q) + 0.7040;
        ta + hf * (v as f32)
    };
    let mut pot = if ASTAR {
        // A* expands whole random maps, where which candidate applies is a coin toss and a
        // mispredicted branch also discards the loads of the following updates (about a tenth
        // of the time on a 500² random map): both are computed and one is selected. The
        // unused candidate has no effect (no float traps; 0/0 when `hf` is 0 only yields a
        // NaN that is not selected). Dijkstra keeps the branch: on the paper suite's maps it
        // predicts well, and computing both cost it 15 %.
        std::hint::select_unpredictable(dc >= hf, ta + hf, quadratic())
    } else if dc >= hf {
        ta + hf
    } else {
        quadratic()
    };
    if pot < g.pot[n] {
        let le = EDGE[g.cost[n - 1] as usize];
        let re = EDGE[g.cost[n + 1] as usize];
        let ue = EDGE[g.cost[n - nx] as usize];
        let de = EDGE[g.cost[n + nx] as usize];
        g.pot[n] = pot;
        if ASTAR {
            let (x, y) = heuristic.width.col_row(n);
            let h = astar_heuristic(x as i64 - heuristic.start_x, y as i64 - heuristic.start_y);
            pot = pot + h;
        }
        let buf = if pot < cur_t { next } else { over };
        let (pending, cost) = (&mut *g.pending, g.cost);
        buf.push_if(l > pot + le, pending, cost, n - 1);
        buf.push_if(r > pot + re, pending, cost, n + 1);
        buf.push_if(u > pot + ue, pending, cost, n - nx);
        buf.push_if(d > pot + de, pending, cost, n + nx);
    }
}

impl NavFn {
    /// `setupNavFn(keepit=true)`: reset potentials and gradients, force the border ring to 254,
    /// empty the buffers, put the goal at potential 0 and queue its four neighbours.
    pub fn setup(&mut self) {
        self.pot.fill(POT_HIGH);
        // gradients: only the cells the last path extraction cached are non-zero
        for &n in &self.grad_touched {
            self.grad[n as usize] = [0.0; 2];
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
            for &n in b.as_slice() {
                self.pending[n as usize] = 0;
            }
        }
        debug_assert!(self.pending.iter().all(|&p| p == 0));
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
                self.cur.push_if(true, &mut self.pending, &self.cost, n as usize);
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
        let heuristic = Heuristic {
            width: WidthDiv::new(self.nx),
            start_x: self.start.x as i64,
            start_y: self.start.y as i64,
        };
        let pri_inc = self.pri_inc;
        let mut cur_t = self.cur_t;
        let NavFn { pot, cost, pending, cur, next, over, nx, .. } = self;
        let mut g = Grid { pot: &mut pot[..], cost: &cost[..], pending: &mut pending[..], nx: *nx };
        let mut cycle = 0;
        let mut end = PropagationEnd::CycleLimit;
        while cycle < cycles {
            obs.on_cycle(&CycleView {
                cycle,
                threshold: cur_t,
                current: cur.as_slice(),
                next: next.as_slice(),
                overflow: over.as_slice(),
                potential: g.pot,
            });
            // (the upstream cancel hook every 5,000 cycles has no numeric effect)
            if cur.is_empty() && next.is_empty() {
                end = PropagationEnd::QueuesEmpty;
                break;
            }
            for &c in cur.as_slice() {
                g.pending[c as usize] = 0;
            }
            let queued = cur.as_slice();
            for (i, &c) in queued.iter().enumerate() {
                if let Some(&ahead) = queued.get(i + PREFETCH_AHEAD) {
                    g.prefetch(ahead as usize);
                }
                update_cell::<ASTAR>(&mut g, c as usize, cur_t, heuristic, next, over);
            }
            // next becomes current; the old current storage becomes the empty next
            std::mem::swap(cur, next);
            next.clear();
            if cur.is_empty() {
                cur_t = cur_t + pri_inc;
                std::mem::swap(cur, over);
                over.clear();
            }
            if stop_at_start && g.pot[start_cell] < POT_HIGH {
                end = PropagationEnd::StartReached;
                break;
            }
            cycle += 1;
        }
        obs.on_propagation_end(&PropagationEndView {
            cycles: cycle,
            end,
            threshold: cur_t,
            current: cur.as_slice(),
            next: next.as_slice(),
            overflow: over.as_slice(),
            potential: g.pot,
        });
        self.cur_t = cur_t;
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

#[cfg(test)]
mod tests {
    use super::WidthDiv;

    /// The multiplication gives the hardware quotient and remainder (widths and indices at the
    /// ends of their ranges, and a sample in between).
    #[test]
    fn width_division_is_exact() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let mut widths: Vec<usize> = (1..=70).chain([4095, 4096, 4097, 46_340, 65_535]).collect();
        widths.extend((0..200).map(|_| 1 + (rnd() % (i32::MAX as u64)) as usize));
        for d in widths {
            let w = WidthDiv::new(d);
            let mut ns: Vec<usize> = (0..300).chain([i32::MAX as usize - 1, d, d - 1]).collect();
            ns.extend((0..300).map(|_| (rnd() % (i32::MAX as u64)) as usize));
            for n in ns {
                assert_eq!(w.col_row(n), ((n % d) as u64, (n / d) as u64), "{n} / {d}");
            }
        }
    }
}
