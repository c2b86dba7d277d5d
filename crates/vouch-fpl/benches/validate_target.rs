//! Benchmark: translation validation of every corpus plan, one plan at a time, on the emulated
//! Cortex-M4 (`--target cortex-m4`) and, side by side in the same run, on the host: the time of
//! each plan (build, walk to the fixpoint, one short random run), then the median and the worst
//! per target. Not a test: it asserts nothing about time.
//!
//! Run: `cargo bench -p vouch-fpl --bench validate_target` (needs `../shared`,
//! `arm-none-eabi-gcc` and `qemu-system-arm`; `-- --host-only` / `-- --target-only` for one side).

use std::path::PathBuf;
use std::time::Instant;

use vouch_fpl::evidence::validate::{Options, Target, validate};

#[path = "../tests/common/mod.rs"]
mod common;

/// The 104 corpus plans upstream compiles, with their corpus-relative names.
fn corpus_plans() -> Vec<(String, PathBuf)> {
    let Some(dir) = common::corpus_dir() else { return Vec::new() };
    common::corpus_plans(&dir)
        .into_iter()
        .map(|p| (p.strip_prefix(&dir).unwrap_or(&p).display().to_string(), p))
        .collect()
}

/// Seconds per plan (in corpus order) and the plans that did not validate to the fixpoint.
fn run(target: Target, plans: &[(String, PathBuf)]) -> (Vec<(f64, String)>, Vec<String>) {
    let opts = Options { target, random_runs: 1, random_steps: 100, ..Options::default() };
    let mut times = Vec::new();
    let mut failed = Vec::new();
    for (name, path) in plans {
        let t0 = Instant::now();
        let ok = vouch_fpl::front::parse_file(path)
            .ok()
            .and_then(|p| validate(&p, &opts).ok())
            .is_some_and(|r| r.passed() && r.fixpoint);
        times.push((t0.elapsed().as_secs_f64(), name.clone()));
        if !ok {
            failed.push(name.clone());
        }
    }
    (times, failed)
}

fn summary(target: Target, mut times: Vec<(f64, String)>, failed: &[String]) {
    times.sort_by(|a, b| a.0.total_cmp(&b.0));
    let n = times.len();
    let median =
        if n % 2 == 1 { times[n / 2].0 } else { (times[n / 2 - 1].0 + times[n / 2].0) / 2.0 };
    let total: f64 = times.iter().map(|t| t.0).sum();
    let worst = &times[n - 1];
    println!(
        "{:<10} {n} plans, {} to the fixpoint: median {median:.3} s, worst {:.3} s ({}), total {total:.1} s",
        target.name(),
        n - failed.len(),
        worst.0,
        worst.1
    );
    for f in failed {
        println!("  not validated: {f}");
    }
}

fn main() {
    let plans = corpus_plans();
    if plans.is_empty() {
        eprintln!("validate_target: no corpus (../shared/fpl/corpus), nothing measured");
        return;
    }
    let args: Vec<String> = std::env::args().collect();
    let host = !args.iter().any(|a| a == "--target-only");
    let arm = !args.iter().any(|a| a == "--host-only");
    if arm
        && (vouch_testkit::program("arm-none-eabi-gcc", "--version").is_none()
            || vouch_testkit::program("qemu-system-arm", "--version").is_none())
    {
        eprintln!("validate_target: no arm-none-eabi-gcc or qemu-system-arm, nothing measured");
        return;
    }
    println!("validation time per corpus plan, one plan at a time, measured now on this machine:");
    for (target, on) in [(Target::CortexM4, arm), (Target::Host, host)] {
        if on {
            let (times, failed) = run(target, &plans);
            summary(target, times, &failed);
        }
    }
}
