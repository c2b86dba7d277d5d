//! The `vouch fpl validate | lint | check | graph` commands, here so the CLI file shared by the
//! fpl helpers only declares arguments. Each returns the process exit code (0 ok, 1 plan
//! rejected, 2 usage/IO error, 3 violations found) and prints its own output.

use std::path::{Path, PathBuf};

use crate::ast::FlightPlan;
use crate::evidence::validate::{self, Options};
use crate::front::{parse_file_with, Options as FrontOptions};

fn load(plan: &Path, include_dirs: Vec<PathBuf>) -> Result<FlightPlan, u8> {
    let opts = FrontOptions { search_dirs: include_dirs, ..Default::default() };
    parse_file_with(plan, &opts).map_err(|d| {
        eprint!("{}", d.render(false));
        if d.is_io() {
            2
        } else {
            1
        }
    })
}

fn lower(plan: &FlightPlan) -> Result<crate::passes::fp::Fp, u8> {
    crate::passes::compile(plan).map_err(|e| {
        eprint!("{}", e.to_diagnostics(plan).render(false));
        1u8
    })?;
    crate::passes::lower::lower(plan).map_err(|e| {
        eprint!("{}", e.to_diagnostics(plan).render(false));
        1u8
    })
}

fn json_out<T: serde::Serialize>(v: &T) -> u8 {
    match serde_json::to_string_pretty(v) {
        Ok(s) => {
            println!("{s}");
            0
        }
        Err(e) => {
            eprintln!("error: cannot serialise: {e}");
            2
        }
    }
}

pub fn validate_cmd(
    plan: &Path,
    include_dirs: Vec<PathBuf>,
    opts: &Options,
    json: bool,
    bounds: bool,
) -> u8 {
    let p = match load(plan, include_dirs) {
        Ok(p) => p,
        Err(c) => return c,
    };
    if let Err(c) = lower(&p) {
        return c;
    }
    let t0 = std::time::Instant::now();
    let rep = match validate::validate(&p, opts) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    let code = if rep.passed() { 0 } else { 3 };
    if json {
        let c = json_out(&rep);
        return if c != 0 { c } else { code };
    }
    println!(
        "{}: {} ({} states, {} call paths compared exhaustively over {} calls = {:.3e} complete runs, {} random calls, {:.2} s)",
        plan.display(),
        if rep.passed() { "C and semantics agree" } else { "MISMATCH" },
        rep.states,
        rep.call_paths,
        rep.depth,
        rep.runs_covered,
        rep.random_calls,
        t0.elapsed().as_secs_f64()
    );
    if let Some(c) = &rep.cut {
        println!("  exploration cut: {c} (the exhaustive part is incomplete)");
    }
    println!(
        "  bound per call: at most {} stages and {} external events (largest seen: {} events)",
        rep.bound.max_stages, rep.bound.max_events, rep.max_events_seen
    );
    if bounds {
        if let Ok(t) = wcet_lines(&p) {
            print!("{t}");
        }
    }
    if let Some(cx) = &rep.counterexample {
        println!("  {} after {} call(s)", cx.what, cx.calls);
        let a: Vec<String> = cx.answers.iter().map(|x| x.to_string()).collect();
        println!("  answers (replay with `vouch fpl sim --conditions FILE`): {}", a.join(" "));
        println!("  semantics:");
        for l in &cx.expected {
            println!("    {l}");
        }
        println!("  compiled C:");
        for l in &cx.actual {
            println!("    {l}");
        }
    }
    code
}

pub fn wcet_lines(p: &FlightPlan) -> Result<String, u8> {
    let fp = lower(p)?;
    let b = super::wcet::bound(&fp);
    let mut s = String::new();
    for bb in &b.blocks {
        s.push_str(&format!(
            "  {:>3} {:<30} stages <= {:>3}  events <= {:>4}\n",
            bb.block, bb.name, bb.stages, bb.events
        ));
    }
    Ok(s)
}

