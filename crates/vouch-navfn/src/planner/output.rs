//! Golden-format lines of a planner-mode case (`CASE … status= tol_used= best=`, `PATH`, `WORLD`).

use std::fmt::Write as _;

use super::PlannerPlan;
use crate::core::numeric::{path_fnv, potential_fnv};
use crate::core::NavFn;
use crate::maps::SuiteCase;
use crate::suite_run::fmt_g17;

/// Append the three lines of one planner-mode case. `nav` is the planner's NavFn after the plan.
pub fn write_planner_case(out: &mut String, case: &SuiteCase, plan: &PlannerPlan, nav: &NavFn) {
    let [x0, y0, x1, y1] = case.coords.map(fmt_g17);
    let cell = |c: Option<crate::core::Cell>| match c {
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
    out.push_str("PATH");
    for p in path {
        let _ = write!(out, " {:08x}:{:08x}", p[0].to_bits(), p[1].to_bits());
    }
    out.push_str("\nWORLD");
    for p in &plan.world {
        let _ = write!(out, " {:016x}:{:016x}", p[0].to_bits(), p[1].to_bits());
    }
    out.push('\n');
}
