//! Benchmark: translation validation of the crafted plans whose calls have exponentially many
//! paths (`tests/evidence_plans/explode_*.xml`, `wide.xml`): the runs of a call are joined at
//! stage starts, so the work grows with the distinct states there, not with the paths. Prints,
//! per plan and target, the states, the transitions compared (every path counted), the runs
//! made, the runs repeated from changed C states, and the median wall time of 3 validations
//! (build, walk to the fixpoint, one short random run). Not a test: it asserts nothing about
//! time.
//!
//! Run: `cargo bench -p vouch-fpl --bench validate_explode` (needs a C compiler; the Cortex-M4
//! rows need `arm-none-eabi-gcc` and `qemu-system-arm`, `-- --host-only` leaves them out).

use std::path::Path;
use std::time::Instant;

use vouch_fpl::evidence::validate::{Options, Target, validate};

const PLANS: [&str; 3] = ["wide.xml", "explode_loops.xml", "explode_ranges.xml"];

fn main() {
    if vouch_testkit::c_compiler().is_none() {
        eprintln!("validate_explode: no C compiler, nothing measured");
        return;
    }
    let args: Vec<String> = std::env::args().collect();
    let arm = !args.iter().any(|a| a == "--host-only")
        && vouch_testkit::program("arm-none-eabi-gcc", "--version").is_some()
        && vouch_testkit::program("qemu-system-arm", "--version").is_some();
    let mut targets = vec![Target::Host];
    if arm {
        targets.push(Target::CortexM4);
    }
    println!("validation of the exploding plans, median of 3, measured now on this machine:");
    println!(
        "{:<20} {:<10} {:>7} {:>22} {:>9} {:>11} {:>9}",
        "plan", "target", "states", "transitions", "runs", "copy runs", "median s"
    );
    for name in PLANS {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/evidence_plans").join(name);
        let Ok(plan) = vouch_fpl::front::parse_file(&path) else {
            println!("{name}: does not parse");
            continue;
        };
        for &target in &targets {
            let opts = Options { target, random_runs: 1, random_steps: 100, ..Options::default() };
            let mut times = Vec::new();
            let mut last = None;
            for _ in 0..3 {
                let t0 = Instant::now();
                let r = validate(&plan, &opts);
                times.push(t0.elapsed().as_secs_f64());
                last = Some(r);
            }
            times.sort_by(f64::total_cmp);
            match last {
                Some(Ok(r)) => println!(
                    "{name:<20} {:<10} {:>7} {:>22} {:>9} {:>11} {:>9.2}{}",
                    target.name(),
                    r.states,
                    r.transitions,
                    r.runs,
                    r.second_runs,
                    times[1],
                    if r.passed() && r.fixpoint { "" } else { "  (not validated to the fixpoint)" }
                ),
                Some(Err(e)) => println!("{name:<20} {:<10} error: {e}", target.name()),
                None => {}
            }
        }
    }
}
