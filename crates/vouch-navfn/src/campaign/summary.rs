//! The human summary of a campaign report: one row per category and a total row, then the
//! checks, relations, oracle and optimality figures.

use std::fmt::Write as _;

use crate::campaign::report::{CategoryStats, RATIO_BINS, Report};

fn pct(part: u64, whole: u64) -> String {
    if whole == 0 { "-".into() } else { format!("{:.2}%", 100.0 * part as f64 / whole as f64) }
}

/// The human summary: one row per category and a total row, then the checks.
pub fn summary_table(r: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<9} {:>5} {:>7} {:>7} {:>6} {:>6} {:>6} {:>6} {:>7} {:>8} {:>7} {:>7} {:>7} {:>7} {:>8}",
        "category",
        "maps",
        "cases",
        "found",
        "s=g",
        "unrch",
        "cyclim",
        "pfail",
        "checks",
        "relation",
        "excess%",
        "ratioMx",
        "obtuse",
        "oscill",
        "cpu_s"
    );
    let mut rows: Vec<(String, CategoryStats)> =
        r.categories.iter().map(|(k, v)| (k.clone(), v.clone())).collect();
    rows.push(("TOTAL".into(), r.total()));
    for (name, c) in &rows {
        category_row(&mut s, r, name, c);
    }
    let t = r.total();
    let _ = writeln!(s, "\nchecks (pass / fail):");
    for (k, v) in &t.checks {
        let _ = writeln!(s, "  {:<34} {:>9} / {}", k.to_string(), v.pass, v.fail);
    }
    if !t.metamorphic.is_empty() {
        let _ = writeln!(
            s,
            "metamorphic relations (held / violated; `approx_*` are findings, not failures):"
        );
        for (k, v) in &t.metamorphic {
            let _ = writeln!(s, "  {:<34} {:>9} / {}", k.to_string(), v.pass, v.fail);
        }
    }
    if t.oracle.pass + t.oracle.fail > 0 {
        let _ = writeln!(s, "oracle: {} equal, {} different", t.oracle.pass, t.oracle.fail);
    }
    optimality_lines(&mut s, &t);
    run_lines(&mut s, r);
    s
}

/// One row of the table: a category's (or the total's) outcomes, checks and optimality.
fn category_row(s: &mut String, r: &Report, name: &str, c: &CategoryStats) {
    let checks_fail = c.checks.values().map(|p| p.fail).fold(0, u64::saturating_add);
    let checks_all = c.checks.values().map(|p| p.pass.saturating_add(p.fail));
    let checks_all = checks_all.fold(0, u64::saturating_add);
    let rel_fail = c.metamorphic.iter().filter(|(r, _)| r.exact()).map(|(_, p)| p.fail);
    let rel_fail = rel_fail.fold(0, u64::saturating_add);
    let o = &c.optimality;
    let cpu: f64 = r
        .runs
        .iter()
        .filter_map(|run| match name {
            "TOTAL" => Some(run.cpu_seconds.values().sum::<f64>()),
            _ => run.cpu_seconds.get(name).copied(),
        })
        .sum();
    let _ = writeln!(
        s,
        "{:<9} {:>5} {:>7} {:>7} {:>6} {:>6} {:>6} {:>6} {:>7} {:>8} {:>7.2} {:>7.3} {:>7} {:>7} {:>8.3}",
        name,
        c.maps,
        c.cases,
        c.outcomes.found,
        c.outcomes.start_is_goal,
        c.outcomes.unreachable,
        c.outcomes.cycle_limit,
        c.outcomes.path_failed,
        if checks_fail == 0 {
            format!("ok{}", if checks_all == 0 { "?" } else { "" })
        } else {
            format!("{checks_fail}F")
        },
        if rel_fail == 0 { "ok".to_string() } else { format!("{rel_fail}F") },
        o.excess_percent(),
        o.ratio_max,
        pct(o.obtuse_paths, c.cases),
        pct(o.oscillating_paths, c.cases),
        cpu,
    );
}

/// The shards, threads and suite identity the report covers.
fn run_lines(s: &mut String, r: &Report) {
    let wall: f64 = r.runs.iter().map(|run| run.wall_seconds).fold(0.0, f64::max);
    let threads: Vec<usize> = r.runs.iter().map(|run| run.threads).collect();
    let sh = &r.shards;
    let _ = writeln!(
        s,
        "cases {}, shards {} of {} (split by {}), wall {:.2} s (slowest shard), threads {:?}",
        r.cases,
        sh.indices.len(),
        sh.count,
        sh.by.name(),
        wall,
        threads
    );
    let id = &r.suite;
    let content =
        id.content.as_deref().map_or("not all maps present", |c| c.get(..16).unwrap_or(c));
    let _ = writeln!(
        s,
        "suite: {} of {} maps, content {content}, vouch {}",
        id.maps.len(),
        id.maps_total,
        r.vouch_version
    );
}

/// The optimality figures of the total row and the ratio histogram.
fn optimality_lines(s: &mut String, t: &CategoryStats) {
    let o = &t.optimality;
    let _ = writeln!(
        s,
        "optimality: {} paths compared; obtuse turns in {} paths ({} of all cases; paper 1.91 %), oscillation in {} ({}; paper 0.13 %); {} paths above the counterexample ratio",
        o.compared,
        o.obtuse_paths,
        pct(o.obtuse_paths, t.cases),
        o.oscillating_paths,
        pct(o.oscillating_paths, t.cases),
        o.suboptimal_paths
    );
    if !o.ratio_hist.is_empty() {
        let mut line = String::from("  ratio navfn/optimal:");
        let mut lo = "0".to_string();
        for (i, n) in o.ratio_hist.iter().enumerate() {
            let hi = RATIO_BINS.get(i).map(|b| format!("{b}")).unwrap_or_else(|| "inf".into());
            let _ = write!(line, " [{lo},{hi}):{n}");
            lo = hi;
        }
        let _ = writeln!(s, "{line}");
        let _ =
            writeln!(s, "  excess navfn−optimal: min {:.1}, max {:.1}", o.excess_min, o.excess_max);
    }
}
