//! Set-up and potential propagation (`setupNavFn`, `updateCell`, `updateCellAstar`,
//! `propNavFnDijkstra`, `propNavFnAstar`), SEMANTICS.md §4.
//!
//! The update order and every rounding are the C++'s; what differs is how the work is laid
//! out for the processor:
//! * the push test of navfn.cpp (`!pending[n] && costarr[n] < COST_OBS`) reads one byte array,
//!   `blocked` (1 while a cell is queued or an obstacle), kept apart from the read-only costs so
//!   that the cost loads of an update never wait on the flag stores of the previous one;
//! * one propagation cycle (`sweep`) holds the lengths of the buffers it fills in locals, and
//!   an update whose buffer has room for its four candidates pushes them without a capacity
//!   test each (the common case; a nearly full buffer takes the tested path, same result);
//! * the four pushes of an update are computed without branches (their tests are
//!   data-dependent and mispredict often).

use super::numeric::{WidthDiv, astar_heuristic};
use super::observer::{CycleView, PropagationEnd, PropagationEndView, SearchObserver};
use super::{COST_OBS, CUR_T_INIT, NavFn, POT_HIGH, PRIORITY_BUF_SIZE};
use prefetch_index::prefetch_index;

/// `INVSQRT2` of navfn.cpp: a double literal, not exactly 1/√2 (hence not `FRAC_1_SQRT_2`).
#[allow(clippy::approx_constant)]
const INVSQRT2: f64 = 0.707106781;

/// Capacity of a priority buffer, and its storage: four slots of slack so that an update can
/// store its four candidates before it is known which of them count.
const CAP: usize = PRIORITY_BUF_SIZE;
const SLOTS: usize = CAP + 4;

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

/// One of the three priority buffers (`pb1..pb3` with their end counters upstream).
pub(crate) struct PriorityBuf {
    cells: Box<[i32; SLOTS]>,
    len: usize,
}

impl PriorityBuf {
    pub(crate) fn new() -> Self {
        PriorityBuf { cells: Box::new([0; SLOTS]), len: 0 }
    }
    #[inline(always)]
    pub(crate) fn clear(&mut self) {
        self.len = 0;
    }
}

/// The push macros of navfn.cpp (`push_next`/`push_over`) for the four candidates of one
/// update, `n-1, n+1, n-nx, n+nx` in that order: candidate `k` is appended iff the update's
/// own test `neighbour[k] > priority + edge[k]` holds, it is not blocked (queued or an
/// obstacle) and the buffer has room; a push into a full buffer is dropped, as upstream. Each
/// test is made just before its push, so that only floats wait in registers. The caller
/// guarantees the candidates are inside the arrays (upstream tests `0 ≤ n < ns`; only the
/// goal's neighbours at set-up can fall outside, and set-up tests that itself).
#[inline(always)]
fn push4(
    cells: &mut [i32; SLOTS],
    len: &mut usize,
    blocked: &mut [u8],
    candidates: [usize; 4],
    priority: f32,
    neighbour: [f32; 4],
    edge: [f32; 4],
) {
    let base = *len;
    if base <= CAP - 4 {
        // room for all four: the capacity test cannot fail
        let slots = &mut cells[base..base + 4];
        let mut pushed = 0usize;
        for k in 0..4 {
            let m = candidates[k];
            let b = blocked[m];
            let ok = (neighbour[k] > priority + edge[k]) & (b == 0);
            slots[pushed & 3] = m as i32;
            pushed += ok as usize;
            blocked[m] = b | ok as u8;
        }
        *len = base + pushed;
    } else {
        let mut end = base;
        for k in 0..4 {
            let m = candidates[k];
            let b = blocked[m];
            let ok = (neighbour[k] > priority + edge[k]) & (b == 0) & (end < CAP);
            cells[end.min(CAP)] = m as i32;
            end += ok as usize;
            blocked[m] = b | ok as u8;
        }
        *len = end;
    }
}

