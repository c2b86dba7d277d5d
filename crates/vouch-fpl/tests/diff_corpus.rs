//! Differential test: for every corpus plan, the compiled `auto_nav()` (instrumented header,
//! built with `cc -std=c99 -Wall -Wextra -Werror` against the project's stub runtime in
//! `tests/stub`) and the reference interpreter, driven by the same condition-answer sequences,
//! must print identical traces and block/stage states for 200 calls under several seeds.
//! Building the drivers is also the check that every generated header compiles.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use rayon::prelude::*;
use vouch_fpl::emit::{EmitOptions, Flavor, compile_plan};
use vouch_fpl::semantics::Interp;
use vouch_fpl::semantics::oracle::{Scripted, seeded_sequence};

const STEPS: usize = 200;
/// (seed, percent of true conditions): rare exceptions, balanced, mostly true.
const SEEDS: [(u64, u64); 4] = [(1, 10), (2, 30), (3, 50), (4, 80)];

fn cc() -> String {
    std::env::var("CC").unwrap_or_else(|_| "cc".to_string())
}

/// Builds the stub driver for one instrumented header; returns the executable or cc's errors.
pub fn build_driver(header: &str, work: &Path) -> Result<PathBuf, String> {
    std::fs::create_dir_all(work).map_err(|e| e.to_string())?;
    std::fs::write(work.join("flight_plan.h"), header).map_err(|e| e.to_string())?;
    let stub = common::stub_dir();
    let exe = work.join("driver");
    let out = Command::new(cc())
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-O0"])
        .arg("-I")
        .arg(stub.join("include"))
        .arg("-I")
        .arg(work)
        .arg(stub.join("fp_stub.c"))
        .arg(stub.join("driver.c"))
        .arg("-o")
        .arg(&exe)
        .output()
        .map_err(|e| format!("cannot run cc: {e}"))?;
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).chars().take(3000).collect());
    }
    Ok(exe)
}

fn first_difference(a: &str, b: &str) -> String {
    for (i, (la, lb)) in a.lines().zip(b.lines()).enumerate() {
        if la != lb {
            let ctx: Vec<&str> = a.lines().take(i + 1).skip(i.saturating_sub(6)).collect();
            return format!(
                "line {}: C `{la}` vs interpreter `{lb}`\ncontext (C):\n{}",
                i + 1,
                ctx.join("\n")
            );
        }
    }
    format!(
        "lengths differ: C {} lines, interpreter {} lines",
        a.lines().count(),
        b.lines().count()
    )
}

fn check_plan(idx: usize, path: &Path, tmp: &Path) -> Result<(), String> {
    let plan = vouch_fpl::front::parse_file(path).map_err(|d| d.to_string())?;
    let opts = EmitOptions {
        source_path: path.display().to_string(),
        flavor: Flavor::Instrumented,
        ..Default::default()
    };
    let header = compile_plan(&plan, &opts).map_err(|e| e.to_string())?;
    let work = tmp.join(format!("plan{idx}"));
    let exe = build_driver(&header, &work)?;
    let fp = vouch_fpl::passes::lower::lower(&plan).map_err(|e| e.to_string())?;
    for (seed, pct) in SEEDS {
        let seq = seeded_sequence(seed, 20 * STEPS, pct);
        let seq_file = work.join(format!("answers_{seed}.txt"));
        let text: Vec<String> = seq.iter().map(i64::to_string).collect();
        std::fs::write(&seq_file, text.join(" ")).map_err(|e| e.to_string())?;
        // Operator block changes every 13 calls, to a block chosen from the seed, so that every
        // block is exercised even when the plan would settle in HOME.
        let nb = fp.blocks.len();
        let jumps: Vec<(usize, usize)> =
            (1..STEPS).step_by(13).map(|c| (c + 1, (c * 7 + seed as usize * 3) % nb)).collect();
        let jumps_file = work.join(format!("jumps_{seed}.txt"));
        let jt: Vec<String> = jumps.iter().map(|(c, b)| format!("{c} {b}")).collect();
        std::fs::write(&jumps_file, jt.join("\n")).map_err(|e| e.to_string())?;
        let out = Command::new(&exe)
            .arg(&seq_file)
            .arg(STEPS.to_string())
            .arg(&jumps_file)
            .output()
            .map_err(|e| e.to_string())?;
        if !out.status.success() {
            return Err(format!("driver failed: {}", String::from_utf8_lossy(&out.stderr)));
        }
        let c_trace = String::from_utf8_lossy(&out.stdout).into_owned();
        let mut interp = Interp::new(&fp);
        let run = interp
            .run_with_jumps(&mut Scripted::new(seq), STEPS, &jumps)
            .map_err(|e| format!("interpreter: {e:?}"))?;
        let i_trace = run.to_text();
        if c_trace != i_trace {
            return Err(format!("seed {seed}: {}", first_difference(&c_trace, &i_trace)));
        }
    }
    Ok(())
}

#[test]
fn compiled_auto_nav_matches_the_interpreter_on_every_corpus_plan() {
    let Some(dir) = common::corpus_dir() else { return };
    if common::c_compiler().is_none() {
        return;
    }
    let plans = common::corpus_plans(&dir);
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR")).join("diff_corpus");
    let failures: Vec<String> = plans
        .par_iter()
        .enumerate()
        .filter_map(|(i, p)| check_plan(i, p, &tmp).err().map(|e| format!("{}: {e}", p.display())))
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} plans differ or fail:\n{}",
        failures.len(),
        plans.len(),
        failures.join("\n\n")
    );
}

#[test]
fn demo_plan_matches_the_interpreter() {
    if common::c_compiler().is_none() {
        return;
    }
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fpl/demo.xml");
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR")).join("diff_demo");
    check_plan(0, &p, &tmp).unwrap();
}
