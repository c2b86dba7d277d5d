//! Running one case with the campaign's observer: the search-trace properties are checked while
//! NavFn runs (through the core's zero-cost `SearchObserver` hook), and the per-cycle trace is
//! recorded when asked for.

use crate::campaign::grid::{Case, OBSTACLE, SuiteMap};
use crate::campaign::names::Property;
use crate::campaign::trace::{Trace, TraceDetail, TraceRecorder};
use crate::checks::{PlanView, Violation as PlanViolation, check_plan};
use crate::core::{
    Cell, CycleView, NavFn, POT_HIGH, PathStartView, PropagationEnd, PropagationEndView,
    SearchObserver,
};
use crate::suite::{CaseError, CaseOutcome, CaseRunner, CostInput, MapRef, RunMode};

/// First violation of a search-trace property.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Violation {
    /// The property.
    pub property: Property,
    /// What was seen.
    pub detail: String,
}

/// The observer of one case: property checks, optional trace.
pub struct CaseObserver<'a> {
    /// NavFn costs as set-up leaves them (border ring 254).
    costs: &'a [u8],
    pub violations: Vec<Violation>,
    pub trace: Option<TraceRecorder>,
    pub end: Option<(PropagationEnd, usize)>,
    /// Potential of the NavFn start cell when path extraction began.
    pub pot_at_path_start: Option<f32>,
    /// Largest total buffer occupancy seen (the paper's 10,000 capacity is never approached).
    pub max_occupancy: usize,
}

impl<'a> CaseObserver<'a> {
    pub fn new(costs: &'a [u8], trace: Option<TraceDetail>) -> Self {
        CaseObserver {
            costs,
            violations: Vec::new(),
            trace: trace.map(TraceRecorder::new),
            end: None,
            pot_at_path_start: None,
            max_occupancy: 0,
        }
    }

    fn check_buffer(&mut self, cycle: usize, name: &str, cells: &[i32]) {
        if !self.violations.is_empty() {
            return; // the first violation is enough; keep the hot loop cheap
        }
        for &c in cells {
            let bad = usize::try_from(c)
                .ok()
                .and_then(|i| self.costs.get(i))
                .is_none_or(|&cost| cost >= OBSTACLE);
            if bad {
                self.violations.push(Violation {
                    property: Property::ObstacleFreeQueues,
                    detail: format!("cycle {cycle}: {name} buffer holds cell {c} of cost ≥ 254"),
                });
                return;
            }
        }
    }
}

impl SearchObserver for CaseObserver<'_> {
    fn on_cycle(&mut self, v: &CycleView<'_>) {
        self.max_occupancy =
            self.max_occupancy.max(v.current.len() + v.next.len() + v.overflow.len());
        self.check_buffer(v.cycle, "current", v.current);
        self.check_buffer(v.cycle, "next", v.next);
        self.check_buffer(v.cycle, "overflow", v.overflow);
        if let Some(t) = &mut self.trace {
            t.on_cycle(v);
        }
    }
    fn on_propagation_end(&mut self, v: &PropagationEndView<'_>) {
        self.end = Some((v.end, v.cycles));
        // Pushes of the last cycle are only visible here.
        self.check_buffer(v.cycles, "current (final)", v.current);
        self.check_buffer(v.cycles, "next (final)", v.next);
        self.check_buffer(v.cycles, "overflow (final)", v.overflow);
        if let Some(t) = &mut self.trace {
            t.on_propagation_end(v);
        }
    }
    fn on_path_start(&mut self, v: &PathStartView<'_>) {
        self.pot_at_path_start = v.potential.get(v.start_cell).copied();
    }
}

/// Everything the campaign keeps of one run.
#[derive(Clone, Debug)]
pub struct CaseRun {
    pub outcome: CaseOutcome,
    /// How propagation ended and after how many cycles.
    pub end: Option<(PropagationEnd, usize)>,
    pub violations: Vec<Violation>,
    pub trace: Option<Trace>,
    pub max_occupancy: usize,
}

/// NavFn start and goal of a case in `mode` (the planner sequence swaps them).
pub fn navfn_ends(mode: RunMode, c: &Case) -> (Cell, Cell) {
    let from = Cell::new(c.x0 as usize, c.y0 as usize);
    let to = Cell::new(c.x1 as usize, c.y1 as usize);
    match mode {
        RunMode::Paper => (from, to),
        _ => (to, from),
    }
}

