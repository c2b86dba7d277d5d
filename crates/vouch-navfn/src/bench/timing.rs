//! vouch's own measurements: its side of the contract's timing extension (the planning calls
//! of every case of a test file, best of R repetitions, thread CPU time) and one planner
//! request on a ROS map (vouch only: the contract has no planner mode).

use std::path::Path;
use std::time::Instant;

use cpu_time::ThreadTime;

use super::side::{TimeLine, peak_rss_kb};
use super::{BenchError, Row, Unit};
use crate::core::{Cell, NoObserver, POT_HIGH};
use crate::maps::{SuiteFile, find_test_files, load_ros_map, read_suite_file};
use crate::planner::{NavfnPlanner, PlannerParams};
use crate::suite::{CaseRunner, CostInput, MapRef, RunMode};

/// Thread CPU time of `f` (wall time where the clock is unavailable), seconds.
pub(crate) fn cpu_seconds(f: impl FnOnce()) -> f64 {
    let c0 = ThreadTime::try_now().ok();
    let t0 = Instant::now();
    f();
    let wall = t0.elapsed().as_secs_f64();
    c0.and_then(|c| c.try_elapsed().ok()).map_or(wall, |d| d.as_secs_f64())
}

/// One `TIME` line per test file below `target` (the contract's timing extension).
pub fn time_planning(
    target: &Path,
    mode: RunMode,
    reps: usize,
) -> Result<Vec<TimeLine>, BenchError> {
    let start_rss_kb = peak_rss_kb();
    let mut lines = Vec::new();
    for f in find_test_files(target, "test.txt")? {
        let file = read_suite_file(&f)?;
        let mut t = time_file(&file, mode, reps.max(1));
        t.maxrss_kb = peak_rss_kb();
        t.start_rss_kb = Some(start_rss_kb);
        lines.push(t);
    }
    Ok(lines)
}

/// The cases of a file as cells (parsing stays outside the timed region).
fn case_cells(file: &SuiteFile) -> Vec<(Cell, Cell)> {
    file.cases
        .iter()
        .filter_map(|c| c.cells(file.width, file.height))
        .map(|(a, b)| (Cell::new(a[0], a[1]), Cell::new(b[0], b[1])))
        .collect()
}

/// Best and summed thread CPU time of `reps` repetitions of every case's planning calls, then
/// (untimed, same arrays) the cells each case gives a finite potential.
fn time_file(file: &SuiteFile, mode: RunMode, reps: usize) -> TimeLine {
    let cells = case_cells(file);
    let map = MapRef { bytes: &file.map, nx: file.width, ny: file.height, costs: CostInput::Raw };
    let mut runner = CaseRunner::new();
    let (mut best, mut sum, mut found) = (f64::INFINITY, 0.0, 0);
    for _ in 0..reps {
        let mut n = 0;
        let secs = cpu_seconds(|| {
            for &(from, to) in &cells {
                let o = runner.run(mode, map, from, to, &mut NoObserver);
                n += o.is_ok_and(|o| o.len > 0) as u64;
            }
        });
        best = f64::min(best, secs * 1e9);
        sum += secs * 1e9;
        found = n;
    }
    let explored = cells
        .iter()
        .map(|&(from, to)| {
            let _ = runner.run(mode, map, from, to, &mut NoObserver);
            runner.nav().potential().iter().filter(|&&p| p < POT_HIGH).count() as u64
        })
        .sum();
    TimeLine {
        cases: cells.len() as u64,
        reps: reps as u64,
        best_ns: best,
        sum_ns: sum,
        found,
        explored: Some(explored),
        ..TimeLine::default()
    }
}

/// One planner request on a ROS map, Dijkstra and A*, `repeat` times each (vouch only).
pub fn planner_rows(
    map: &Path,
    start: [f64; 2],
    goal: [f64; 2],
    repeat: usize,
) -> Result<Vec<Row>, BenchError> {
    let map = load_ros_map(map, true)?;
    let mut rows = Vec::new();
    for astar in [false, true] {
        let params = PlannerParams { use_astar: astar, ..PlannerParams::default() };
        let mut planner =
            NavfnPlanner::new(&map.costmap, map.width, map.height, map.world(), params)?;
        planner.plan_checked(start, goal)?;
        let mut points = 0;
        let mut samples = Vec::new();
        for _ in 0..repeat.max(1) {
            let secs = cpu_seconds(|| points = planner.create_plan(start, goal).navfn_len);
            samples.push(secs * 1e3);
        }
        let algo = if astar { "A*" } else { "Dijkstra" };
        let mut row = Row::new(
            format!("planner {algo} ({}x{}, {points} points)", map.width, map.height),
            1,
            Unit::MsPerPlan,
        );
        row.vouch = samples;
        rows.push(row);
    }
    Ok(rows)
}