/// The two buffers a cycle fills, their lengths in locals.
struct Outputs<'a> {
    next: &'a mut [i32; SLOTS],
    next_len: usize,
    over: &'a mut [i32; SLOTS],
    over_len: usize,
}

/// The queued cells of a buffer's storage.
#[inline(always)]
fn queued(cells: &[i32; SLOTS], len: usize) -> &[i32] {
    &cells[..len.min(CAP)]
}

/// The parts the three buffers play in a propagation cycle.
#[derive(Clone, Copy)]
enum Role {
    Current = 0,
    Next = 1,
    Overflow = 2,
}

/// Which buffer (0 = `cur`, 1 = `next`, 2 = `over` at the start of the loop) plays each
/// [`Role`] now.
struct Roles([u8; 3]);

impl Roles {
    fn new() -> Self {
        Roles([0, 1, 2])
    }

    #[inline(always)]
    fn swap(&mut self, a: Role, b: Role) {
        self.0.swap(a as usize, b as usize);
    }

    /// Moves the storages back so that `bufs[r]` holds what plays role `r`, with its length.
    fn put_back(&self, bufs: [&mut PriorityBuf; 3], lens: [usize; 3]) {
        let mut bufs = bufs;
        // holds[k]: which original buffer's storage is in bufs[k] now
        let mut holds = [0u8, 1, 2];
        for r in 0..3 {
            if let Some(k) = (r..3).find(|&k| holds[k] == self.0[r]) {
                let (head, tail) = bufs.split_at_mut(k);
                if let Some(target) = head.get_mut(r) {
                    std::mem::swap(&mut **target, &mut *tail[0]);
                    holds.swap(r, k);
                }
            }
            bufs[r].len = lens[r];
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

/// How many queued cells ahead of the one being updated A* prefetches.
const PREFETCH_AHEAD: usize = 6;

/// Asks the cache for the lines of the rows above and below cell `n` that its update reads,
/// in the three arrays (its own row's lines were read by the neighbour update that queued it,
/// and are mostly still cached). A* updates most cells once or twice, and on a large map its
/// queue jumps along the front, so these lines are often out of the first cache levels; a
/// prefetch a few cells ahead overlaps the waits. Dijkstra re-updates the cells of its front
/// several times while they are cached, and gains nothing from it. A hint only: it never
/// faults and changes no value (hence no bounds: an index past the array is fine).
#[inline(always)]
fn prefetch_rows(pot: &[f32], cost: &[u8], blocked: &[u8], nx: usize, n: usize) {
    for i in [n.wrapping_sub(nx), n.wrapping_add(nx)] {
        prefetch_index(pot, i);
        prefetch_index(cost, i);
        prefetch_index(blocked, i);
    }
}

/// One propagation cycle: `updateCell` (ASTAR = false) or `updateCellAstar` (ASTAR = true) on
/// every queued cell in order, pushing into `out`. The arrays come as plain slices and the
/// update is written out in the loop: the compiler then keeps the addresses and both buffer
/// lengths in registers (a struct of slices, or a helper returning the update's result,
/// measurably did not: 10 % slower on a random 1000² map).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn sweep<const ASTAR: bool>(
    pot: &mut [f32],
    cost: &[u8],
    blocked: &mut [u8],
    nx: usize,
    queued: &[i32],
    cur_t: f32,
    heuristic: Heuristic,
    out: &mut Outputs<'_>,
) {
    let ns = pot.len();
    if cost.len() != ns || blocked.len() != ns {
        return; // never: the three arrays have the map's size
    }
    for (i, &c) in queued.iter().enumerate() {
        if ASTAR && let Some(&ahead) = queued.get(i + PREFETCH_AHEAD) {
            prefetch_rows(pot, cost, blocked, nx, ahead as usize);
        }
        let n = c as usize;
        // Never true for a queued cell (its cost is < 254, so it is not on the border ring);
        // stating it lets the compiler drop the bounds checks of the neighbour reads. For the
        // same reason navfn.cpp's own obstacle test on the cell always holds.
        if n <= nx || n + nx >= ns {
            continue;
        }
        let l = pot[n - 1];
        let r = pot[n + 1];
        let u = pot[n - nx];
        let d = pot[n + nx];
        let tc = if l < r { l } else { r };
        let mut ta = if u < d { u } else { d };
        let hf = cost[n] as f32;
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
        let mut p = if ASTAR {
            // A* expands whole random maps, where which candidate applies is a coin toss and
            // a mispredicted branch also discards the loads of the following updates: both
            // are computed and one is selected. The unused candidate has no effect (no float
            // traps; 0/0 when `hf` is 0 only yields a NaN that is not selected). Dijkstra
            // keeps the branch: on the paper suite's maps it predicts well.
            std::hint::select_unpredictable(dc >= hf, ta + hf, quadratic())
        } else if dc >= hf {
            ta + hf
        } else {
            quadratic()
        };
        if p < pot[n] {
            let le = EDGE[cost[n - 1] as usize];
            let re = EDGE[cost[n + 1] as usize];
            let ue = EDGE[cost[n - nx] as usize];
            let de = EDGE[cost[n + nx] as usize];
            pot[n] = p;
            if ASTAR {
                let (x, y) = heuristic.width.col_row(n);
                p = p + astar_heuristic(x as i64 - heuristic.start_x, y as i64 - heuristic.start_y);
            }
            let (cand, near, edge) =
                ([n - 1, n + 1, n - nx, n + nx], [l, r, u, d], [le, re, ue, de]);
            if p < cur_t {
                push4(out.next, &mut out.next_len, blocked, cand, p, near, edge);
            } else {
                push4(out.over, &mut out.over_len, blocked, cand, p, near, edge);
            }
        }
    }
}

impl NavFn {
    /// `setupNavFn(keepit=true)`: reset potentials and gradients, force the border ring to 254,
    /// empty the buffers (no cell queued: `blocked` = obstacle), put the goal at potential 0
    /// and queue its four neighbours.
    pub fn setup(&mut self) {
        let (nx, ny, ns) = (self.nx, self.ny, self.ns);
        let goal = self.goal_index();
        let NavFn { pot, cost, blocked, grad, cur, next, over, .. } = self;
        let (pot, cost, blocked) = (&mut pot[..], &mut cost[..], &mut blocked[..]);
        pot.fill(POT_HIGH);
        grad.reset();
        cost[..nx].fill(COST_OBS);
        cost[(ny - 1) * nx..].fill(COST_OBS);
        for row in cost.chunks_exact_mut(nx) {
            row[0] = COST_OBS;
            row[nx - 1] = COST_OBS;
        }
        for (b, &c) in blocked.iter_mut().zip(cost.iter()) {
            *b = (c >= COST_OBS) as u8;
        }
        next.clear();
        over.clear();
        pot[goal] = 0.0;
        let mut len = 0;
        for n in [goal.wrapping_add(1), goal.wrapping_sub(1), goal.wrapping_sub(nx), goal + nx] {
            // the goal may sit on the border, so its neighbours need the range test
            if n < ns && blocked[n] == 0 {
                cur.cells[len] = n as i32;
                len += 1;
                blocked[n] = 1;
            }
        }
        cur.len = len;
        self.cur_t = CUR_T_INIT;
        self.last_path_cost = POT_HIGH;
    }

    /// The shared main loop. `stop_at_start` is `atStart` for Dijkstra and always true for A*.
    /// Returns the loop index at exit and why it exited.
    ///
    /// The three buffers' storage and lengths are locals for the whole loop, so that a
    /// rotation (next becomes current, overflow becomes current) swaps two references and two
    /// lengths in registers. Rotating the `PriorityBuf`s in memory stored the lengths and read
    /// them back within a wider load of the same cycle, a store-forwarding stall on every cycle
    /// (about a tenth of the time on the suite's small maps, where a case is ten cycles of
    /// three updates). `roles` remembers which storage plays which part.
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
        let NavFn { pot, cost, blocked, cur, next, over, nx, .. } = self;
        let (pot, cost, blocked, nx) = (&mut pot[..], &cost[..], &mut blocked[..], *nx);
        let (mut cur_cells, mut next_cells, mut over_cells) =
            (&mut *cur.cells, &mut *next.cells, &mut *over.cells);
        let (mut cur_len, mut next_len, mut over_len) = (cur.len, next.len, over.len);
        let mut roles = Roles::new();
        let mut cycle = 0;
        let mut end = PropagationEnd::CycleLimit;
        while cycle < cycles {
            obs.on_cycle(&CycleView {
                cycle,
                threshold: cur_t,
                current: queued(cur_cells, cur_len),
                next: queued(next_cells, next_len),
                overflow: queued(over_cells, over_len),
                potential: pot,
            });
            // (the upstream cancel hook every 5,000 cycles has no numeric effect)
            if cur_len == 0 && next_len == 0 {
                end = PropagationEnd::QueuesEmpty;
                break;
            }
            let current = queued(cur_cells, cur_len);
            // the current cells are no longer pending (queued cells are never obstacles)
            for &c in current {
                if let Some(b) = blocked.get_mut(c as usize) {
                    *b = 0;
                }
            }
            let mut out = Outputs { next: next_cells, next_len, over: over_cells, over_len };
            sweep::<ASTAR>(pot, cost, blocked, nx, current, cur_t, heuristic, &mut out);
            (next_cells, next_len, over_cells, over_len) =
                (out.next, out.next_len, out.over, out.over_len);
            // next becomes current; the old current storage becomes the empty next
            std::mem::swap(&mut cur_cells, &mut next_cells);
            (cur_len, next_len) = (next_len, 0);
            roles.swap(Role::Current, Role::Next);
            if cur_len == 0 {
                cur_t = cur_t + pri_inc;
                std::mem::swap(&mut cur_cells, &mut over_cells);
                (cur_len, over_len) = (over_len, 0);
                roles.swap(Role::Current, Role::Overflow);
            }
            if stop_at_start && pot[start_cell] < POT_HIGH {
                end = PropagationEnd::StartReached;
                break;
            }
            cycle += 1;
        }
        obs.on_propagation_end(&PropagationEndView {
            cycles: cycle,
            end,
            threshold: cur_t,
            current: queued(cur_cells, cur_len),
            next: queued(next_cells, next_len),
            overflow: queued(over_cells, over_len),
            potential: pot,
        });
        roles.put_back([cur, next, over], [cur_len, next_len, over_len]);
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
    use super::super::{Cell, NavFn, NoObserver};

    /// Propagation resumed one cycle per call (as a tracing driver steps navfn.cpp) must pick
    /// up the buffers where the last call left them: the potentials after every call and at
    /// the end equal one uninterrupted run, whatever order the buffers rotated in.
    #[test]
    fn resumed_propagation_continues_with_the_right_buffers() {
        let (nx, ny) = (23, 17);
        let costs: Vec<u8> = (0..nx * ny)
            .map(|i| match (i * 7919) % 31 {
                0 => 254,
                k => 50 + (k as u8) * 6,
            })
            .collect();
        // (A* is not resumable this way: each call adds the start–goal distance to the
        // threshold, in navfn.cpp as here; the rotation code is the same for both)
        let mut whole = NavFn::new(nx, ny).expect("size");
        let mut stepped = NavFn::new(nx, ny).expect("size");
        for nav in [&mut whole, &mut stepped] {
            nav.set_costs_raw(&costs).expect("size");
            nav.set_goal(Cell::new(3, 4)).expect("inside");
            nav.set_start(Cell::new(19, 13)).expect("inside");
            nav.setup();
        }
        whole.propagate_dijkstra(10_000, false, &mut NoObserver);
        let mut calls = 0;
        while !stepped.propagate_dijkstra(1, false, &mut NoObserver) {
            calls += 1;
        }
        assert!(calls > 20, "{calls} cycles");
        let bits = |n: &NavFn| n.potential().iter().map(|p| p.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&stepped), bits(&whole));
        assert!(whole.potential().iter().filter(|&&p| p < 1e10).count() > nx * ny / 2);
    }
}
