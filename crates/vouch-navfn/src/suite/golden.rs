//! The golden line format of `shared/navfn/golden/README.md`: `CASE` + `PATH` lines (`WORLD` in
//! planner mode), float bit patterns, FNV-1a-64 hashes, and the runner of a whole suite file.

use std::fmt::Write as _;

use super::{CaseError, CaseOutcome, CaseRunner, RunMode, SuiteMode, SuiteOptions};
use crate::core::numeric::{path_fnv, potential_fnv};
use crate::core::{Algo, Cell, NavFn};
use crate::maps::{SuiteCase, SuiteFile};
use crate::planner::{NavfnPlanner, PlanStatus, PlannerParams, PlannerPlan};

/// C's `printf("%.17g", v)` (used for the case coordinates of the CASE line).
pub fn fmt_g17(v: f64) -> String {
    if v == 0.0 {
        return if v.is_sign_negative() { "-0".into() } else { "0".into() };
    }
    if !v.is_finite() {
        return if v.is_nan() {
            "nan".into()
        } else if v > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        };
    }
    // the exponent after rounding to 17 significant digits decides between the two styles
    let sci = format!("{:.16e}", v);
    let (mant, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if (-4..17).contains(&exp) {
        let decimals = (16 - exp) as usize;
        strip_zeros(format!("{:.*}", decimals, v))
    } else {
        let m = strip_zeros(mant.to_string());
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{m}e{sign}{:02}", exp.abs())
    }
}

fn strip_zeros(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn write_path_line(out: &mut String, tag: &str, path: &[[f32; 2]]) {
    out.push_str(tag);
    for p in path {
        let _ = write!(out, " {:08x}:{:08x}", p[0].to_bits(), p[1].to_bits());
    }
    out.push('\n');
}

/// Append the CASE and PATH lines of one cell-level case.
pub fn write_cell_case(out: &mut String, case: &SuiteCase, o: &CaseOutcome, nav: &NavFn) {
    let [x0, y0, x1, y1] = case.coords.map(fmt_g17);
    let lpc = match o.last_path_cost {
        Some(c) => format!("{:08x}", c.to_bits()),
        None => "na".to_string(),
    };
    let _ = writeln!(
        out,
        "CASE {} {x0} {y0} {x1} {y1} navfn_start={},{} navfn_goal={},{} prop={} len={} last_path_cost={lpc} pot_fnv={:016x} path_fnv={:016x}",
        case.number,
        o.navfn_start.x,
        o.navfn_start.y,
        o.navfn_goal.x,
        o.navfn_goal.y,
        o.prop as u8,
        o.len,
        potential_fnv(nav.potential()),
        path_fnv(nav.path()),
    );
    write_path_line(out, "PATH", nav.path());
}

/// Counters of one run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunStats {
    /// Cases run.
    pub cases: usize,
    /// Cases with a non-empty path.
    pub found: usize,
}

/// Run every case of `file` and append the golden-format lines to `out`.
pub fn run_file(
    file: &SuiteFile,
    opts: &SuiteOptions,
    out: &mut String,
) -> Result<RunStats, CaseError> {
    let mut stats = RunStats::default();
    match opts.mode {
        SuiteMode::Planner => {
            let mut planner = NavfnPlanner::new(
                &file.map,
                file.width,
                file.height,
                opts.world,
                PlannerParams { use_astar: opts.algo == Algo::Astar, ..PlannerParams::default() },
            )?;
            for case in &file.cases {
                let [x0, y0, x1, y1] = case.coords;
                let plan = planner.create_plan([x0, y0], [x1, y1]);
                stats.cases += 1;
                stats.found += (plan.status == PlanStatus::Ok) as usize;
                write_planner_case(out, case, &plan, planner.nav());
            }
        }
        mode => {
            let mut runner = CaseRunner::new();
            let run_mode = RunMode::new(mode, opts.algo).unwrap_or(RunMode::Paper);
            let mut obs = crate::core::NoObserver;
            for case in &file.cases {
                let o = runner.run_case(file, case, run_mode, opts.costs, &mut obs)?;
                stats.cases += 1;
                stats.found += (o.len > 0) as usize;
                write_cell_case(out, case, &o, runner.nav());
            }
        }
    }
    Ok(stats)
}

/// Append the three lines of one planner-mode case. `nav` is the planner's NavFn after the plan.
pub fn write_planner_case(out: &mut String, case: &SuiteCase, plan: &PlannerPlan, nav: &NavFn) {
    let [x0, y0, x1, y1] = case.coords.map(fmt_g17);
    let cell = |c: Option<Cell>| match c {
        Some(c) => format!("{},{}", c.x, c.y),
        None => "-".to_string(),
    };
    let lpc = match plan.last_path_cost {
        Some(c) => format!("{:08x}", c.to_bits()),
        None => "na".to_string(),
    };
    let path = if plan.navfn_len > 0 { nav.path() } else { &[] };
    let best = match plan.best {
        Some(b) => format!("{:016x},{:016x}", b[0].to_bits(), b[1].to_bits()),
        None => "-".to_string(),
    };
    let _ = writeln!(
        out,
        "CASE {} {x0} {y0} {x1} {y1} navfn_start={} navfn_goal={} prop=- len={} last_path_cost={lpc} pot_fnv={:016x} path_fnv={:016x} status={} tol_used={} best={best}",
        case.number,
        cell(plan.navfn_start),
        cell(plan.navfn_goal),
        plan.navfn_len,
        potential_fnv(nav.potential()),
        path_fnv(path),
        plan.status.name(),
        plan.tol_used as u8,
    );
    write_path_line(out, "PATH", path);
    out.push_str("WORLD");
    for p in &plan.world {
        let _ = write!(out, " {:016x}:{:016x}", p[0].to_bits(), p[1].to_bits());
    }
    out.push('\n');
}
