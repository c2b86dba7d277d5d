//! The benchmark behind `vouch navfn bench` (and `cargo bench -p vouch-navfn`): the paper
//! suite in µs per path, and the nav2 system-test pair on the 400×400 map in ms per plan,
//! next to the C++ figures of SEMANTICS.md §10. Single thread; the timed region holds only
//! the planning calls (array set-up, cost input, propagation, path extraction, and the world
//! conversion in planner mode), like the C++ measurement.

use std::io::Write;
use std::path::Path;
use std::time::Instant;

use crate::core::{Algo, Cell, NoObserver};
use crate::maps::{find_test_files, read_suite_file, SuiteFile};
use crate::planner::{NavfnPlanner, PlannerParams, WorldParams};
use crate::suite_run::{CaseRunner, CostInput, SuiteMode};

/// CPU time of this thread in seconds (`CLOCK_THREAD_CPUTIME_ID`), so the figures hold on a
/// loaded machine; `None` if the clock is unavailable (then wall time is used).
pub fn thread_cpu_seconds() -> Option<f64> {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: clock_gettime only writes the timespec we pass, which lives on our stack.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (rc == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

/// Wall and CPU seconds of `f`.
pub fn timed(f: impl FnOnce()) -> (f64, f64) {
    let c0 = thread_cpu_seconds();
    let t0 = Instant::now();
    f();
    let wall = t0.elapsed().as_secs_f64();
    let cpu = match (c0, thread_cpu_seconds()) {
        (Some(a), Some(b)) => b - a,
        _ => wall,
    };
    (wall, cpu)
}

fn best_mean(v: &[f64]) -> (f64, f64) {
    (v.iter().copied().fold(f64::INFINITY, f64::min), v.iter().sum::<f64>() / v.len().max(1) as f64)
}

/// Run the whole benchmark on `data` (the `shared/navfn` folder) and print a table.
pub fn run(
    data: &Path,
    repeat: usize,
    repeat_pair: usize,
    out: &mut dyn Write,
) -> Result<(), String> {
    let suite = data.join("suite");
    let files = find_test_files(&suite, "test.txt").map_err(|e| e.to_string())?;
    let loaded: Vec<SuiteFile> = files
        .iter()
        .map(|f| read_suite_file(f))
        .collect::<Result<_, _>>()
        .map_err(|e| e.to_string())?;
    let is_ros = |s: &SuiteFile| s.test_path.components().any(|c| c.as_os_str() == "ROS");
    let small: Vec<&SuiteFile> = loaded.iter().filter(|s| !is_ros(s)).collect();
    let all: Vec<&SuiteFile> = loaded.iter().collect();
    let w = |out: &mut dyn Write, s: String| out.write_all(s.as_bytes()).map_err(|e| e.to_string());
    w(
        out,
        format!(
            "vouch navfn bench: single thread, {repeat} repetitions; CPU time of the thread \
         (wall time in brackets, inflated when the machine is shared)\n"
        ),
    )?;
    w(
        out,
        format!(
            "{:<40} {:>8} {:>15} {:>15} {:>6}\n",
            "workload", "cases", "best µs/path", "mean µs/path", "C++"
        ),
    )?;
    let workloads: [(&str, &[&SuiteFile], SuiteMode, Algo, &str); 4] = [
        ("paper A*, whole suite (101 maps)", &all, SuiteMode::Paper, Algo::Astar, "-"),
        ("paper A*, 96 small maps", &small, SuiteMode::Paper, Algo::Astar, "1.18"),
        ("navfn Dijkstra, 96 small maps", &small, SuiteMode::Navfn, Algo::Dijkstra, "0.82"),
        ("navfn A*, 96 small maps", &small, SuiteMode::Navfn, Algo::Astar, "1.23"),
    ];
    for (label, set, mode, algo, cpp) in workloads {
        let mut runner = CaseRunner::new();
        // case parsing is outside the timed region, as in the C++ measurement
        let cells: Vec<Vec<(Cell, Cell)>> = set
            .iter()
            .map(|f| {
                f.cases
                    .iter()
                    .filter_map(|c| c.cells(f.width, f.height))
                    .map(|(a, b)| (Cell::new(a[0], a[1]), Cell::new(b[0], b[1])))
                    .collect()
            })
            .collect();
        let n: usize = cells.iter().map(Vec::len).sum();
        let (mut cpu, mut wall) = (Vec::new(), Vec::new());
        let mut sink = 0usize;
        for _ in 0..repeat.max(1) {
            let (wt, ct) = timed(|| {
                for (file, cases) in set.iter().zip(&cells) {
                    let (map, w, h) = (&file.map, file.width, file.height);
                    for &(from, to) in cases {
                        let o = match mode {
                            SuiteMode::Paper => {
                                runner.run_paper(map, w, h, from, to, &mut NoObserver)
                            }
                            _ => runner.run_navfn(
                                map,
                                w,
                                h,
                                CostInput::Raw,
                                algo,
                                from,
                                to,
                                &mut NoObserver,
                            ),
                        };
                        sink += o.map(|o| o.len).unwrap_or(0);
                    }
                }
            });
            wall.push(wt * 1e6 / n as f64);
            cpu.push(ct * 1e6 / n as f64);
        }
        std::hint::black_box(sink);
        let ((cb, cm), (wb, wm)) = (best_mean(&cpu), best_mean(&wall));
        w(
            out,
            format!(
                "{label:<40} {n:>8} {:>15} {:>15} {cpp:>6}\n",
                format!("{cb:.3} ({wb:.2})"),
                format!("{cm:.3} ({wm:.2})")
            ),
        )?;
    }
    // nav2_system_tests' default pair on the 400x400 map, full planner emulation
    let map_path = data.join("suite_ros/400x400_ros/map.bin");
    let bytes = std::fs::read(&map_path).map_err(|e| format!("{}: {e}", map_path.display()))?;
    if bytes.len() != 400 * 400 {
        return Err(format!("{} is not 400x400", map_path.display()));
    }
    w(
        out,
        format!(
            "{:<40} {:>8} {:>15} {:>15} {:>6}\n",
            "planner 400x400 (390,10)->(10,390)", "points", "best ms", "mean ms", "C++"
        ),
    )?;
    for (astar, cpp) in [(false, "4.5"), (true, "3.4")] {
        let params = PlannerParams { use_astar: astar, ..PlannerParams::default() };
        let mut planner =
            NavfnPlanner::new(bytes.clone(), 400, 400, WorldParams::default(), params)
                .map_err(|e| e.to_string())?;
        let (mut cpu, mut wall) = (Vec::new(), Vec::new());
        let mut points = 0;
        for _ in 0..repeat_pair.max(1) {
            let (wt, ct) =
                timed(|| points = planner.create_plan([390.0, 10.0], [10.0, 390.0]).navfn_len);
            wall.push(wt * 1e3);
            cpu.push(ct * 1e3);
        }
        let ((cb, cm), (wb, wm)) = (best_mean(&cpu), best_mean(&wall));
        let label = if astar { "  A*" } else { "  Dijkstra (atStart, nav2 default)" };
        w(
            out,
            format!(
                "{label:<40} {points:>8} {:>15} {:>15} {cpp:>6}\n",
                format!("{cb:.3} ({wb:.2})"),
                format!("{cm:.3} ({wm:.2})")
            ),
        )?;
    }
    Ok(())
}