/// Run one case of `m` on `runner`. `set_up_costs` must be `m.costs` with the border stamped.
pub fn run_case(
    runner: &mut CaseRunner,
    m: &SuiteMap,
    set_up_costs: &[u8],
    case: &Case,
    mode: RunMode,
    trace: Option<TraceDetail>,
) -> Result<CaseRun, CaseError> {
    let mut obs = CaseObserver::new(set_up_costs, trace);
    let (w, h) = (m.width as usize, m.height as usize);
    let from = Cell::new(case.x0 as usize, case.y0 as usize);
    let to = Cell::new(case.x1 as usize, case.y1 as usize);
    let map = MapRef { bytes: &m.costs, nx: w, ny: h, costs: CostInput::Raw };
    let outcome = runner.run(mode, map, from, to, &mut obs)?;
    let mut violations = std::mem::take(&mut obs.violations);
    // No path without finite potential (the paper's (¬PathComputed) W NonInfinitePotAtInit):
    // a non-empty path implies the start potential was finite when extraction began.
    if outcome.len > 0 && !obs.pot_at_path_start.is_some_and(|p| p < POT_HIGH) {
        violations.push(Violation {
            property: Property::NoPathWithoutFinitePotential,
            detail: format!(
                "path of {} points from a start of potential {:?}",
                outcome.len, obs.pot_at_path_start
            ),
        });
    }
    Ok(CaseRun {
        outcome,
        end: obs.end,
        violations,
        trace: obs.trace.map(|t| t.trace),
        max_occupancy: obs.max_occupancy,
    })
}

fn plan_check_property(v: &PlanViolation) -> Property {
    match v {
        PlanViolation::PoseInObstacle { .. } => Property::ValidPath,
        PlanViolation::PoseOnUnreachedCell { .. } => Property::FinitePotentialPath,
        PlanViolation::PotentialOnObstacle { .. } | PlanViolation::SizeMismatch { .. } => {
            Property::PositionSafe
        }
        PlanViolation::NoProgress { .. } => Property::Progress,
        PlanViolation::WrongFirstPoint { .. } | PlanViolation::WrongLastPoint { .. } => {
            Property::PathEndPoints
        }
    }
}

/// The core's run-time plan checks (the paper's Dafny properties `ValidPath`,
/// `FinitePotentialPath`, `PositionSafe`, `Progress`, plus the end points) on the last plan of
/// `nav`, as campaign violations (one per property, the first of each).
pub fn plan_checks(nav: &NavFn) -> Vec<Violation> {
    let report = check_plan(&PlanView::of(nav));
    let mut out: Vec<Violation> = Vec::new();
    for v in &report.violations {
        let property = plan_check_property(v);
        if !out.iter().any(|o| o.property == property) {
            out.push(Violation { property, detail: v.to_string() });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn obstacle_in_any_buffer_is_reported_once() {
        let costs = [254u8, 50, 50, 254, 50];
        let pot = [0.0f32; 5];
        let mut obs = CaseObserver::new(&costs, None);
        let clean = CycleView {
            cycle: 0,
            threshold: 254.0,
            current: &[1, 2],
            next: &[],
            overflow: &[4],
            potential: &pot,
        };
        obs.on_cycle(&clean);
        assert!(obs.violations.is_empty());
        let dirty = CycleView {
            cycle: 3,
            threshold: 354.0,
            current: &[1],
            next: &[],
            overflow: &[3],
            potential: &pot,
        };
        obs.on_cycle(&dirty);
        obs.on_cycle(&dirty);
        assert_eq!(obs.violations.len(), 1);
        assert_eq!(obs.violations[0].property, Property::ObstacleFreeQueues);
        assert!(
            obs.violations[0].detail.contains("cycle 3")
                && obs.violations[0].detail.contains("overflow")
        );
        assert_eq!(obs.max_occupancy, 3);
    }

    #[test]
    fn pushes_of_the_last_cycle_are_checked_at_loop_exit() {
        let costs = [50u8, 254];
        let pot = [0.0f32; 2];
        let mut obs = CaseObserver::new(&costs, None);
        obs.on_propagation_end(&PropagationEndView {
            cycles: 7,
            end: PropagationEnd::StartReached,
            threshold: 254.0,
            current: &[],
            next: &[1],
            overflow: &[],
            potential: &pot,
        });
        assert_eq!(obs.violations.len(), 1);
        assert!(obs.violations[0].detail.contains("next (final)"));
        // Out-of-range indices are violations too, never a panic.
        let mut obs = CaseObserver::new(&costs, None);
        let v = CycleView {
            cycle: 0,
            threshold: 0.0,
            current: &[-1],
            next: &[],
            overflow: &[],
            potential: &pot,
        };
        obs.on_cycle(&v);
        assert_eq!(obs.violations.len(), 1);
    }
}
