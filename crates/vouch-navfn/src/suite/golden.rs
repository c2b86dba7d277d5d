//! The golden line format of `shared/navfn/golden/README.md`: `CASE` + `PATH` lines (`WORLD` in
//! planner mode), float bit patterns, FNV-1a-64 hashes, and the runner of a whole suite file.

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
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
}

/// Append `printf("%.17g", v)`. Integral values below 10^15 (every cell coordinate) are
/// their decimal digits; the rest go through [`fmt_g17`].
pub fn push_g17(out: &mut String, v: f64) {
    if v.trunc() == v && v.abs() < 1e15 {
        if v == 0.0 && v.is_sign_negative() {
            out.push_str("-0");
        } else {
            out.push_str(itoa::Buffer::new().format(v as i64));
        }
    } else {
        out.push_str(&fmt_g17(v));
    }
}

fn push_uint(out: &mut String, v: usize) {
    out.push_str(itoa::Buffer::new().format(v));
}

const HEX_DIGITS: &[u8; 16] = b"0123456789abcdef";

/// Lower-case hex digits of the low `N/2` bytes of `v`, zero-padded to `N` digits.
#[inline]
fn hex<const N: usize>(v: u64) -> [u8; N] {
    let mut buf = [0u8; N];
    for (i, d) in buf.iter_mut().rev().enumerate() {
        *d = HEX_DIGITS[((v >> (4 * i)) & 0xf) as usize];
    }
    buf
}

/// Append ASCII bytes (the hex buffers above).
#[inline]
fn push_ascii(out: &mut String, bytes: &[u8]) {
    out.push_str(std::str::from_utf8(bytes).unwrap_or("?"));
}

/// Append `{:08x}` of float32 bits.
fn push_f32_bits(out: &mut String, v: f32) {
    push_ascii(out, &hex::<8>(v.to_bits() as u64));
}

/// Append `{:016x}`.
fn push_hex64(out: &mut String, v: u64) {
    push_ascii(out, &hex::<16>(v));
}

fn write_path_line(out: &mut String, tag: &str, path: &[[f32; 2]]) {
    out.reserve(tag.len() + 18 * path.len() + 1);
    out.push_str(tag);
    for p in path {
        let mut point = [b' '; 18];
        point[1..9].copy_from_slice(&hex::<8>(p[0].to_bits() as u64));
        point[9] = b':';
        point[10..].copy_from_slice(&hex::<8>(p[1].to_bits() as u64));
        push_ascii(out, &point);
    }
    out.push('\n');
}

/// `CASE k x0 y0 x1 y1`: the case number and the case as read.
fn push_case_head(out: &mut String, case: &SuiteCase) {
    out.push_str("CASE ");
    push_uint(out, case.number);
    for c in case.coords {
        out.push(' ');
        push_g17(out, c);
    }
}

fn push_cell(out: &mut String, key: &str, c: Option<Cell>) {
    out.push_str(key);
    match c {
        Some(c) => {
            push_uint(out, c.x);
            out.push(',');
            push_uint(out, c.y);
        }
        None => out.push('-'),
    }
}

/// ` last_path_cost=… pot_fnv=… path_fnv=…`
fn push_costs_and_hashes(
    out: &mut String,
    last_path_cost: Option<f32>,
    nav: &NavFn,
    path: &[[f32; 2]],
) {
    out.push_str(" last_path_cost=");
    match last_path_cost {
        Some(c) => push_f32_bits(out, c),
        None => out.push_str("na"),
    }
    out.push_str(" pot_fnv=");
    push_hex64(out, potential_fnv(nav.potential()));
    out.push_str(" path_fnv=");
    push_hex64(out, path_fnv(path));
}

/// Append the CASE and PATH lines of one cell-level case.
pub fn write_cell_case(out: &mut String, case: &SuiteCase, o: &CaseOutcome, nav: &NavFn) {
    push_case_head(out, case);
    push_cell(out, " navfn_start=", Some(o.navfn_start));
    push_cell(out, " navfn_goal=", Some(o.navfn_goal));
    out.push_str(if o.prop { " prop=1 len=" } else { " prop=0 len=" });
    push_uint(out, o.len);
    push_costs_and_hashes(out, o.last_path_cost, nav, nav.path());
    out.push('\n');
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
    let path = if plan.navfn_len > 0 { nav.path() } else { &[] };
    push_case_head(out, case);
    push_cell(out, " navfn_start=", plan.navfn_start);
    push_cell(out, " navfn_goal=", plan.navfn_goal);
    out.push_str(" prop=- len=");
    push_uint(out, plan.navfn_len);
    push_costs_and_hashes(out, plan.last_path_cost, nav, path);
    out.push_str(" status=");
    out.push_str(plan.status.name());
    out.push_str(if plan.tol_used { " tol_used=1 best=" } else { " tol_used=0 best=" });
    match plan.best {
        Some(b) => {
            push_hex64(out, b[0].to_bits());
            out.push(',');
            push_hex64(out, b[1].to_bits());
        }
        None => out.push('-'),
    }
    out.push('\n');
    write_path_line(out, "PATH", path);
    out.push_str("WORLD");
    for p in &plan.world {
        out.push(' ');
        push_hex64(out, p[0].to_bits());
        out.push(':');
        push_hex64(out, p[1].to_bits());
    }
    out.push('\n');
}
