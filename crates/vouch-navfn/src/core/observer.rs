//! White-box observation of a NavFn search.
//!
//! The core is generic over `O: SearchObserver`; the default methods are empty and
//! `#[inline(always)]`, so with [`NoObserver`] the monomorphised search contains no trace
//! code at all (the views are built from values the loop already holds). The verification
//! campaign plugs in a recording observer to trace every propagation cycle.

/// State of the three priority buffers at the top of one propagation cycle, *before* the
/// "both current and next empty" exit test (so the exiting cycle is seen too) and before the
/// current buffer is processed (the paper's breakpoint, line 18 of its Algorithm 1).
pub struct CycleView<'a> {
    /// Cycle number, from 0.
    pub cycle: usize,
    /// Current threshold `curT` (float32, as NavFn holds it).
    pub threshold: f32,
    /// Cells of the current buffer, in processing order.
    pub current: &'a [i32],
    /// Cells of the next buffer (empty at the start of a cycle in NavFn's scheme, given for completeness).
    pub next: &'a [i32],
    /// Cells of the overflow buffer.
    pub overflow: &'a [i32],
    /// The whole potential array (row-major, `y*nx + x`).
    pub potential: &'a [f32],
}

/// How a propagation loop ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum PropagationEnd {
    /// The current and next buffers were both empty at the start of a cycle.
    QueuesEmpty,
    /// The start cell had a finite potential at the end of a cycle (`atStart` / A*).
    StartReached,
    /// The cycle limit was used up.
    CycleLimit,
}

/// Summary handed to [`SearchObserver::on_propagation_end`].
pub struct PropagationEndView<'a> {
    /// Number of cycles entered (the loop index at exit).
    pub cycles: usize,
    pub end: PropagationEnd,
    pub threshold: f32,
    /// The buffers as the loop leaves them (pushes of the last cycle included).
    pub current: &'a [i32],
    pub next: &'a [i32],
    pub overflow: &'a [i32],
    pub potential: &'a [f32],
}

/// Start of path extraction (`calcPath`).
pub struct PathStartView<'a> {
    /// NavFn start cell index (`y*nx + x`) the descent starts from.
    pub start_cell: usize,
    /// NavFn goal cell index.
    pub goal_cell: usize,
    /// Iteration limit `n` of `calcPath(n)`.
    pub max_iterations: usize,
    pub potential: &'a [f32],
}

/// Hooks called by the search. All default to no-ops that compile away.
pub trait SearchObserver {
    /// Called once per propagation cycle (see [`CycleView`]).
    #[inline(always)]
    fn on_cycle(&mut self, _view: &CycleView<'_>) {}
    /// Called once when the propagation loop exits.
    #[inline(always)]
    fn on_propagation_end(&mut self, _view: &PropagationEndView<'_>) {}
    /// Called once at the start of path extraction.
    #[inline(always)]
    fn on_path_start(&mut self, _view: &PathStartView<'_>) {}
    /// Called when path extraction detects an oscillation (`iteration` from 0; `point` is the
    /// point just recorded, equal to the one two positions earlier).
    #[inline(always)]
    fn on_path_oscillation(&mut self, _iteration: usize, _point: [f32; 2]) {}
}

/// The zero-cost observer used by the normal path.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoObserver;

impl SearchObserver for NoObserver {}

impl<O: SearchObserver + ?Sized> SearchObserver for &mut O {
    #[inline(always)]
    fn on_cycle(&mut self, view: &CycleView<'_>) {
        (**self).on_cycle(view)
    }
    #[inline(always)]
    fn on_propagation_end(&mut self, view: &PropagationEndView<'_>) {
        (**self).on_propagation_end(view)
    }
    #[inline(always)]
    fn on_path_start(&mut self, view: &PathStartView<'_>) {
        (**self).on_path_start(view)
    }
    #[inline(always)]
    fn on_path_oscillation(&mut self, iteration: usize, point: [f32; 2]) {
        (**self).on_path_oscillation(iteration, point)
    }
}
