//! Every generated header compiles: the *drop-in* header (not the instrumented test
//! flavour) of every corpus plan upstream compiles, and of the demo, is built with
//! `cc -std=c99 -Wall -Wextra -Werror -O2` against the project's stub runtime (`tests/stub/`),
//! the no-op navigation API and the module environment the plans' own C texts name
//! (`tests/stub/env/`), linked with a driver that calls `auto_nav_init()` then `auto_nav()`
//! five times, and run. `-O2` is Paparazzi's optimisation level; it matters for two corpus plans
//! whose `<header>` defines C99 `inline` functions without an external definition.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use rayon::prelude::*;
use vouch_fpl::emit::EmitOptions;
use vouch_fpl::pipeline::compile_file;

/// Builds and runs the drop-in header of `plan` in `work`; the driver's output on success.
fn build_and_run(cc: &str, plan: &Path, work: &Path) -> Result<String, String> {
    let header = compile_file(plan, &EmitOptions::default())
        .map_err(|e| format!("compile: {}", e.listing()))?;
    std::fs::create_dir_all(work).map_err(|e| e.to_string())?;
    std::fs::write(work.join("flight_plan.h"), &header).map_err(|e| e.to_string())?;
    let stub = common::stub_dir();
    let exe = work.join("dropin");
    let out = Command::new(cc)
        .args(["-std=c99", "-Wall", "-Wextra", "-Werror", "-O2"])
        .arg("-I")
        .arg(stub.join("include"))
        .arg("-I")
        .arg(stub.join("env"))
        .arg("-I")
        .arg(work)
        // Every translation unit sees the modules' names, as in a Paparazzi build.
        .args(["-include", "paparazzi_env.h"])
        .arg(stub.join("fp_stub.c"))
        .arg(stub.join("nav_api_stub.c"))
        .arg(stub.join("env/paparazzi_env.c"))
        .arg(stub.join("env/dropin_main.c"))
        .arg("-o")
        .arg(&exe)
        .arg("-lm")
        .output()
        .map_err(|e| format!("cannot run {cc}: {e}"))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!("cc failed:\n{}", err.lines().take(12).collect::<Vec<_>>().join("\n")));
    }
    let run = Command::new(&exe).output().map_err(|e| e.to_string())?;
    let stdout = String::from_utf8_lossy(&run.stdout).trim().to_string();
    if !run.status.success() {
        return Err(format!("driver exited with {} (output {stdout:?})", run.status));
    }
    Ok(stdout)
}

fn demo_plan() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/fpl/demo.xml")
}

#[test]
fn dropin_header_of_the_demo_compiles_with_the_module_environment() {
    let Some(cc) = common::c_compiler() else { return };
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("dropin_env_demo");
    let out = build_and_run(&cc, &demo_plan(), &work).unwrap_or_else(|e| panic!("demo: {e}"));
    // Every module function answers 0 here, so GpsFixValid() is false: the demo waits in its
    // first block ("Wait GPS": stage 0 sets kill_throttle, the while test is stage 1, its
    // loop-back stage 2 is where each call stops).
    assert_eq!(out, "0 2");
}

#[test]
fn dropin_header_of_every_corpus_plan_compiles_and_runs() {
    let Some(cc) = common::c_compiler() else { return };
    let Some(dir) = common::corpus_dir() else { return };
    let plans = common::corpus_plans(&dir);
    assert_eq!(plans.len(), 104, "INDEX.tsv lists 104 plans upstream compiles");
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR")).join("dropin_corpus");
    let failures: Vec<String> = plans
        .par_iter()
        .enumerate()
        .filter_map(|(i, p)| {
            let work = tmp.join(format!("plan{i:03}"));
            let result = build_and_run(&cc, p, &work).and_then(|out| {
                // "block stage", both numbers, as printed by the driver.
                let nums: Vec<u32> =
                    out.split_whitespace().filter_map(|w| w.parse().ok()).collect();
                if nums.len() == 2 {
                    Ok(())
                } else {
                    Err(format!("unexpected driver output {out:?}"))
                }
            });
            result.err().map(|e| format!("{}: {e}", p.display()))
        })
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {} drop-in headers failed:\n{}",
        failures.len(),
        plans.len(),
        failures.join("\n\n")
    );
}