pub fn lint_cmd(plan: &Path, include_dirs: Vec<PathBuf>, json: bool, strict: bool) -> u8 {
    let p = match load(plan, include_dirs) {
        Ok(p) => p,
        Err(c) => return c,
    };
    let w = crate::lint::lint(&p);
    if json {
        let c = json_out(&w);
        if c != 0 {
            return c;
        }
    } else {
        print!("{}", crate::lint::render(&p, &w));
        let counts: Vec<String> = crate::lint::counts(&w)
            .into_iter()
            .filter(|c| c.1 > 0)
            .map(|(c, n)| format!("{c}: {n}"))
            .collect();
        println!(
            "{} warning(s){}{}",
            w.len(),
            if counts.is_empty() { "" } else { " — " },
            counts.join(", ")
        );
    }
    if strict && !w.is_empty() {
        3
    } else {
        0
    }
}

/// What `check` verifies.
#[derive(Debug, Clone, Default)]
pub struct CheckArgs {
    pub properties: Vec<String>,
    pub safe_blocks: Vec<String>,
    pub no_blocked: bool,
    pub deadlock_free: bool,
    pub max_states: usize,
    /// Model ground-station jumps to any block.
    pub operator: bool,
    pub json: bool,
}

pub fn check_cmd(plan: &Path, include_dirs: Vec<PathBuf>, a: &CheckArgs) -> u8 {
    use crate::model_check::{build, check};
    let p = match load(plan, include_dirs) {
        Ok(p) => p,
        Err(c) => return c,
    };
    let fp = match lower(&p) {
        Ok(f) => f,
        Err(c) => return c,
    };
    let g = match build(&fp, a.max_states, a.operator) {
        Ok(g) => g,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    let mut outcomes = Vec::new();
    for text in &a.properties {
        match check::check_text(&g, text) {
            Ok(o) => outcomes.push(o),
            Err(e) => {
                eprintln!("error: property: {e}");
                return 2;
            }
        }
    }
    if !a.safe_blocks.is_empty() {
        let mut ids = Vec::new();
        for n in &a.safe_blocks {
            match g.block_index(n) {
                Some(i) => ids.push(i),
                None => {
                    eprintln!("error: --safe-blocks: unknown block '{n}'");
                    return 2;
                }
            }
        }
        outcomes.push(check::check_safe_blocks(&g, &ids));
    }
    let defaults =
        a.properties.is_empty() && a.safe_blocks.is_empty() && !a.no_blocked && !a.deadlock_free;
    if a.no_blocked || defaults {
        outcomes.push(check::check_no_blocked(&g));
    }
    if a.deadlock_free || defaults {
        outcomes.push(check::check_deadlock_free(&g));
    }
    let failed = outcomes.iter().any(|o| !o.holds);
    if a.json {
        #[derive(serde::Serialize)]
        struct Out<'a> {
            states: usize,
            transitions: usize,
            cut: &'a Option<String>,
            outcomes: &'a [check::Outcome],
        }
        let t = g.edges.iter().map(|e| e.len()).sum();
        let c = json_out(&Out {
            states: g.states.len(),
            transitions: t,
            cut: &g.cut,
            outcomes: &outcomes,
        });
        if c != 0 {
            return c;
        }
    } else {
        println!(
            "{}: {} abstract states, {} transitions{}",
            plan.display(),
            g.states.len(),
            g.edges.iter().map(|e| e.len()).sum::<usize>(),
            g.cut.as_ref().map(|c| format!(" (cut: {c})")).unwrap_or_default()
        );
        for o in &outcomes {
            print!("{}", check::render(o));
        }
    }
    if failed {
        3
    } else {
        0
    }
}

pub fn graph_cmd(plan: &Path, include_dirs: Vec<PathBuf>, output: Option<&Path>) -> u8 {
    let p = match load(plan, include_dirs) {
        Ok(p) => p,
        Err(c) => return c,
    };
    let svg = crate::graph::render_svg(&p);
    match output {
        Some(o) => match std::fs::write(o, svg) {
            Ok(()) => 0,
            Err(e) => {
                eprintln!("error: cannot write {}: {e}", o.display());
                2
            }
        },
        None => {
            print!("{svg}");
            0
        }
    }
}
